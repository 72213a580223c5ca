"""The focused problem scripts run with --quick in-process and write what they promise; their numbers are checked
against independent evaluations (brute-force sweeps, the numeric joint models, a second LTCA path)."""

import json
import math

import numpy as np
import pandas as pd
import pytest

from gearopt.joints import press_fit, taper_fit, taper_slip_utilisation


@pytest.fixture(scope="module")
def microgeometry_run(run_quick):
    return run_quick("pair_microgeometry") / "crank-cam"


@pytest.fixture(scope="module")
def shift_run(run_quick):
    return run_quick("shift_split")


@pytest.fixture(scope="module")
def joint_run(run_quick):
    return run_quick("joint_sizing")


# ------------------------------------------------------------------------------------------------ pair_microgeometry

def test_pair_microgeometry_writes_tables_and_figures(microgeometry_run):
    for name in ("comparison.csv", "microgeometry.csv", "starts.csv", "harris_map.csv", "transmission_error.csv",
                 "harris_map.png", "transmission_error.png", "summary.json"):
        assert (microgeometry_run / name).stat().st_size > 50, name


def test_pair_microgeometry_improves_ppte_within_the_limits(microgeometry_run):
    s = json.loads((microgeometry_run / "summary.json").read_text())
    assert s["torque_range_Nm"] == [300.0, 150.0, 450.0]        # [design_loads] crank-cam 300 N m x (1, 0.5, 1.5)
    assert s["solve_status"] == "Solve_Succeeded"
    assert s["max_ppte_optimised_um"] < 0.6 * s["max_ppte_unmodified_um"]
    # the NLP's limits hold on the exact LTCA re-check: contact stress not raised, loaded contact ratio >= 1.2
    assert s["max_contact_stress_optimised_MPa"] <= s["max_contact_stress_unmodified_MPa"] * (1 + 1e-6)
    assert s["min_loaded_contact_ratio_optimised"] >= 1.2


def test_pair_microgeometry_harris_map_agrees_with_the_design_check(microgeometry_run):
    # two code paths to the same exact LTCA: harris_map at the design torque and the optimiser's own re-check
    harris = pd.read_csv(microgeometry_run / "harris_map.csv").set_index("torque_Nm")
    comp = pd.read_csv(microgeometry_run / "comparison.csv")
    opt = comp[(comp["design"] == "optimised") & (comp["torque_Nm"] == 300.0)]["ppte_um"].item()
    unmod = comp[(comp["design"] == "unmodified") & (comp["torque_Nm"] == 300.0)]["ppte_um"].item()
    assert harris.loc[300.0, "ppte_um_optimised"] == pytest.approx(opt, rel=1e-9)
    assert harris.loc[300.0, "ppte_um_unmodified"] == pytest.approx(unmod, rel=1e-9)
    te = pd.read_csv(microgeometry_run / "transmission_error.csv")
    assert np.ptp(te["te_optimised_um"]) == pytest.approx(opt, rel=1e-9)


# ------------------------------------------------------------------------------------------------------- shift_split

MESHES = ("crank-cam", "cam-ac", "cam-fp", "crank-lpi", "lpi-lpg")


def test_shift_split_writes_every_mesh(shift_run):
    table = pd.read_csv(shift_run / "shift_split.csv")
    assert set(table["mesh"]) == set(MESHES)
    assert set(table["design"]) == {"iso_tr_4467", "max_min_tip_thickness", "balance_specific_sliding"}
    for mesh in MESHES:
        assert (shift_run / f"shift_split_{mesh}.png").stat().st_size > 1000
        assert (shift_run / f"sweep_{mesh}.csv").stat().st_size > 100


def test_shift_split_optima_meet_the_limits_and_beat_the_feasible_sweep(shift_run):
    table = pd.read_csv(shift_run / "shift_split.csv")
    opt = table[table["design"] != "iso_tr_4467"]
    assert (opt["status"] == "Solve_Succeeded").all()
    # contact-ratio limit (worst case: maximum centre distance, minimum tip diameters)
    assert (opt["worst_case_transverse_contact_ratio"] >= 1.2 - 1e-6).all()
    for mesh in MESHES:
        sweep = pd.read_csv(shift_run / f"sweep_{mesh}.csv")
        feas = sweep[sweep["feasible"]]
        assert len(feas) > 0
        rows = table[table["mesh"] == mesh].set_index("design")
        # brute-force check of optimality on the feasible grid (the sum of shifts is fixed by the centre distance)
        tip = rows.loc["max_min_tip_thickness", ["tip_thickness_1_mm", "tip_thickness_2_mm"]].min()
        assert tip >= feas[["tip_thickness_1_mm", "tip_thickness_2_mm"]].min(axis=1).max() - 1e-6
        slide = rows.loc["balance_specific_sliding", ["specific_sliding_root_1", "specific_sliding_root_2"]]
        grid = feas[["specific_sliding_root_1", "specific_sliding_root_2"]].abs().max(axis=1).min()
        assert slide.abs().max() <= grid + 1e-6
        # both optima keep the fixed sum of shifts
        sums = rows["profile_shift_1"] + rows["profile_shift_2"]
        assert np.ptp(sums.to_numpy()) < 1e-9


# ------------------------------------------------------------------------------------------------------ joint_sizing

def test_joint_sizing_rows_and_files(joint_run):
    table = pd.read_csv(joint_run / "joint_sizing.csv")
    assert len(table) == 8 and set(table["train"]) == {"spur", "helical"}
    assert set(table["joint"]) == {"crank", "cam", "ac", "fp"}
    assert (table["status"] == "Solve_Succeeded").all()
    assert (table["sized_min_combined_margin"] >= 1.5 * (1 - 1e-6)).all()
    margins = pd.read_csv(joint_run / "margins.csv")
    assert set(margins["design"]) == {"present", "sized"}
    assert (joint_run / "fits_spur_cam.csv").exists()
    # spur gears have no axial thrust; the helical ones do
    assert (table[table["train"] == "spur"]["rated_axial_force_N"] == 0.0).all()
    assert (table[table["train"] == "helical"]["rated_axial_force_N"].abs() > 0.0).all()


def test_sized_press_fits_hold_the_target_when_reevaluated(joint_run):
    # independent re-evaluation with the numeric Lame/DIN 7190 model: weakest interference of the band, smoothing
    # 0.8 (Rz 4 + 6.3), centrifugal loss at the overspeed shaft speed; data: crank d 65/D_o 100/l 30,
    # cam d 42/D_o 70/l 25, 20MnCr5 hub on a 42CrMo4 shaft, mu 0.12
    table = pd.read_csv(joint_run / "joint_sizing.csv")
    geometry = {"crank": (65.0, 100.0, 30.0), "cam": (42.0, 70.0, 25.0)}
    for _, r in table[table["type"] == "press_fit"].iterrows():
        d, do, l = geometry[r["joint"]]
        weakest = press_fit(d, 0.0, do, l, r["sized_interference_min_um"], 210000.0, 0.3, 206000.0, 0.3, 0.12,
                            roughness_Rz_um=(4.0, 6.3), speed_rpm=r["overspeed_rpm"])
        demand = math.hypot(2000.0 * r["rated_torque_Nm"] / d, r["rated_axial_force_N"])
        assert weakest.friction_force_N / demand == pytest.approx(1.5, rel=1e-6)
        # the suggested ISO 286 fit lies inside the admissible interval
        assert r["suggested_fit_min_um"] >= r["required_min_interference_um"] - 1e-9
        assert r["suggested_fit_max_um"] <= r["allowed_max_interference_um"] + 1e-9
    # the present crank fit (H7/r6, 11 um at its weakest, less 8.24 um smoothing) is far below the target
    crank = table[(table["joint"] == "crank") & (table["train"] == "spur")].iloc[0]
    assert crank["present_min_combined_margin"] < 1.0 < crank["sized_min_combined_margin"]


def test_sized_taper_nuts_hold_the_target_when_reevaluated(joint_run):
    # thesis Eqs. 3.48/3.49 at the largest nut factor 0.16 (lowest preload); data: AC taper 30/26.25 mm 1:8 M16,
    # FP taper 25/20 mm 1:5 M14, mu 0.15
    table = pd.read_csv(joint_run / "joint_sizing.csv")
    geometry = {"ac": (30.0, 26.25, 3.5763, 16.0), "fp": (25.0, 20.0, 5.7106, 14.0)}
    for _, r in table[table["type"] == "taper_nut"].iterrows():
        D, d, theta, thread = geometry[r["joint"]]
        t = taper_fit(D, d, theta, 0.15, nut_torque_Nm=r["sized_nut_torque_Nm"], nut_factor=0.16,
                      thread_diameter_mm=thread)
        u = taper_slip_utilisation(r["rated_torque_Nm"], abs(r["rated_axial_force_N"]), t.torque_capacity_Nm,
                                   t.bolt_preload_N)
        assert 1.0 / u == pytest.approx(1.5, rel=1e-6)
        assert r["sized_nut_torque_Nm"] < r["present_nut_torque_Nm"]   # the data's nut torques hold with room
