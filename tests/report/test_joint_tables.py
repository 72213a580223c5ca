"""Joint and blank tables for the default train (helical baseline and spur redesign): the data's [C] capacities,
inf axial margins of the spur train with their note, torque histories, design loads, blank inertias."""

import math

import numpy as np
import pytest

import gearopt as go
from gearopt.blank.web import web_stress
from gearopt.cases.timing_train import quasi_static_load_case
from gearopt.data import load_system
from gearopt.errors import GearoptInputError
from gearopt.joints.walk_off import joint_margins, walk_off
from gearopt.report.joint_tables import blank_table, design_load_torques_Nm, joint_table, web_table

COLUMNS = ["gear", "type", "pressure_MPa", "torque_capacity_Nm", "axial_capacity_N", "torque_Nm", "axial_force_N",
           "torque_margin", "axial_margin", "combined_margin"]


def test_helical_table_columns_and_data_capacities():
    system = go.load_system()
    df = joint_table(system, train="helical", torques_Nm=quasi_static_load_case(system, "helical"))
    assert list(df.index) == ["crank", "cam", "lpi", "lpg", "ac", "fp"]
    assert all(c in df.columns for c in COLUMNS)
    # default_train.toml [C] values: pressures 32.61 / 103.24 / 40.00 / 111.0 MPa; capacities 779.2 / 858.2 /
    # 217.8 / 202.6 / 2117 / 811 N m; axial holding 23974 / 40868 N; taper preloads 62500 / 47619 N
    expected = {"crank": (32.61, 779.2, 23974.0), "cam": (103.24, 858.2, 40868.0), "lpi": (40.00, 217.8, None),
                "lpg": (111.0, 202.6, None), "ac": (None, 2117.0, 62500.0), "fp": (None, 811.0, 47619.0)}
    for j, (p, T, F) in expected.items():
        if p is not None:
            assert df.loc[j, "pressure_MPa"] == pytest.approx(p, abs=0.06)
        assert df.loc[j, "torque_capacity_Nm"] == pytest.approx(T, abs=0.5)
        if F is not None:
            assert df.loc[j, "axial_capacity_N"] == pytest.approx(F, abs=1.0)
    # quasi-static case: the cam joint carries the valve-train peak (10 + 40 N m) and its thrust follows it
    assert df.loc["cam", "torque_Nm"] == pytest.approx(50.0)
    d_cam = go.load_default_train("helical").pairs["crank-cam"].geometry()["pitch_diameter_mm"][1]
    assert abs(df.loc["cam", "axial_force_N"]) == pytest.approx(2000 * 50.0 * math.tan(math.radians(6.0)) / d_cam)
    assert np.all(np.isfinite(df.loc[["crank", "cam", "ac", "fp"], "axial_margin"]))
    assert "quasi-static" in df.attrs["load_case"]


def test_spur_table_axial_margins_inf_with_note():
    system = go.load_system()
    df = joint_table(system, train="spur", torques_Nm=quasi_static_load_case(system, "spur"))
    assert (df["axial_force_N"] == 0.0).all()
    assert (df["axial_margin"] == math.inf).all()
    assert df["note"].str.contains("spur: no axial tooth force").all()
    # with no axial load the combined margin is the torque margin, finite where torque flows
    loaded = df.index != "lpi"
    assert np.allclose(df.loc[loaded, "combined_margin"], df.loc[loaded, "torque_margin"])
    assert df.loc["lpi", "torque_margin"] == math.inf and "idler" in df.loc["lpi", "note"]


def test_history_gives_the_minimum_margin_over_time():
    t = np.linspace(0, 2 * np.pi, 40)
    torques = {"crank-cam": 190 + 150 * np.sin(3 * t), "cam-ac": 240 * np.cos(t), "cam-fp": 90 + 60 * np.sin(6 * t)}
    df = joint_table(load_system(), train="helical", torques_Nm=torques)
    r = walk_off(go.load_default_train("helical"), torques)
    T, F = r.joint_torque_Nm["cam"], r.axial_force_N["cam"]
    worst = min(joint_margins("press_fit", T[i], F[i], df.loc["cam", "torque_capacity_Nm"],
                              df.loc["cam", "axial_capacity_N"])["combined_margin"] for i in range(t.size))
    assert df.loc["cam", "combined_margin"] == pytest.approx(worst)
    assert abs(df.loc["cam", "torque_Nm"]) == pytest.approx(np.max(np.abs(T)))


def test_design_loads_and_weakest_tolerances():
    data = load_system()
    loads = design_load_torques_Nm(data)
    assert {k: loads[k] for k in ("crank-cam", "cam-ac", "cam-fp")} == {"crank-cam": 300.0, "cam-ac": 240.0,
                                                                        "cam-fp": 150.0}
    assert set(loads) <= set(go.load_default_train("helical").meshes)
    df = joint_table(data, "helical", "design")
    assert df.loc["cam", "torque_Nm"] == pytest.approx(2 * 300.0 - 240.0 - 150.0)  # camshaft share of the design
    weak = joint_table(data, "helical", "design", interference="min", nut_factor="max")
    assert (weak["torque_capacity_Nm"] < df["torque_capacity_Nm"]).all()
    # data notes: cam 590 N m at the minimum interference, AC 1984 N m at k = 0.16
    assert weak.loc["cam", "torque_capacity_Nm"] == pytest.approx(590.0, abs=1.0)
    assert weak.loc["ac", "torque_capacity_Nm"] == pytest.approx(1984.0, abs=1.0)
    with pytest.raises(GearoptInputError, match="'design'"):
        joint_table(data, "helical", "peak")


def test_blank_table():
    df = blank_table(load_system(), train="spur")
    assert list(df.index) == ["crank", "cam", "ac", "fp", "lpi", "lpg"]
    assert df.loc["cam", "blank"] == "pocketed" and df.loc["crank", "blank"] == "solid"
    assert df.loc["cam", "inertia_kgm2"] == pytest.approx(0.0305, rel=0.01)
    assert 35.0 < df.loc["cam", "inertia_reduction_percent"] < 50.0
    assert df.loc["crank", "inertia_reduction_percent"] == pytest.approx(0.0)
    assert df.loc["ac", "assumed"] == ""          # the data now gives the AC web and rim thickness
    assert (df["backup_ratio"] > 1.2).all() and (df["rim_thickness_factor"] == 1.0).all()


def test_web_table_single_case_and_history():
    df = web_table(load_system(), train="helical", torques_Nm="design")
    assert list(df.index) == ["cam", "ac", "fp"]  # the webbed gears
    # a single load case is applied forward and reversed: the forward-reverse case is fully reversed
    assert np.allclose(df["forward_stress_MPa"], df["reverse_stress_MPa"])
    assert np.allclose(df["forward_reverse_efr_MPa"], df["forward_stress_MPa"])
    assert np.allclose(df["forward_fatigue_margin"], df["reverse_fatigue_margin"])
    assert (df["forward_reverse_fatigue_margin"] < df["forward_fatigue_margin"]).all()
    # the cam row is web_stress of its loads: joint torque 210 N m, net thrust, force bound from the three meshes
    train = go.load_default_train("helical")
    r = walk_off(train, design_load_torques_Nm(load_system()))
    alpha = {m: math.radians(p.geometry()["working_pressure_angle_deg"]) for m, p in train.pairs.items()}
    force = sum(abs(c["tangential_force_N"]) / math.cos(alpha[c["mesh"]]) for c in r.contributions
                if c["gear"] == "cam")
    rim_inner = train.gear_table().loc["cam", "root_diameter_mm"] - 21.0
    s = web_stress(210.0, hub_outer_diameter_mm=70.0, rim_inner_diameter_mm=rim_inner, web_thickness_mm=12.0,
                   in_plane_force_N=force,
                   axial_force_N=r.axial_force_N["cam"], pocket_area_fraction=0.4)
    assert df.loc["cam", "forward_stress_MPa"] == pytest.approx(s["von_mises_MPa"], rel=1e-12)
    assert df.loc["cam", "forward_fatigue_margin"] == pytest.approx(
        500.0 / (0.5 * s["von_mises_MPa"] / (1 - 0.5 * s["von_mises_MPa"] / 1000.0)), rel=1e-12)
    # a history that only drives forward has no reverse stress: reverse margin inf, forward-reverse = forward
    t = np.linspace(0.0, 1.0, 20)
    h = web_table(load_system(), train="helical", torques_Nm={"crank-cam": 250 + 100 * t, "cam-ac": 240 + 0 * t,
                                          "cam-fp": 150 + 0 * t})
    assert h.loc["cam", "reverse_stress_MPa"] == 0.0 and h.loc["cam", "reverse_fatigue_margin"] == math.inf
    assert h.loc["cam", "forward_reverse_fatigue_margin"] == pytest.approx(h.loc["cam", "forward_fatigue_margin"])
