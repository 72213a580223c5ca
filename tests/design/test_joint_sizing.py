"""Joint sizing NLPs: closed forms, independent re-evaluation with the numeric joint models, ISO 286 fit choice,
derivatives against finite differences, errors."""

import math

import casadi as ca
import numpy as np
import pytest

from gearopt.data import load_system
from gearopt.design.joint_sizing import (JointDemand, PressFitSpec, TaperFitSpec, default_tolerance_band_um,
                                         press_fit_sizing_margins, size_joint, size_press_fit, size_taper_fit,
                                         suggest_fit, taper_fit_sizing_margins)
from gearopt.errors import GearoptInputError, SolveError
from gearopt.joints import fit_interference_um, press_fit, taper_fit, taper_slip_utilisation

E, NU = 206000.0, 0.3


def plain_spec(**kw):
    """Equal steels, solid shaft, no roughness: the textbook case."""
    args = dict(shaft_diameter_mm=40.0, shaft_bore_mm=0.0, hub_outer_diameter_mm=80.0, length_mm=30.0, friction=0.12,
                shaft_E_MPa=E, shaft_nu=NU, hub_E_MPa=E, hub_nu=NU, shaft_yield_MPa=650.0, hub_yield_MPa=700.0,
                name="plain")
    args.update(kw)
    return PressFitSpec(**args)


@pytest.fixture(scope="module")
def data():
    return load_system()


# ---------------------------------------------------------------------------------------------------------- press fit

@pytest.mark.parametrize("band", [0.0, 30.0])
def test_torque_only_press_fit_matches_shigley_closed_form(band):
    # Shigley's MED, press and shrink fits: holding torque T = (pi/2) f p l d^2, and for equal materials and a solid
    # shaft p = E delta/(2 d) (1 - d^2/D_o^2) (Shigley's Lame interference pressure with r_i = 0; the same closed
    # form is quoted by ideambox.com/tools/press-fit-interference). Hence the required diametral interference
    # delta = 2 d p / (E (1 - d^2/D_o^2)) with p = 2 S T / (pi f l d^2); the NLP's nominal adds half the band.
    spec, T, S = plain_spec(), 400.0, 1.5
    res = size_press_fit(spec, JointDemand(T), target_margin=S, tolerance_band_um=band, smoothing=False)
    d, do, l, f = 40.0, 80.0, 30.0, 0.12
    p = 2.0 * S * T * 1e3 / (math.pi * f * l * d ** 2)
    delta_um = 1e3 * 2.0 * d * p / (E * (1.0 - d ** 2 / do ** 2))
    assert res.values["interference_um"] == pytest.approx(delta_um + 0.5 * band, rel=1e-6)
    assert res.values["required_min_interference_um"] == pytest.approx(delta_um, rel=1e-6)
    assert res.margins.loc["demand", "torque_margin"] == pytest.approx(S, rel=1e-6)
    assert res.active_constraints == ["demand:slip_reserve_N"]


def test_press_fit_optimum_reevaluated_with_press_fit_model(data):
    # independent re-evaluation: the numeric Lame/DIN 7190 model at the weakest interference (nominal - band/2),
    # smoothing 0.8 (Rz_s + Rz_h), centrifugal loss at the overspeed; the combined slip margin is the target there
    spec = PressFitSpec.from_data(data, "cam")
    demands = [JointDemand(210.0, 5000.0, 2500.0, "rated"), JointDemand(210.0, 5000.0, 3000.0, "overspeed")]
    res = size_press_fit(spec, demands, target_margin=1.5)
    v = res.values
    assert v["tolerance_band_um"] == pytest.approx(86.0 - 45.0)      # the present H7/u6 band of the data
    mat = dict(shaft_E_MPa=210000.0, shaft_nu=0.3, hub_E_MPa=206000.0, hub_nu=0.3, friction=0.12)
    weakest = press_fit(42.0, 0.0, 70.0, 25.0, v["interference_min_um"], roughness_Rz_um=(4.0, 6.3),
                        speed_rpm=3000.0, **mat)
    resultant = math.hypot(2000.0 * 210.0 / 42.0, 5000.0)
    assert weakest.friction_force_N / resultant == pytest.approx(1.5, rel=1e-6)
    # the slower case holds more (smaller centrifugal loss)
    rated = press_fit(42.0, 0.0, 70.0, 25.0, v["interference_min_um"], roughness_Rz_um=(4.0, 6.3),
                      speed_rpm=2500.0, **mat)
    assert rated.friction_force_N / resultant > 1.5
    assert res.active_constraints == ["overspeed:slip_reserve_N"]
    # stresses at the largest interference are inside the limits and match the model
    strongest = press_fit(42.0, 0.0, 70.0, 25.0, v["interference_max_um"], roughness_Rz_um=(4.0, 6.3),
                          hub_yield_MPa=700.0, shaft_yield_MPa=650.0, **mat)
    assert strongest.hub_yield_safety > 1.2
    assert res.margins.loc["overspeed", "hub_von_mises_rest_MPa"] == pytest.approx(strongest.hub_von_mises_MPa)
    # the suggested ISO 286 fit realises the interval: min >= required, max <= allowed
    fit = res.fit
    assert fit is not None
    assert fit["min_um"] >= v["required_min_interference_um"] - 1e-9
    assert fit["max_um"] <= v["allowed_max_interference_um"] + 1e-9
    assert fit == fit_interference_um(42.0, fit["fit"])


def test_separate_margins_make_the_binding_one_equal_the_target():
    spec = plain_spec()
    # torque-dominated: 2000 T/d = 20 kN of friction force against a 5 kN axial force
    res = size_press_fit(spec, JointDemand(400.0, 5000.0), target_margin=2.0, slip="separate", smoothing=False,
                         tolerance_band_um=0.0)
    m = res.margins.loc["demand"]
    assert m["torque_margin"] == pytest.approx(2.0, rel=1e-6)
    assert m["axial_margin"] > 2.0
    assert m["combined_margin"] < 2.0        # the separate criterion is weaker than the friction resultant
    assert res.active_constraints == ["demand:torque_reserve_Nm"]
    # axial-dominated
    res = size_press_fit(spec, JointDemand(10.0, 30000.0), target_margin=2.0, slip="separate", smoothing=False,
                         tolerance_band_um=0.0)
    assert res.margins.loc["demand", "axial_margin"] == pytest.approx(2.0, rel=1e-6)
    assert res.active_constraints == ["demand:axial_reserve_N"]


def test_max_margin_objective_ends_on_the_hub_stress_limit():
    # without smoothing and at rest the hub von Mises stress is linear in the interference: its limit fixes the
    # largest interference, delta_max = delta * safety / S_min, and the margin grows in proportion
    spec = plain_spec()
    res = size_press_fit(spec, JointDemand(400.0), target_margin=1.5, objective="max_margin", smoothing=False,
                         tolerance_band_um=20.0, min_hub_yield_safety=1.5)
    v = res.values
    strongest = press_fit(40.0, 0.0, 80.0, 30.0, v["interference_max_um"], E, NU, E, NU, 0.12, hub_yield_MPa=700.0)
    assert strongest.hub_yield_safety == pytest.approx(1.5, rel=1e-6)
    weakest = press_fit(40.0, 0.0, 80.0, 30.0, v["interference_min_um"], E, NU, E, NU, 0.12)
    assert weakest.torque_capacity_Nm / 400.0 == pytest.approx(v["margin"], rel=1e-6)
    assert v["allowed_max_interference_um"] == pytest.approx(v["interference_max_um"], rel=1e-6)
    assert any(n.endswith("hub_von_mises_rest_MPa") for n in res.active_constraints)


def test_free_length_goes_to_its_upper_bound_and_hub_diameter_helps():
    spec = plain_spec()
    fixed = size_press_fit(spec, JointDemand(400.0), smoothing=False, tolerance_band_um=0.0)
    free = size_press_fit(spec, JointDemand(400.0), smoothing=False, tolerance_band_um=0.0,
                          free=("interference_um", "length_mm", "hub_outer_diameter_mm"),
                          bounds={"length_mm": (20.0, 40.0), "hub_outer_diameter_mm": (60.0, 100.0)})
    assert free.values["length_mm"] == pytest.approx(40.0, rel=1e-6)
    assert free.values["hub_outer_diameter_mm"] == pytest.approx(100.0, rel=1e-6)
    # interference scales as 1/l and with the compliance factor (D_o^2/(D_o^2 - d^2)) of the equal-material form
    ratio = (30.0 / 40.0) * (100.0 ** 2 / (100.0 ** 2 - 1600.0)) / (80.0 ** 2 / (80.0 ** 2 - 1600.0))
    assert free.values["interference_um"] == pytest.approx(fixed.values["interference_um"] * ratio, rel=1e-6)
    assert free.margins.loc["demand", "torque_margin"] == pytest.approx(1.5, rel=1e-6)


def test_impossible_margin_raises_a_solve_error_naming_the_limits():
    with pytest.raises(SolveError) as err:
        size_press_fit(plain_spec(), JointDemand(20000.0), smoothing=False, tolerance_band_um=0.0)
    names = " ".join(v.name for v in err.value.violated)
    assert "slip_reserve" in names or "von_mises" in names


def test_default_data_joints_need_more_than_the_present_weakest_fit(data):
    # crank: H7/r6 at 65 mm gives 11 um at the weakest limit, less than the 8.24 um DIN 7190 smoothing loss plus
    # what 310 N m needs -- the sizing asks for more, and its margin is the target when re-evaluated
    res = size_joint(data, "crank", JointDemand(310.0, 0.0, 2500.0), target_margin=1.5)
    assert res.values["interference_min_um"] > 11.0
    assert res.margins.loc["demand", "torque_margin"] == pytest.approx(1.5, rel=1e-6)
    assert default_tolerance_band_um(65.0) == 30.0 + 19.0


# -------------------------------------------------------------------------------------------------------- taper fit

def taper_spec(**kw):
    args = dict(large_diameter_mm=30.0, small_diameter_mm=26.25, half_angle_deg=math.degrees(math.atan(1 / 16)),
                friction=0.15, thread_diameter_mm=16.0, nut_factor_min=0.12, nut_factor_max=0.16,
                hub_outer_diameter_mm=60.0, hub_yield_MPa=700.0, thread_stress_area_mm2=167.0,
                proof_strength_MPa=830.0, nut_torque_Nm=150.0, name="ac")
    args.update(kw)
    return TaperFitSpec(**args)


@pytest.mark.parametrize("theory", ["uniform_pressure", "uniform_wear"])
def test_taper_nut_torque_matches_cone_clutch_closed_form(theory):
    # rigid cone clutch (thesis Eq. 3.48 / Shigley's cone-clutch relations): T_cap = mu W r_f / sin(theta) with
    # r_f = (D^3 - d^3)/(3 (D^2 - d^2)) (uniform pressure) or (D + d)/4 (uniform wear); slip when
    # |T|/T_cap + F_a/W = 1, so W = S (|T| sin(theta)/(mu r_f) + |F_a|), and T_n = k_max W d (thesis Eq. 3.49)
    spec = taper_spec(theory=theory)
    T, Fa, S = 120.0, 3000.0, 1.5
    res = size_taper_fit(spec, JointDemand(T, Fa), target_margin=S)
    D, d, th = 30.0, 26.25, math.atan(1 / 16)
    r_f = (D ** 3 - d ** 3) / (3 * (D ** 2 - d ** 2)) if theory == "uniform_pressure" else (D + d) / 4
    W = S * (T * 1e3 * math.sin(th) / (0.15 * r_f) + Fa)
    assert res.values["nut_torque_Nm"] == pytest.approx(0.16 * W * 16.0 * 1e-3, rel=1e-6)
    # independent re-evaluation with the numeric taper model at the largest nut factor
    t = taper_fit(D, d, math.degrees(th), 0.15, nut_torque_Nm=res.values["nut_torque_Nm"], nut_factor=0.16,
                  thread_diameter_mm=16.0, theory=theory)
    u = taper_slip_utilisation(T, Fa, t.torque_capacity_Nm, t.bolt_preload_N)
    assert 1.0 / u == pytest.approx(S, rel=1e-6)


def test_taper_separate_and_engagement_friction():
    spec = taper_spec()
    sep = size_taper_fit(spec, JointDemand(120.0, 3000.0), slip="separate", capacity="engagement_friction")
    m = sep.margins.loc["demand"]
    assert min(m["torque_margin"], m["axial_margin"]) == pytest.approx(1.5, rel=1e-6)
    t = taper_fit(30.0, 26.25, math.degrees(math.atan(1 / 16)), 0.15, nut_torque_Nm=sep.values["nut_torque_Nm"],
                  nut_factor=0.16, thread_diameter_mm=16.0)
    assert t.torque_capacity_engagement_friction_Nm / 120.0 == pytest.approx(m["torque_margin"], rel=1e-9)
    comb = size_taper_fit(spec, JointDemand(120.0, 3000.0), capacity="engagement_friction")
    assert comb.values["nut_torque_Nm"] > sep.values["nut_torque_Nm"]     # the combined criterion is stricter


def test_taper_proof_load_limit_makes_large_demands_infeasible():
    spec = taper_spec()
    with pytest.raises(SolveError) as err:
        size_taper_fit(spec, JointDemand(1500.0, 20000.0), target_margin=2.0)
    assert any(v.name in ("thread_stress_MPa", "hub_von_mises_MPa", "demand:slip_utilisation")
               for v in err.value.violated)
    # the thread stress at the smallest nut factor stays below 0.9 x proof in a feasible sizing
    ok = size_taper_fit(spec, JointDemand(300.0, 5000.0))
    assert ok.margins.loc["demand", "proof_utilisation"] <= 0.9 + 1e-9
    assert ok.margins.loc["demand", "thread_stress_MPa"] == pytest.approx(
        ok.values["nut_torque_Nm"] * 1e3 / (0.12 * 16.0) / 167.0, rel=1e-9)


# ---------------------------------------------------------------------------------------------------- derivatives

def _fd_check(f, x0, h):
    x = ca.SX.sym("x", len(x0))
    out = f(x)
    J = np.array(ca.Function("J", [x], [ca.jacobian(out, x)])(x0))
    F = ca.Function("F", [x], [out])
    fd = np.zeros_like(J)
    for i in range(len(x0)):
        e = np.zeros(len(x0))
        e[i] = h[i]
        fd[:, i] = (np.array(F(x0 + e)).ravel() - np.array(F(x0 - e)).ravel()) / (2 * h[i])
    np.testing.assert_allclose(J, fd, rtol=1e-6, atol=1e-9)


def test_press_fit_margin_derivatives_match_finite_differences():
    spec = plain_spec(roughness_Rz_um=(4.0, 6.3))
    demand = JointDemand(300.0, 4000.0, 3000.0)

    def f(x):
        e = press_fit_sizing_margins(spec, x[0], demand, length_mm=x[1], hub_outer_diameter_mm=x[2],
                                     tolerance_band_um=20.0)
        return ca.vertcat(e["torque_margin"], e["axial_margin"], e["combined_margin"], e["hub_von_mises_rest_MPa"],
                          e["hub_von_mises_speed_MPa"], e["shaft_von_mises_speed_MPa"])

    _fd_check(f, np.array([60.0, 30.0, 80.0]), np.array([1e-3, 1e-4, 1e-4]))


def test_taper_margin_derivatives_match_finite_differences():
    spec = taper_spec()

    def f(x):
        e = taper_fit_sizing_margins(spec, x[0], JointDemand(120.0, 3000.0), capacity="engagement_friction")
        return ca.vertcat(e["torque_margin"], e["combined_margin"], e["hub_von_mises_MPa"], e["thread_stress_MPa"])

    _fd_check(f, np.array([80.0]), np.array([1e-3]))


# ------------------------------------------------------------------------------------------------------- fit choice

def test_suggest_fit_picks_the_lightest_fit_inside_the_interval():
    best, table = suggest_fit(42.0, 40.0, 95.0)
    feasible = table[table["feasible"]]
    assert best["fit"] in set(feasible["fit"])
    assert best["max_um"] == feasible["max_um"].min()
    assert best["min_um"] >= 40.0 and best["max_um"] <= 95.0
    # ISO 286 at 42 mm: H7/u6 = 45..86 um (the data's cam fit) lies in the interval
    assert "H7/u6" in set(feasible["fit"])
    none, _ = suggest_fit(42.0, 80.0, 85.0)            # narrower than every band
    assert none is None


# ----------------------------------------------------------------------------------------------------------- errors

def test_bad_inputs_raise_named_errors(data):
    with pytest.raises(GearoptInputError, match="target_margin"):
        size_press_fit(plain_spec(), JointDemand(100.0), target_margin=0.5)
    with pytest.raises(GearoptInputError, match="nothing to size"):
        JointDemand(0.0, 0.0)
    with pytest.raises(GearoptInputError, match="speed_rpm"):
        JointDemand(10.0, speed_rpm=-1.0)
    with pytest.raises(GearoptInputError, match="taper_nut"):
        TaperFitSpec.from_data(data, "cam")
    with pytest.raises(GearoptInputError, match="hub_outer_diameter_mm"):
        plain_spec(hub_outer_diameter_mm=30.0)
    with pytest.raises(GearoptInputError, match="free"):
        size_press_fit(plain_spec(), JointDemand(100.0), free=("length_mm",))
    with pytest.raises(GearoptInputError, match="slip"):
        size_taper_fit(taper_spec(), JointDemand(100.0), slip="both")
    with pytest.raises(GearoptInputError, match="joint"):
        size_joint(data, "nope", JointDemand(100.0))
