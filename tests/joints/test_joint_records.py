"""Typed results of the joint models: PressFitResult, TaperFitResult, JointCapacity (frozen records with
unit-suffixed fields; ``to_dict()``/``as_row()`` for tables) -- the same values and row layout as the dicts they
replaced."""

import dataclasses

import casadi as ca
import pandas as pd
import pytest

from gearopt.data import load_system, values
from gearopt.joints import (JointCapacity, PressFitResult, TaperFitResult, joint_capacities, joint_capacity,
                            press_fit, taper_fit)

PRESS = (42.0, 0.0, 70.0, 25.0, 65.5, 210e3, 0.3, 206e3, 0.3, 0.12)

#: Row layout of joint_capacity's former dicts (key order per joint type).
PRESS_ROW = ["joint", "gear", "type", "fit", "fit_diameter_mm", "interference_um", "pressure_MPa",
             "torque_capacity_Nm", "axial_capacity_N", "hub_hoop_stress_MPa", "hub_von_mises_MPa", "hub_yield_safety"]
TAPER_ROW = ["joint", "gear", "type", "fit", "fit_diameter_mm", "pressure_MPa", "torque_capacity_Nm",
             "axial_capacity_N", "bolt_preload_N", "torque_capacity_engagement_friction_Nm", "hub_hoop_stress_MPa",
             "hub_von_mises_MPa", "hub_yield_safety"]


def test_press_fit_result_is_a_frozen_typed_record():
    r = press_fit(*PRESS, hub_yield_MPa=700.0)
    assert isinstance(r, PressFitResult)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.pressure_MPa = 0.0
    d = r.to_dict()
    assert list(d)[:5] == ["smoothing_loss_um", "thermal_interference_change_um", "centrifugal_interference_loss_um",
                           "effective_interference_um", "pressure_MPa"]
    assert "shaft_yield_safety" not in d and r.shaft_yield_safety is None  # not asked for
    assert d["hub_yield_safety"] == r.hub_yield_safety and d["fit_lost"] is False
    assert r.axial_capacity_N == r.friction_force_N
    with pytest.raises(AttributeError, match="pressure_MPa"):
        r.pressure_mpa  # noqa: B018 -- a misspelled field names the nearest ones
    with pytest.raises(TypeError, match=r"\.pressure_MPa"):
        r["pressure_MPa"]  # noqa: B018 -- string keys point to the attribute


def test_press_fit_result_holds_casadi_expressions():
    x = ca.SX.sym("x")
    r = press_fit(42.0, 0.0, 70.0, 25.0, x, 210e3, 0.3, 206e3, 0.3, 0.12)
    assert r.fit_lost is None  # numeric only
    f = ca.Function("f", [x], [r.torque_capacity_Nm])
    assert float(f(65.5)) == pytest.approx(press_fit(*PRESS).torque_capacity_Nm, rel=1e-12)


def test_taper_fit_result():
    r = taper_fit(30.0, 26.25, 3.5763, 0.15, bolt_preload_N=62500.0)
    assert isinstance(r, TaperFitResult) and r.theory == "uniform_pressure"
    assert r.self_locking is True and r.hub_von_mises_MPa is None
    assert set(r.to_dict()) == {"theory", "bolt_preload_N", "axial_capacity_N", "torque_capacity_Nm",
                                "torque_capacity_engagement_friction_Nm", "normal_force_N", "friction_radius_mm",
                                "taper_length_mm", "contact_pressure_MPa",
                                "contact_pressure_engagement_friction_MPa", "self_locking"}


def test_joint_capacity_record_and_row_layout():
    system = load_system()
    data = system.data
    caps = joint_capacities(system, speed_rpm=2500.0)
    assert set(caps) == set(values(data)["joints"])
    for name, cap in caps.items():
        assert isinstance(cap, JointCapacity) and cap.joint == name
        row = cap.as_row()
        assert list(row) == (PRESS_ROW if cap.type == "press_fit" else TAPER_ROW)
        assert all(isinstance(v, (str, float)) for v in row.values())
        if cap.type == "press_fit":
            assert cap.bolt_preload_N is None and cap.torque_capacity_engagement_friction_Nm is None
        else:
            assert cap.interference_um is None
    cam = caps["cam"]
    j = values(data)["joints"]["cam"]
    m = values(data)["materials"]
    hub, shaft = m[j["hub_material"]], m[j["shaft_material"]]
    r = press_fit(j["shaft_diameter_mm"], j["shaft_bore_diameter_mm"], j["hub_outer_diameter_mm"], j["fit_length_mm"],
                  j["diametral_interference_um"], shaft["E_MPa"], shaft["poisson_ratio"], hub["E_MPa"],
                  hub["poisson_ratio"], j["friction_coefficient"], speed_rpm=2500.0,
                  shaft_density_kg_m3=shaft["density_kg_m3"], hub_density_kg_m3=hub["density_kg_m3"],
                  hub_yield_MPa=hub["yield_strength_MPa"], shaft_yield_MPa=shaft["yield_strength_MPa"])
    assert cam.torque_capacity_Nm == r.torque_capacity_Nm and cam.interference_um == r.effective_interference_um
    assert cam == cam and joint_capacity(system, "cam", speed_rpm=2500.0).as_row() == cam.as_row()
    table = pd.DataFrame([c.as_row() for c in caps.values()]).set_index("joint")
    assert table.loc["cam", "axial_capacity_N"] == cam.axial_capacity_N
    assert pd.isna(table.loc["cam", "bolt_preload_N"]) and pd.isna(table.loc["ac", "interference_um"])


def test_joint_capacity_is_symbolic_in_its_overrides():
    x = ca.SX.sym("x")
    cap = joint_capacity(load_system(), "cam", overrides={"diametral_interference_um": x})
    assert isinstance(cap.torque_capacity_Nm, ca.SX) and cap.gear == "cam"
