"""The presolve of a scene's train variables (:mod:`gearopt.design.scene_presolve`, issue 29 item 1): a scan of the
root profile shift with the flanks held judges each value by the exact LTCA (the same numbers as ``gearopt.ltca`` on
the train at that shift) and the geometry limits, and an interval narrower than the stated width is reported as
pinned with the limits that close it."""

import dataclasses

import numpy as np
import pandas as pd
import pytest

import gearopt as go
from gearopt.contact.ltca import ltca
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.design.scene_presolve import pinned_interval, scan_train_variable
from gearopt.errors import GearoptInputError

MESH = "crank-cam"
TORQUE = 300.0
GEOMETRY = dict(min_contact_ratio=1.2, min_tip_thickness_ratio=0.2, worst_case=True, iso_tr_4467_limits=True,
                min_backlash_mm=None)


@pytest.fixture(scope="module")
def solved():
    train = go.load_default_train("spur")
    unmodified = ltca(train.pairs[MESH], TORQUE)
    stress_limit = 1.02 * unmodified.max_contact_stress_MPa      # 2 % above the data's own shift, unmodified
    scene = Scene("relief", train=train, load_cases=[LoadCase("T", TORQUE)],
                  variables=[DesignVariable(v, MESH) for v in ("tip_relief_1_um", "tip_relief_2_um")],
                  objectives=[Objective("ppte_um", MESH)],
                  limits=[Limit("max_contact_stress_MPa", MESH, upper=stress_limit)],
                  ltca_options={"screen_samples": 0, "polish_evaluations_per_variable": 0})
    built = scene.build()
    return built, built.solve(), stress_limit


def test_scan_agrees_with_the_ltca_at_each_shift_and_names_what_closes_it(solved):
    built, result, stress_limit = solved
    x0 = float(built.scene.train.root_profile_shift)
    grid = np.round(np.linspace(x0 - 0.3, x0 + 0.3, 7), 6)
    scan = scan_train_variable(built, result.values, "root_profile_shift", grid, geometry_limits=GEOMETRY)
    assert list(scan["value"]) == list(grid)
    mods = built.microgeometry_at(result.values, MESH)
    for _, row in scan.iterrows():
        if row["geometry"]:
            continue
        trial = dataclasses.replace(built.scene.train, root_profile_shift=row["value"])
        stress = ltca(trial.pairs[MESH], TORQUE, microgeometry=mods,
                      positions=built.options.check.check_positions).max_contact_stress_MPa
        expected = max(stress - stress_limit, 0.0) / stress_limit
        assert row["violation"] == pytest.approx(expected, rel=1e-6, abs=1e-9)
        assert row["feasible"] == (expected <= 1e-3)
        assert (row["worst"] == f"max_contact_stress_MPa {MESH}") == (expected > 0)
    assert scan.loc[scan["value"] == x0, "feasible"].item()          # the solved design meets its own limit
    evaluated = scan[scan["geometry"] == ""]
    assert len(evaluated) >= 3 and (evaluated["violation"] > 0).any()  # the limit closes the interval somewhere


def test_pinned_interval_reads_the_feasible_run_around_the_start():
    scan = pd.DataFrame({"value": [0.0, 0.1, 0.2, 0.3, 0.4], "feasible": [False, True, True, False, True],
                         "geometry": ["", "", "", "", ""], "worst": ["stress a", "", "", "stress b", ""]})
    pin = pinned_interval(scan, "root_profile_shift", 0.18, max_width=0.35)
    assert pin.interval == (0.0, 0.3) and pin.binding == ("stress a", "stress b")
    assert "0.18" in pin.reason and "stress a" in pin.reason and "pinned" in pin.reason
    assert pinned_interval(scan, "root_profile_shift", 0.18, max_width=0.25) is None        # wider than allowed
    assert pinned_interval(scan, "root_profile_shift", 0.31, max_width=1.0) is None         # start infeasible
    edge = pinned_interval(scan, "root_profile_shift", 0.4, max_width=0.2)
    assert edge.interval == (0.3, 0.4) and edge.binding == ("stress b", "")


def test_bad_variable_is_named(solved):
    built, result, _ = solved
    with pytest.raises(GearoptInputError, match="variable='module_mm'"):
        scan_train_variable(built, result.values, "module_mm", [0.1, 0.2])
    with pytest.raises(GearoptInputError, match="at least 2"):
        scan_train_variable(built, result.values, "root_profile_shift", [0.1])
