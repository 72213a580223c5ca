"""Profile-shift split NLP against an independent brute-force scan of the same pair (exact geometry per point)."""

import numpy as np
import pytest

import gearopt as go
from gearopt.design.shift_distribution import optimise_shift_split
from gearopt.errors import GearoptInputError, GeometryError


def _scan(pair, objective, **limits):
    """Best split on a grid of x1 (0.01, then 0.0005 around the best), keeping only splits that pass
    GearPair.check (numeric, no derivatives)."""
    coarse = _scan_grid(pair, objective, np.linspace(-0.8, 1.6, 241), **limits)
    return _scan_grid(pair, objective, np.linspace(coarse[0] - 0.015, coarse[0] + 0.015, 61), **limits)


def _scan_grid(pair, objective, grid, **limits):
    sum_x = sum(pair.profile_shifts)
    best = None
    for x1 in grid:
        trial = go.GearPair.from_centre_distance(teeth=pair.teeth, centre_distance_mm=pair.centre_distance_mm,
                                                 module_mm=pair.module_mm, profile_shift1=x1,
                                                 tolerances=pair.tolerances)
        try:
            trial.check(min_backlash_mm=None, **limits)
        except GeometryError:
            continue
        g = trial.geometry()
        value = min(g["tip_thickness_mm"]) if objective == "max_min_tip_thickness" \
            else -max(-z for z in g["specific_sliding_root"])
        if best is None or value > best[1]:
            best = (x1, value)
    assert sum_x == pytest.approx(sum(pair.profile_shifts))
    return best


@pytest.fixture(scope="module")
def crank_cam():
    return go.load_default_train("spur").pairs["crank-cam"]


def test_max_min_tip_thickness_matches_grid(crank_cam):
    res = optimise_shift_split(crank_cam, objective="max_min_tip_thickness", min_contact_ratio=1.2)
    x1_grid, value_grid = _scan(crank_cam, "max_min_tip_thickness", min_contact_ratio=1.2)
    assert res["status"] == "Solve_Succeeded"
    assert res["objective_value"] >= value_grid - 1e-6  # Ipopt is at least as good as the 5e-4 grid
    assert res["profile_shifts"][0] == pytest.approx(x1_grid, abs=1e-3)
    # interior optimum of a max-min: both tip thicknesses equal
    t = res["table"]["ipopt"]
    assert t["tip_thickness_1_mm"] == pytest.approx(t["tip_thickness_2_mm"], abs=1e-6)
    assert sum(res["profile_shifts"]) == pytest.approx(sum(crank_cam.profile_shifts), abs=1e-12)


def test_balanced_specific_sliding_matches_grid(crank_cam):
    res = optimise_shift_split(crank_cam, objective="balance_specific_sliding", min_contact_ratio=1.2)
    x1_grid, value_grid = _scan(crank_cam, "balance_specific_sliding", min_contact_ratio=1.2)
    assert -res["objective_value"] >= value_grid - 1e-4
    assert res["profile_shifts"][0] == pytest.approx(x1_grid, abs=1e-3)
    t = res["table"]["ipopt"]
    assert t["specific_sliding_root_1"] == pytest.approx(t["specific_sliding_root_2"], rel=1e-6)


def test_active_limit_is_reported_when_it_binds():
    # 17/40 pair at a small centre distance: the pinion's undercut limit stops the tip-thickness balance
    pair = go.GearPair.from_centre_distance(teeth=(17, 40), centre_distance_mm=85.2, module_mm=3.0)
    res = optimise_shift_split(pair, objective="max_min_tip_thickness", min_contact_ratio=1.0,
                               iso_tr_4467_limits=False)
    x1_grid, _ = _scan(pair, "max_min_tip_thickness", min_contact_ratio=1.0, iso_tr_4467_limits=False)
    assert res["profile_shifts"][0] == pytest.approx(x1_grid, abs=1e-3)
    assert "undercut_margin_1" in res["active_constraints"]


def test_bad_objective_named(crank_cam):
    with pytest.raises(GearoptInputError, match="objective='quiet'"):
        optimise_shift_split(crank_cam, objective="quiet")
