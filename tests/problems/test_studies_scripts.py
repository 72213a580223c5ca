"""The studies problem scripts run with --quick in-process; their fronts are checked against direct evaluations of
the models (the blank's inertia and rim backup ratio) and their robustness claims against their own samples."""

import json
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

import gearopt as go
from gearopt.blank import blank_from_data


@pytest.fixture(scope="module")
def blank_run(run_quick):
    return run_quick("blank_inertia_front")


@pytest.fixture(scope="module")
def ppte_run(run_quick):
    return run_quick("ppte_trade_off")


def test_blank_front_matches_the_blank_model_evaluated_directly(blank_run):
    front = pd.read_csv(blank_run / "front.csv")
    assert len(front) == 5 and (front["status"] == "ok").all()
    assert (blank_run / "front.png").stat().st_size > 5000
    train = go.load_default_train("spur")
    base, _ = blank_from_data(go.load_system(), train, "cam")
    for _, row in front.iterrows():
        blank = replace(base, web_thickness_mm=row["cam.web_thickness_mm"],
                        rim_thickness_mm=row["cam.rim_thickness_mm"])
        assert float(blank.inertia_kgm2()) == pytest.approx(row["inertia_kgm2[cam]"], rel=1e-9)
        assert float(blank.backup_ratio) == pytest.approx(row["rim_backup_ratio[cam]"], rel=1e-9)
    # the web does not back the rim: it stays at its lower bound; the front is monotone
    assert np.allclose(front["cam.web_thickness_mm"], 4.0, atol=1e-6)
    assert np.all(np.diff(front["rim_backup_ratio[cam]"]) > 0) and np.all(np.diff(front["inertia_kgm2[cam]"]) > 0)
    # the ε multiplier is d inertia / d m_B: a central difference of the blank model along the rim thickness
    row = front.iloc[2]
    h = 1e-3
    pts = [replace(base, web_thickness_mm=row["cam.web_thickness_mm"], rim_thickness_mm=row["cam.rim_thickness_mm"] + s)
           for s in (-h, h)]
    slope = (float(pts[1].inertia_kgm2()) - float(pts[0].inertia_kgm2())) / (
        float(pts[1].backup_ratio) - float(pts[0].backup_ratio))
    assert row["front_slope"] == pytest.approx(slope, rel=1e-4)


def test_blank_sensitivity_of_the_backup_limit(blank_run):
    s = json.loads((blank_run / "summary.json").read_text())
    front = pd.read_csv(blank_run / "front.csv")
    # the optimum sits on m_B = 1.2 between front points 0 and 1: its multiplier equals the local slope of the front
    assert s["inertia_per_backup_ratio_kgm2"] == pytest.approx(front["front_slope"].iloc[1], rel=0.02)
    sens = pd.read_csv(blank_run / "sensitivity.csv")
    assert {"name", "kind", "value", "unit", "sensitivity", "log_sensitivity"} <= set(sens.columns)


def test_ppte_trade_off_writes_front_sensitivity_and_robustness(ppte_run):
    for name in ("front.csv", "front.png", "sensitivity.csv", "sensitivity.md", "monte_carlo_summary.csv",
                 "summary.json"):
        assert (ppte_run / name).stat().st_size > 100, name
    s = json.loads((ppte_run / "summary.json").read_text())
    front = pd.read_csv(ppte_run / "front.csv")
    assert (front["status"] == "ok").all()
    assert np.all(np.diff(front["loaded_contact_ratio[crank-cam]"]) > 0)
    assert "coinciding ends" in s["contact_stress_front"]
    # the robust design (limits held at the tolerance corners of the smooth model) breaks no limit of that model on
    # the samples, and on the exact LTCA's re-check never more often than the nominal one; it costs PPTE when the
    # nominal one breaks a limit, and nothing when the nominal design (the start the exact LTCA ranks best, issue 28)
    # already keeps off the limits
    assert s["robust"]["worst_probability_broken_smooth"] == 0.0
    assert s["robust"]["worst_probability_broken"] <= s["nominal"]["worst_probability_broken"]
    if s["nominal"]["worst_probability_broken_smooth"] > 0.0:
        assert s["robust"]["ppte_um"] > s["nominal"]["ppte_um"]
    else:
        assert s["robust"]["ppte_um"] == pytest.approx(s["nominal"]["ppte_um"], rel=1e-6)
    mc = pd.read_csv(ppte_run / "monte_carlo_summary.csv")
    assert set(mc["design"]) == {"nominal", "robust"}
    # Sobol indices (64 Saltelli base samples, noisy for the non-smooth stresses): the contact ratio at the low torque
    # is driven by the relief amounts
    sobol = pd.read_csv(ppte_run / "sobol_indices.csv").set_index(["quantity", "input"])
    assert sobol.loc["loaded_contact_ratio[crank-cam]@T150"]["ST"].max() > 0.2
    assert s["largest_total_sobol_index_of_loaded_contact_ratio"]["ST"] == pytest.approx(sobol.loc[
        sobol.index.get_level_values(0).str.startswith("loaded_contact_ratio"), "ST"].max())
