"""Minimum-inertia blank NLP: the active set predicted analytically in simple cases, closed-form web thicknesses,
independent re-evaluation with GearBlank / web_stress / web_fatigue, derivatives against finite differences."""

import math

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.blank import GearBlank, blank_from_data, web_fatigue, web_stress
from gearopt.design.blank_sizing import (BlankSpec, WebDemand, blank_sizing_expressions, size_blank,
                                         web_demand_from_loads)
from gearopt.errors import GearoptInputError

RHO = 7850.0


def spec(**kw):
    # a cam-gear-like blank (module 3, z 76): d_a 234, d_f 220.5 -> whole depth 6.75 mm
    args = dict(tip_diameter_mm=234.0, root_diameter_mm=220.5, face_width_mm=25.0, bore_diameter_mm=42.0,
                hub_outer_diameter_mm=70.0, hub_length_mm=25.0, endurance_limit_MPa=500.0,
                ultimate_strength_MPa=1000.0, yield_strength_MPa=700.0, web_thickness_mm=12.0, rim_thickness_mm=10.5,
                pocket_area_fraction=0.4, name="cam-like")
    args.update(kw)
    return BlankSpec(**args)


def annulus_j(D, d, L):
    """Polar inertia of a steel annulus [kg m^2]: rho pi/32 (D^4 - d^4) L (mm in)."""
    return RHO * math.pi / 32.0 * (D ** 4 - d ** 4) * L * 1e-15


@pytest.fixture(scope="module")
def data():
    return go.load_system()


def test_without_fatigue_rim_goes_to_backup_bound_web_to_lower_bound_pockets_to_upper():
    # inertia falls with the pocket fraction and the web thickness, and a thicker rim adds more (full face width)
    # than it removes from the web: the optimum is rim at t_R = 1.2 h_t, web at its lower bound, pockets at the upper
    s = spec()
    res = size_blank(s, (), min_fatigue_margin=None, web_thickness_bounds_mm=(4.0, 25.0),
                     pocket_fraction_bounds=(0.0, 0.6))
    v = res.values
    assert v["rim_thickness_mm"] == pytest.approx(1.2 * 6.75, rel=1e-6)
    assert v["web_thickness_mm"] == pytest.approx(4.0, rel=1e-6)
    assert v["pocket_area_fraction"] == pytest.approx(0.6, rel=1e-6)
    assert res.active_constraints == ["backup_ratio"]
    assert res.at_bound == {"web_thickness_mm": "lower", "pocket_area_fraction": "upper"}
    # inertia: the optimum's GearBlank, and an independent sum of annuli (teeth half-filled, web less 60 %)
    assert v["inertia_kgm2"] == pytest.approx(float(res.blank.inertia_kgm2()), rel=1e-12)
    d_r = 220.5 - 2 * 8.1
    j = (0.5 * annulus_j(234.0, 220.5, 25.0) + annulus_j(220.5, d_r, 25.0) + 0.4 * annulus_j(d_r, 70.0, 4.0)
         + annulus_j(70.0, 42.0, 25.0))
    assert v["inertia_kgm2"] == pytest.approx(j, rel=1e-6)
    assert v["inertia_kgm2"] < v["present_inertia_kgm2"] < v["solid_inertia_kgm2"]


def test_torsion_fatigue_fixes_the_web_thickness_in_closed_form():
    # torque only, fully reversed: the forward-reverse case has mean 0, so EFR = von Mises = sqrt(3) tau with
    # tau = T/(2 pi a^2 t) at the hub junction (equilibrium of a thin disc in torsion); with few pockets the hub
    # stays critical, so t = sqrt(3) T S / (2 pi a^2 S_e)
    s = spec()
    T, S = 3000.0, 2.0
    res = size_blank(s, WebDemand(T), min_fatigue_margin=S, pocket_fraction_bounds=(0.0, 0.3),
                     web_thickness_bounds_mm=(1.0, 25.0))
    a = 35.0
    t_exact = math.sqrt(3.0) * T * 1e3 * S / (2.0 * math.pi * a ** 2 * 500.0)
    v = res.values
    assert v["web_thickness_mm"] == pytest.approx(t_exact, rel=1e-6)
    assert v["pocket_area_fraction"] == pytest.approx(0.3, rel=1e-6)
    assert v["rim_thickness_mm"] == pytest.approx(1.2 * 6.75, rel=1e-6)
    assert "demand:efr_forward_reverse_hub_MPa" in res.active_constraints
    assert res.margins.loc["demand", "fatigue_margin"] == pytest.approx(S, rel=1e-6)


def test_axial_bending_fatigue_matches_the_clamped_plate_closed_form():
    # axial force only: sigma_b = 6 M_r(a)/t^2 with the Kirchhoff clamped-free annular plate moment (formula of
    # gearopt.blank.web, written out here); fully reversed -> t = sqrt(6 M S / S_e) at the optimum's rim radius
    s = spec()
    P, S, nu = 20000.0, 1.5, 0.3
    res = size_blank(s, WebDemand(0.0, axial_force_N=P), min_fatigue_margin=S, web_thickness_bounds_mm=(1.0, 25.0))
    v = res.values
    a, b = 35.0, 0.5 * (220.5 - 2 * v["rim_thickness_mm"])
    q = (a / b) ** 2
    M = P / (2 * math.pi) * (0.5 * (1 + nu) * math.log(b / a) + 0.25 * (1 - nu) * (1 - q)) / (
        0.5 * (1 + nu) + 0.5 * (1 - nu) * q)
    assert v["web_thickness_mm"] == pytest.approx(math.sqrt(6.0 * M * S / 500.0), rel=1e-6)
    assert res.margins.loc["demand", "fatigue_margin"] == pytest.approx(S, rel=1e-6)


def test_pocket_critical_optimum_reevaluated_with_the_web_models():
    # forward-only loading with torque and in-plane force, many pockets allowed: the pocket section becomes
    # critical; the NLP's split (hub and pocket constraints) must agree with the model's max() form
    s = spec()
    demand = WebDemand(1500.0, in_plane_force_N=20000.0, reverse_factor=0.0, name="fwd")
    res = size_blank(s, demand, min_fatigue_margin=1.5, pocket_fraction_bounds=(0.0, 0.8),
                     web_thickness_bounds_mm=(1.0, 25.0), stress_concentration=1.5)
    v = res.values
    blank = GearBlank(234.0, 220.5, 25.0, 42.0, hub_outer_diameter_mm=70.0, hub_length_mm=25.0,
                      web_thickness_mm=v["web_thickness_mm"], rim_thickness_mm=v["rim_thickness_mm"],
                      pocket_area_fraction=v["pocket_area_fraction"])
    st = web_stress(1500.0, hub_outer_diameter_mm=70.0, rim_inner_diameter_mm=blank.rim_inner_diameter_mm,
                    web_thickness_mm=v["web_thickness_mm"], in_plane_force_N=20000.0,
                    pocket_area_fraction=v["pocket_area_fraction"], stress_concentration=1.5)
    fat = web_fatigue(st["von_mises_MPa"], 0.0, endurance_limit_MPa=500.0, ultimate_strength_MPa=1000.0)
    assert min(c["fatigue_margin"] for c in fat.values()) == pytest.approx(1.5, rel=1e-6)
    assert float(blank.inertia_kgm2()) == pytest.approx(v["inertia_kgm2"], rel=1e-12)
    assert any("pocket" in n for n in res.active_constraints)
    assert 0.0 < v["pocket_area_fraction"] < 0.8          # an interior trade-off of pockets against web thickness


def test_inertia_floor_is_met_exactly_when_active():
    s = spec()
    free = size_blank(s, (), min_fatigue_margin=None)
    floor = 1.1 * free.values["inertia_kgm2"]
    res = size_blank(s, (), min_fatigue_margin=None, min_inertia_kgm2=floor)
    assert res.values["inertia_kgm2"] == pytest.approx(floor, rel=1e-6)
    assert "inertia_floor_kgm2" in res.active_constraints


def test_default_data_cam_gear(data):
    train = data.train("spur")
    s = BlankSpec.from_data(data, train, "cam")
    present, _ = blank_from_data(data, train, "cam")
    demand = web_demand_from_loads(data, train, "cam")
    # cam joint torque at the design loads: 2 x 300 (from the crank) - 240 (AC) - 150 (FP) = 210 N m
    assert demand.torque_Nm == pytest.approx(210.0, rel=1e-9)
    res = size_blank(s, demand, min_fatigue_margin=1.5)
    assert res.values["present_inertia_kgm2"] == pytest.approx(float(present.inertia_kgm2()), rel=1e-12)
    assert res.values["inertia_kgm2"] < res.values["present_inertia_kgm2"]
    assert res.margins.loc["design", "fatigue_margin"] >= 1.5 - 1e-6
    assert res.values["backup_ratio"] >= 1.2 - 1e-7


def test_blank_expression_derivatives_match_finite_differences():
    s = spec()
    demand = WebDemand(800.0, in_plane_force_N=6000.0, axial_force_N=3000.0, reverse_factor=0.4)
    x = ca.SX.sym("x", 3)
    e = blank_sizing_expressions(s, x[0], x[1], x[2], demand, stress_concentration=1.3)
    keys = ["inertia_kgm2", "backup_ratio", "efr_forward_hub_MPa", "efr_forward_reverse_hub_MPa",
            "efr_forward_reverse_pocket_MPa", "efr_reverse_pocket_MPa"]
    out = ca.vertcat(*[e[k] for k in keys])
    x0 = np.array([9.0, 9.5, 0.35])
    J = np.array(ca.Function("J", [x], [ca.jacobian(out, x)])(x0))
    F = ca.Function("F", [x], [out])
    h = np.array([1e-5, 1e-5, 1e-7])
    fd = np.column_stack([(np.array(F(x0 + np.eye(3)[i] * h[i])).ravel()
                           - np.array(F(x0 - np.eye(3)[i] * h[i])).ravel()) / (2 * h[i]) for i in range(3)])
    np.testing.assert_allclose(J, fd, rtol=1e-6, atol=1e-12)


def test_bad_inputs_raise_named_errors(data):
    train = data.train("spur")
    with pytest.raises(GearoptInputError, match="solid blank"):
        BlankSpec.from_data(data, train, "crank")
    with pytest.raises(GearoptInputError, match="needs at least one WebDemand"):
        size_blank(spec(), (), min_fatigue_margin=1.5)
    with pytest.raises(GearoptInputError, match="no load"):
        WebDemand(0.0)
    with pytest.raises(GearoptInputError, match="root_diameter_mm"):
        spec(root_diameter_mm=60.0)
    with pytest.raises(GearoptInputError, match="pocket_fraction"):
        size_blank(spec(), (), min_fatigue_margin=None, pocket_fraction_bounds=(0.0, 0.95))
