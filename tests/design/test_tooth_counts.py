"""Integer tooth-count enumeration at fixed centre distances (gearopt.design.tooth_counts).

Sources used as references (not written here):
- thesis (docs/source-study.md) section 3.4.1, Table 3.1: the spur tooth counts keep every
  speed ratio except crank-LPI, whose error is 2.7027 % (= 1/37); Tables 3.3/3.4: the thesis' shifts, whose sums
  per mesh are crank+cam 0.3124+0.1118, cam+AC 0.1118+0.8777, cam+FP 0.1118+0.6652 (docs/source-study.md sec. 1);
- ISO 21771 eqs. 44/46 (inv alpha_w = inv alpha + 2 tan(alpha)(x1+x2)/(z1+z2), a cos alpha_w = a_d cos alpha),
  coded again independently in the tests below;
- ISO/TR 4467 limits as quoted by the thesis Eqs. 3.8-3.12;
- exact fractions (speed-ratio errors by hand) and brute-force grids (optimality of the NLP, emptiness of
  rejected intervals).
"""

from __future__ import annotations

import math
from fractions import Fraction

import casadi as ca
import numpy as np
import pytest

from gearopt.data import load_default_train, load_system
from gearopt.design.tooth_counts import (OBJECTIVES, _iso_limits_relaxed, _train_with_teeth, bonmin_cross_check,
                                         candidate_model, enumerate_tooth_counts, gear_shift_limits,
                                         mesh_sum_of_shifts, reference_speed_ratios, tooth_count_study)
from gearopt.errors import GearoptInputError, GeometryError
from gearopt.geometry.shift import iso_tr_4467_shift_limits

THESIS_TEETH = {"crank": 38, "cam": 76, "ac": 38, "fp": 76, "lpi": 24, "lpg": 24}


@pytest.fixture(scope="module")
def train():
    return load_default_train("spur")


@pytest.fixture(scope="module")
def exact(train):
    # every speed ratio exact against the train's own teeth, +-2 teeth per gear
    return enumerate_tooth_counts(train, span=2)


@pytest.fixture(scope="module")
def wide(train):
    # 3 % on every mesh (the cam stays exactly 2:1), +-4 teeth: 8 admissible candidates
    return enumerate_tooth_counts(train, default_tolerance_percent=3.0, span=4)


def _rows_with(df, teeth):
    mask = np.ones(len(df), dtype=bool)
    for g, z in teeth.items():
        mask &= (df[f"teeth_{g}"] == z).fillna(False).to_numpy(dtype=bool)
    return df[mask]


def _inv(a):
    return math.tan(a) - a


def _sum_of_shifts_by_hand(z1, z2, a_mm, m_mm=3.0, alpha_deg=20.0):
    """ISO 21771 eqs. 44/46 for a spur pair, written out here."""
    alpha = math.radians(alpha_deg)
    a_d = m_mm * (z1 + z2) / 2.0
    alpha_w = math.acos(a_d * math.cos(alpha) / a_mm)
    return (z1 + z2) * (_inv(alpha_w) - _inv(alpha)) / (2.0 * math.tan(alpha))


# ---------------------------------------------------------------------------------------------------------------
# thesis Table 3.1
# ---------------------------------------------------------------------------------------------------------------

def test_thesis_tooth_counts_are_admissible_at_zero_tolerance(exact):
    row = _rows_with(exact.admissible, THESIS_TEETH)
    assert len(row) == 1
    assert row["max_abs_ratio_error_percent"].iloc[0] == pytest.approx(0.0, abs=1e-12)
    # with 0 % everywhere, every admissible assignment keeps the crank:cam 1:2 exactly
    assert (2 * exact.admissible["teeth_crank"] == exact.admissible["teeth_cam"]).all()


def test_thesis_2_7027_percent_row_needs_a_crank_lpi_tolerance(train):
    # thesis Table 3.1: against the original helical pair, the spur crank-LPI ratio is off by 2.7027 % (= 1/37)
    strict = enumerate_tooth_counts(train, reference="helical_original", ratio_tolerance_percent={"crank-lpi": 0.0},
                                    span=1, system=load_system())
    assert _rows_with(strict.admissible, THESIS_TEETH).empty
    why = _rows_with(strict.rejected, {"crank": 38, "cam": 76, "lpi": 24})
    assert (why["stage"] == "speed_ratio").all() and why["reason"].str.contains(r"\+2\.7027 %").any()

    loose = enumerate_tooth_counts(train, reference="helical_original", ratio_tolerance_percent={"crank-lpi": 2.75},
                                   span=1, system=load_system())
    row = _rows_with(loose.admissible, THESIS_TEETH)
    assert len(row) == 1
    assert row["ratio_error_crank-lpi_percent"].iloc[0] == pytest.approx(100.0 / 37.0, abs=1e-3)  # data: 4 decimals
    for mesh in ("crank-cam", "lpi-lpg", "cam-ac", "cam-fp"):  # Table 3.1: all other meshes 0
        assert row[f"ratio_error_{mesh}_percent"].iloc[0] == pytest.approx(0.0, abs=1e-9)
    # the lube pump gear inherits the LPI's speed error (the idler ratio LPI-LPG is exact)
    assert row["speed_ratio_error_lpg_percent"].iloc[0] == pytest.approx(100.0 / 37.0, abs=1e-3)


def test_reference_ratios(train):
    teeth = reference_speed_ratios(train, "teeth")
    assert teeth["cam"] == 0.5 and teeth["lpi"] == pytest.approx(38 / 24, rel=1e-15)
    assert reference_speed_ratios(train, "data", load_system()) == pytest.approx(teeth, rel=1e-12)  # 1.5833 -> 19/12
    helical = reference_speed_ratios(train, "helical_original", load_system())
    assert helical["lpi"] == pytest.approx(37 / 24, rel=1e-6) and helical["cam"] == 0.5
    with pytest.raises(GearoptInputError, match="miss gears"):
        reference_speed_ratios(train, {"crank": 1.0, "cam": 0.5})


def test_ratio_errors_by_hand(wide):
    df = wide.admissible
    assert len(df) == 8
    for teeth in ({"ac": 39, "fp": 77}, {"ac": 38, "fp": 75}):
        row = _rows_with(df, {"crank": 38, "cam": 76, "lpi": 24, "lpg": 24, **teeth}).iloc[0]
        z = {g: int(row[f"teeth_{g}"]) for g in THESIS_TEETH}
        # mesh ratio n2/n1 = z1/z2 against the reference 76/38, 76/76 (exact fractions)
        cam_ac = (Fraction(z["cam"], z["ac"]) / Fraction(76, 38) - 1) * 100
        cam_fp = (Fraction(z["cam"], z["fp"]) / Fraction(76, 76) - 1) * 100
        fp_speed = (Fraction(z["crank"], z["fp"]) / Fraction(38, 76) - 1) * 100
        assert row["ratio_error_cam-ac_percent"] == pytest.approx(float(cam_ac), abs=1e-12)
        assert row["ratio_error_cam-fp_percent"] == pytest.approx(float(cam_fp), abs=1e-12)
        assert row["speed_ratio_error_fp_percent"] == pytest.approx(float(fp_speed), abs=1e-12)
        assert row["max_abs_ratio_error_percent"] <= 3.0
    # no admissible row breaks a tolerance, and the cam is exactly 2:1 (its role is "camshaft gear")
    errs = df[[c for c in df if c.startswith("ratio_error_")]].abs().to_numpy()
    assert errs.max() <= 3.0 + 1e-9
    assert (df["speed_ratio_error_cam_percent"].abs() < 1e-12).all()


# ---------------------------------------------------------------------------------------------------------------
# sums of shifts and their limits
# ---------------------------------------------------------------------------------------------------------------

def test_sum_of_shifts_of_thesis_candidate(train, exact):
    row = _rows_with(exact.admissible, THESIS_TEETH).iloc[0]
    for name, pair in train.pairs.items():
        own = pair.geometry()["sum_profile_shift"]  # the train propagates shifts itself
        assert row[f"sum_profile_shift_{name}"] == pytest.approx(own, abs=1e-9)
        z1, z2 = (THESIS_TEETH[g] for g in train.meshes[name].gears)
        by_hand = _sum_of_shifts_by_hand(z1, z2, float(train.meshes[name].centre_distance_mm))
        assert row[f"sum_profile_shift_{name}"] == pytest.approx(by_hand, abs=1e-12)
    # thesis Tables 3.3/3.4 sums (from the printed percentages; 4 decimals, docs/source-study.md sec. 1)
    for name, thesis in {"crank-cam": 0.3124 + 0.1118, "cam-ac": 0.1118 + 0.8777, "cam-fp": 0.1118 + 0.6652}.items():
        assert row[f"sum_profile_shift_{name}"] == pytest.approx(thesis, abs=2e-3)
    # the train's own root shift 0.3124 lies in the admissible interval
    assert row["root_shift_min"] <= 0.3124 <= row["root_shift_max"]


def test_sum_of_shifts_beyond_limit_is_rejected(exact):
    # crank 37 / cam 74 at a = 172.2406 mm needs x1 + x2 = 2.137, above 0.87 + 1.0 (ISO/TR 4467, z 37 / 74)
    rej = _rows_with(exact.rejected, {"crank": 37, "cam": 74})
    assert len(rej) == 1 and rej["stage"].iloc[0] == "sum_of_shifts"
    reason = rej["reason"].iloc[0]
    need = _sum_of_shifts_by_hand(37, 74, 172.2406)
    upper = iso_tr_4467_shift_limits(37)[1] + iso_tr_4467_shift_limits(74)[1]
    assert need > upper
    assert "crank-cam" in reason and f"{need:.4f}" in reason and f"{upper:.4f}" in reason and "exceeds" in reason
    # and too small a sum: crank 39 / cam 78 needs -1.005 < -0.3167 - 0.5
    rej = _rows_with(exact.rejected, {"crank": 39, "cam": 78})
    assert rej["stage"].iloc[0] == "sum_of_shifts" and "below the limit" in rej["reason"].iloc[0]


def test_shift_limit_rejections_have_no_feasible_split(train):
    e = enumerate_tooth_counts(train, default_tolerance_percent=5.0, teeth_range={
        "crank": (38, 38), "cam": (76, 76), "ac": (37, 39), "fp": (74, 76), "lpi": (24, 24), "lpg": (24, 24)},
        precheck=False)
    rej = e.rejected[e.rejected["stage"] == "shift_limits"]
    assert len(rej) >= 2
    for _, r in rej.head(2).iterrows():
        assert r["root_shift_min"] > r["root_shift_max"]
        teeth = {g: int(r[f"teeth_{g}"]) for g in THESIS_TEETH}
        # brute force: at every root shift some gear breaks its undercut / ISO/TR 4467 limit (pair.constraints)
        for x in np.linspace(-1.0, 1.5, 26):
            tr = _train_with_teeth(train, teeth, float(x))
            worst = min(v for p in tr.pairs.values() for k, v in p.constraints().items()
                        if k.startswith(("undercut", "shift_")))
            assert worst < 0.0


def test_gear_shift_limits_follow_iso_tr_4467_and_undercut(train):
    # z = 24: ISO/TR 4467 (20 - z)/60 = -0.0667 is above the undercut limit 1.0 - 0.38(1 - sin 20) - 24 sin^2 20 / 2
    lo, hi, lo_name, _ = gear_shift_limits(train, 24)
    x_u = 1.25 - 0.38 * (1 - math.sin(math.radians(20))) - 24 * math.sin(math.radians(20)) ** 2 / 2
    assert (lo, hi) == pytest.approx(((20 - 24) / 60, 0.5 + 0.24)) and lo > x_u and lo_name.startswith("ISO")
    lo, hi, lo_name, _ = gear_shift_limits(train, 12)  # no ISO value below 13 teeth: the undercut limit governs
    assert lo == pytest.approx(1.25 - 0.38 * (1 - math.sin(math.radians(20))) - 6 * math.sin(math.radians(20)) ** 2)
    assert hi == pytest.approx(0.5 + 0.01 * 12) and lo_name == "undercut limit"
    with pytest.raises(GeometryError, match="unreachable"):
        mesh_sum_of_shifts(train, "crank-cam", (41, 82))


def test_relaxed_iso_limits_match_at_integers():
    for z in range(13, 90):
        lo, hi = iso_tr_4467_shift_limits(z)
        rl, rh = _iso_limits_relaxed(float(z), True)
        assert float(rl) == pytest.approx(lo, abs=1e-15) and float(rh) == pytest.approx(hi, abs=1e-15)


# ---------------------------------------------------------------------------------------------------------------
# NLP per candidate, ranking, warm start
# ---------------------------------------------------------------------------------------------------------------

def test_candidate_model_derivatives_match_finite_differences(train):
    model = candidate_model(train, THESIS_TEETH)
    x = ca.SX.sym("x")
    outs = model.function(x)
    jac = ca.Function("dmodel", [x], [ca.jacobian(ca.vertcat(*outs), x)])
    val = ca.Function("model", [x], [ca.vertcat(*outs)])
    h = 1e-6
    for x0 in (0.05, 0.2, 0.31):
        exact_d = np.asarray(jac(x0)).ravel()
        fd = (np.asarray(val(x0 + h)).ravel() - np.asarray(val(x0 - h)).ravel()) / (2 * h)
        assert np.allclose(exact_d, fd, rtol=1e-5, atol=1e-7)
        assert np.abs(exact_d).max() > 0.1  # the shifts really move the constraints


@pytest.fixture(scope="module")
def study(train, wide):
    return tooth_count_study(train, enumeration=wide)


def test_ranking_and_best_candidate(train, study):
    table = study.table
    assert (table["status"] == "Solve_Succeeded").all()
    assert list(table["rank"]) == list(range(1, len(table) + 1))
    assert (np.diff(table["objective_value"].to_numpy()) <= 1e-12).all()
    best = study.best
    for pair in best.pairs.values():
        pair.check(min_contact_ratio=1.2, min_tip_thickness_ratio=0.2)  # raises GeometryError if violated
    # the objective is the smallest worst-case contact ratio of the best train
    eps = best.mesh_table()["worst_case_transverse_contact_ratio"]
    assert table["objective_value"].iloc[0] == pytest.approx(eps.min(), abs=1e-7)
    assert {g: best.gears[g].teeth for g in best.gears} == {g: int(table[f"teeth_{g}"].iloc[0]) for g in best.gears}


def test_nlp_optimum_beats_a_dense_grid(study):
    # brute force over the root shift of the best candidate: no feasible grid point does better than Ipopt
    row = study.table.iloc[0]
    teeth = {g: int(row[f"teeth_{g}"]) for g in THESIS_TEETH}
    out = study.enumeration.model(teeth).evaluate(np.linspace(row["root_shift_min"], row["root_shift_max"], 2001))
    feasible = out["margins"].min(axis=0) >= 0.0
    grid_best = out["worst_case_contact_ratio"].min(axis=0)[feasible].max()
    assert row["objective_value"] >= grid_best - 1e-9
    assert row["objective_value"] - grid_best < 1e-3


def test_tip_thickness_objective(train, wide):
    s = tooth_count_study(train, enumeration=wide, objective="max_min_tip_thickness", start="precheck")
    best = s.best
    tips = best.gear_table()["tip_thickness_mm"]
    assert s.table["objective_value"].iloc[0] == pytest.approx(tips.min(), abs=1e-7)
    assert tips.min() >= 0.2 * 3.0
    for pair in best.pairs.values():
        pair.check(min_contact_ratio=1.2)


def test_warm_start_saves_iterations(train, wide):
    # measured on this candidate list: contact ratio 38 (warm) vs 53 (cold), tip thickness 40 vs 51 iterations
    # (on a 33-candidate list, 5 % / span 6, warm start is not always better: 221 vs 214; "precheck" start: 162)
    for objective in OBJECTIVES:
        warm = tooth_count_study(train, enumeration=wide, objective=objective, start="previous")
        cold = tooth_count_study(train, enumeration=wide, objective=objective, start="iso")
        n_warm = sum(s["iterations"] for s in warm.solves)
        n_cold = sum(s["iterations"] for s in cold.solves)
        assert n_warm <= n_cold, (objective, n_warm, n_cold)
        assert [s["start"] for s in warm.solves][1:] == ["previous"] * (len(warm.solves) - 1)
        assert warm.table["objective_value"].to_numpy() == pytest.approx(cold.table["objective_value"].to_numpy(),
                                                                        abs=1e-7)


def test_infeasible_candidates_keep_status_and_violated_names(train):
    # a contact-ratio demand the lube branch cannot give: the NLP fails by name; the precheck rejects it by name
    e = enumerate_tooth_counts(train, span=1, min_contact_ratio=1.3, precheck=False)
    s = tooth_count_study(train, enumeration=e)
    assert len(s.table) == 1 and s.best is None
    assert s.table["status"].iloc[0] == "Infeasible_Problem_Detected"
    assert "lpi-lpg:contact_ratio_margin" in s.table["violated"].iloc[0]
    pre = enumerate_tooth_counts(train, span=1, min_contact_ratio=1.3)
    assert pre.admissible.empty
    reason = pre.rejected.loc[pre.rejected["stage"] == "precheck", "reason"].iloc[0]
    assert "lpi-lpg:contact_ratio_margin" in reason


def test_top_limits_the_solves(train, wide):
    s = tooth_count_study(train, enumeration=wide, top=3)
    assert len(s.solves) == 3 and (s.table["status"] == "not_solved").sum() == len(wide.admissible) - 3


# ---------------------------------------------------------------------------------------------------------------
# Bonmin cross-check (only what this CasADi has)
# ---------------------------------------------------------------------------------------------------------------

def test_bonmin_cross_check_or_clear_error(train, wide):
    if ca.has_nlpsol("bonmin"):
        r = bonmin_cross_check(wide)
        assert r["success"] and r["agrees"], r
        # measured: teeth 38/76/39/76/24/24 (tied with FP 77), shift margin 0.2651
        assert r["shift_margin"] == pytest.approx(r["enumeration_shift_margin"], abs=1e-6)
    else:
        with pytest.raises(GearoptInputError, match="Bonmin"):
            bonmin_cross_check(wide)
        with pytest.raises(GearoptInputError, match="Bonmin"):
            tooth_count_study(train, enumeration=wide, bonmin=True)


# ---------------------------------------------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kwargs, match", [
    (dict(ratio_tolerance_percent={"crank-lpi": -1.0}), r"ratio_tolerance_percent\['crank-lpi'\]=-1"),
    (dict(default_tolerance_percent=-0.5), "default_tolerance_percent=-0.5"),
    (dict(ratio_tolerance_percent={"nope": 1.0}), "ratio_tolerance_percent names 'nope'"),
    (dict(ratio_tolerance_percent={"cam": 1.0}), "conflicts with exact_ratio_gears"),
    (dict(teeth_range={"lpi": (26, 22)}), r"teeth_range\['lpi'\].*empty"),
    (dict(teeth_range={"lpi": range(24, 24)}), r"teeth_range\['lpi'\].*empty"),
    (dict(teeth_range={"xx": (20, 22)}), "unknown gears"),
    (dict(span=-1), "span=-1"),
    (dict(reference="nonsense"), "reference='nonsense'"),
    (dict(precheck_samples=1), "precheck_samples=1"),
])
def test_bad_input(train, kwargs, match):
    with pytest.raises(GearoptInputError, match=match):
        enumerate_tooth_counts(train, **kwargs)


def test_bad_study_input(train, exact):
    with pytest.raises(GearoptInputError, match="objective='fastest'"):
        tooth_count_study(train, enumeration=exact, objective="fastest")
    with pytest.raises(GearoptInputError, match="start='hot'"):
        tooth_count_study(train, enumeration=exact, start="hot")
    with pytest.raises(GearoptInputError, match="top=0"):
        tooth_count_study(train, enumeration=exact, top=0)
