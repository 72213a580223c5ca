"""Taper fit with a nut (thesis Eqs. 3.48-3.49, cone-clutch analogy): the default data's [C] values, quadrature of the
assumed pressure fields over the cone, the narrow-band limit, the engagement-friction reduction, errors, derivatives.

No published numeric cone-clutch example could be retrieved here (the tutor solutions found used inconsistent
geometry); the formulas are instead checked against direct numerical integration of friction over the cone."""

import math

import casadi as ca
import numpy as np
import pytest
from scipy.integrate import quad

from gearopt.data import load_default_data, values
from gearopt.errors import GearoptInputError
from gearopt.joints.taper_fit import cone_friction_radius_mm, taper_fit, taper_slip_utilisation


def _quadrature(D, d, theta_deg, mu, W, theory):
    """Torque [N m] and axial force check by integrating over the cone surface. Surface element on a cone of half
    angle theta at radius r: dA = 2 pi r dr / sin(theta); the normal pressure's axial component is p sin(theta)."""
    s = math.sin(math.radians(theta_deg))
    shape = (lambda r: 1.0) if theory == "uniform_pressure" else (lambda r: 1.0 / r)
    axial_per_p0 = quad(lambda r: shape(r) * s * 2 * math.pi * r / s, d / 2, D / 2)[0]
    p0 = W / axial_per_p0
    torque = quad(lambda r: mu * p0 * shape(r) * r * 2 * math.pi * r / s, d / 2, D / 2)[0]
    return torque / 1000.0, p0


@pytest.mark.parametrize("theory", ["uniform_pressure", "uniform_wear"])
@pytest.mark.parametrize("D, d, theta", [(30.0, 26.25, 3.5763), (25.0, 20.0, 5.7106), (80.0, 40.0, 30.0)])
def test_capacity_matches_quadrature_over_the_cone(theory, D, d, theta):
    r = taper_fit(D, d, theta, 0.15, bolt_preload_N=50000.0, theory=theory)
    T, p0 = _quadrature(D, d, theta, 0.15, 50000.0, theory)
    assert r.torque_capacity_Nm == pytest.approx(T, rel=1e-10)
    p_expected = p0 if theory == "uniform_pressure" else p0 / (d / 2)  # p = c/r peaks at the small end
    assert r.contact_pressure_MPa == pytest.approx(p_expected, rel=1e-10)


def test_default_data_taper_values_reproduced():
    # default_train.toml [joints.ac] / [joints.fp] [C] notes: W = T_n/(k D_b), thesis Eq. 3.48 uniform pressure
    d = values(load_default_data())
    expected = {"ac": (62500.0, 2117.0, {0.12: 2646.0, 0.16: 1984.0}),
                "fp": (47619.0, 811.0, {0.12: 1014.0, 0.16: 760.0})}
    for name, (W, T, by_k) in expected.items():
        j = d["joints"][name]
        r = taper_fit(j["taper_large_diameter_mm"], j["taper_small_diameter_mm"], j["taper_half_angle_deg"],
                      j["friction_coefficient"], nut_torque_Nm=j["nut_torque_Nm"], nut_factor=j["nut_factor"],
                      thread_diameter_mm=j["nut_thread_diameter_mm"])
        assert r.bolt_preload_N == pytest.approx(W, abs=0.5)
        assert r.torque_capacity_Nm == pytest.approx(T, abs=0.5)
        assert r.taper_length_mm == pytest.approx(j["taper_length_mm"], abs=1e-3)
        for k, Tk in by_k.items():
            rk = taper_fit(j["taper_large_diameter_mm"], j["taper_small_diameter_mm"], j["taper_half_angle_deg"],
                           j["friction_coefficient"], nut_torque_Nm=j["nut_torque_Nm"], nut_factor=k,
                           thread_diameter_mm=j["nut_thread_diameter_mm"])
            assert rk.torque_capacity_Nm == pytest.approx(Tk, abs=0.6)


def test_thesis_equation_3_48_form_and_theory_ordering():
    W, mu, D, d, th = 40000.0, 0.12, 40.0, 32.0, 4.0
    r = taper_fit(D, d, th, mu, bolt_preload_N=W)
    s = math.sin(math.radians(th))
    assert r.torque_capacity_Nm * 1000 == pytest.approx(W * mu / (3 * s) * (D ** 3 - d ** 3) / (D ** 2 - d ** 2))
    w = taper_fit(D, d, th, mu, bolt_preload_N=W, theory="uniform_wear")
    assert w.torque_capacity_Nm * 1000 == pytest.approx(W * mu * (D + d) / (4 * s))
    assert r.torque_capacity_Nm > w.torque_capacity_Nm  # uniform pressure is the less conservative model


def test_narrow_band_limit_both_theories_agree():
    # a narrow cone band at radius R: T -> mu W R / sin(theta), whichever pressure distribution
    R = 20.0
    for width in (1.0, 0.1, 0.01):
        rp = cone_friction_radius_mm(2 * R + width, 2 * R - width, "uniform_pressure")
        rw = cone_friction_radius_mm(2 * R + width, 2 * R - width, "uniform_wear")
        assert abs(rp - R) < 0.02 * width and abs(rw - R) < 1e-12


def test_engagement_friction_reduces_locked_normal_force():
    r = taper_fit(30.0, 26.25, 3.5763, 0.15, bolt_preload_N=62500.0)
    th = math.radians(3.5763)
    ratio = math.sin(th) / (math.sin(th) + 0.15 * math.cos(th))
    assert r.torque_capacity_engagement_friction_Nm == pytest.approx(ratio * r.torque_capacity_Nm)
    assert 3.3 < 1 / ratio < 3.5  # the 1:8 taper loses a factor ~3.4 (module docstring)
    assert r.self_locking
    # vanishing friction: the engagement correction disappears
    r0 = taper_fit(30.0, 26.25, 3.5763, 1e-9, bolt_preload_N=62500.0)
    assert r0.torque_capacity_engagement_friction_Nm / r0.torque_capacity_Nm == pytest.approx(1.0, abs=1e-7)
    assert not taper_fit(30.0, 20.0, 30.0, 0.15, bolt_preload_N=1000.0).self_locking


def test_hub_stress_is_lame_at_the_mean_diameter():
    r = taper_fit(30.0, 26.25, 3.5763, 0.15, bolt_preload_N=62500.0, hub_outer_diameter_mm=60.0, hub_yield_MPa=700.0)
    p, dm = r.contact_pressure_MPa, 28.125
    hoop = p * (3600 + dm ** 2) / (3600 - dm ** 2)
    assert r.hub_hoop_stress_MPa == pytest.approx(hoop)
    assert r.hub_von_mises_MPa == pytest.approx(math.sqrt(hoop ** 2 + hoop * p + p ** 2))
    assert r.hub_yield_safety == pytest.approx(700.0 / r.hub_von_mises_MPa)


def test_slip_utilisation_linear_interaction():
    assert taper_slip_utilisation(500.0, 0.0, 1000.0, 40000.0) == pytest.approx(0.5)
    assert taper_slip_utilisation(500.0, 20000.0, 1000.0, 40000.0) == pytest.approx(1.0)
    assert taper_slip_utilisation(-500.0, -20000.0, 1000.0, 40000.0) == pytest.approx(0.5)  # pushes onto the cone


@pytest.mark.parametrize("args, kw, match", [
    ((30.0, 26.0, 0.0, 0.15), {}, "half_angle_deg=0 deg is below"),
    ((30.0, 26.0, 45.0, 0.15), {}, "half_angle_deg=45 deg exceeds"),
    ((30.0, 26.0, 60.0, 0.15), {}, "half_angle_deg=60 deg exceeds its limit: must be < 45"),
    ((30.0, 26.0, 3.0, 0.0), {}, "friction=0 is below"),
    ((30.0, 26.0, 3.0, 1.2), {}, "friction=1.2 exceeds"),
    ((26.0, 30.0, 3.0, 0.15), {}, "small_diameter_mm=30 mm must be smaller than large_diameter_mm=26"),
    ((30.0, 26.0, 3.0, 0.15), {"theory": "cone"}, "theory='cone'"),
])
def test_bad_input_raises(args, kw, match):
    with pytest.raises(GearoptInputError, match=match):
        taper_fit(*args, bolt_preload_N=1000.0, **kw)


def test_preload_input_errors():
    with pytest.raises(GearoptInputError, match="exactly one"):
        taper_fit(30.0, 26.0, 3.0, 0.15)
    with pytest.raises(GearoptInputError, match="exactly one"):
        taper_fit(30.0, 26.0, 3.0, 0.15, bolt_preload_N=1.0, nut_torque_Nm=10.0, thread_diameter_mm=16.0)
    with pytest.raises(GearoptInputError, match="thread_diameter_mm"):
        taper_fit(30.0, 26.0, 3.0, 0.15, nut_torque_Nm=10.0)
    with pytest.raises(GearoptInputError, match="hub_outer_diameter_mm=28 mm must exceed"):
        taper_fit(30.0, 26.0, 3.0, 0.15, bolt_preload_N=1.0, hub_outer_diameter_mm=28.0)


def test_casadi_derivatives_match_finite_differences():
    x = ca.SX.sym("x", 4)  # nut torque, half angle, friction, large diameter

    def outputs(v, lib):
        out = []
        for theory in ("uniform_pressure", "uniform_wear"):
            r = taper_fit(v[3], 26.25, v[1], v[2], nut_torque_Nm=v[0], nut_factor=0.15, thread_diameter_mm=16.0,
                          theory=theory, hub_outer_diameter_mm=60.0)
            out += [r.torque_capacity_Nm, r.torque_capacity_engagement_friction_Nm, r.hub_von_mises_MPa]
        return lib(out)

    f = ca.Function("f", [x], [outputs(x, lambda l: ca.vertcat(*l))])
    J = np.array(ca.Function("J", [x], [ca.jacobian(f(x), x)])(np.array([150.0, 3.5763, 0.15, 30.0])))
    x0 = np.array([150.0, 3.5763, 0.15, 30.0])
    num = lambda v: np.array([float(t) for t in outputs(v, list)])
    for k in range(4):
        h = 1e-6 * max(abs(x0[k]), 1.0)
        e = np.zeros(4)
        e[k] = h
        assert np.allclose(J[:, k], (num(x0 + e) - num(x0 - e)) / (2 * h), rtol=1e-6, atol=1e-8), k
