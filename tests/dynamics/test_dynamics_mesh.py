"""Gear mesh force, stiffness shape and axial force of the torsional model (gearopt.dynamics.mesh)."""

import math

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.rating.stiffness import contact_line_length_mm
from gearopt.dynamics.mesh import (
    MeshStiffnessShape,
    axial_force_N,
    contact_line_length_ratio,
    mesh_force,
    restitution_coefficient,
)
from gearopt.errors import GearoptInputError

K, C, J_BACK, W = 5.0e8, 4000.0, 150e-6, 0.05e-6


# ----------------------------------------------------------------------------------------------------------------
# contact-line length and stiffness shape
# ----------------------------------------------------------------------------------------------------------------

def test_contact_line_ratio_spur_is_the_single_double_pair_wave():
    # plane-of-action geometry (ISO 21771): a spur mesh alternates between floor(eps) and ceil(eps) pairs, the
    # double-pair zone lasting (eps - 1) of a base pitch
    eps = 1.61
    u = (np.arange(10000) + 0.5) / 10000
    r = contact_line_length_ratio(u, eps)
    assert r.mean() == pytest.approx(1.0, abs=1e-4)
    assert set(np.round(r * eps, 12)) == {1.0, 2.0}
    assert np.mean(np.isclose(r * eps, 2.0)) == pytest.approx(eps - 1.0, abs=1e-3)


def test_contact_line_ratio_integer_overlap_is_constant():
    # classical result: with an integer overlap ratio the total contact-line length does not vary
    r = contact_line_length_ratio(np.linspace(0, 1, 997), 1.43, 1.0)
    assert np.ptp(r) < 1e-12
    assert r.mean() == pytest.approx(1.0)


def test_contact_line_ratio_extremes_match_the_contact_module():
    # independent implementation: gearopt.rating.stiffness.contact_line_length_mm (exact min/max over the cycle)
    pair = go.load_default_train("helical").pairs["crank-cam"]
    g = pair.geometry()
    eps_a, eps_b = g["transverse_contact_ratio"], g["overlap_contact_ratio"]
    r = contact_line_length_ratio(np.linspace(0, 1, 20001), eps_a, eps_b)
    mean = contact_line_length_mm(pair, "mean")
    assert r.min() == pytest.approx(contact_line_length_mm(pair, "minimum") / mean, rel=1e-4)
    assert r.max() == pytest.approx(contact_line_length_mm(pair, "maximum") / mean, rel=1e-4)


def test_shape_from_samples_recovers_a_fourier_series_and_has_mean_one():
    psi = 2 * np.pi * np.arange(256) / 256
    k = 3.0 * (1 + 0.2 * np.cos(psi) - 0.05 * np.sin(2 * psi) + 0.01 * np.cos(3 * psi))
    shape = MeshStiffnessShape.from_samples(psi, k, harmonics=4, smoothing="none")
    assert shape.cos_coefficients == pytest.approx((0.2, 0.0, 0.01, 0.0), abs=1e-12)
    assert shape.sin_coefficients == pytest.approx((0.0, -0.05, 0.0, 0.0), abs=1e-12)
    assert np.mean(shape.factor(psi)) == pytest.approx(1.0, abs=1e-12)
    assert np.mean(shape.factor(psi, 0.0)) == 1.0


def test_default_shape_is_smooth_and_bounded():
    shape = MeshStiffnessShape.from_contact_ratios(1.61, 0.0, harmonics=5)
    psi = np.linspace(0, 2 * np.pi, 4001)
    f = shape.factor(psi)
    assert f.min() > 0.5 and f.max() < 1.5           # smoothed 1/1.61 .. 2/1.61 wave
    assert np.mean(f[:-1]) == pytest.approx(1.0, abs=1e-12)
    with pytest.raises(GearoptInputError, match="transverse_contact_ratio"):
        MeshStiffnessShape.from_contact_ratios(0.9)
    with pytest.raises(GearoptInputError, match="equally spaced"):
        MeshStiffnessShape.from_samples(np.array([0.0, 0.1, 0.3, 0.4, 0.5, 0.6]), np.ones(6), harmonics=1)


# ----------------------------------------------------------------------------------------------------------------
# mesh force
# ----------------------------------------------------------------------------------------------------------------

def test_zero_lash_is_the_linear_mesh_exactly():
    # sp(x) - sp(-x) = x and sig(x) + sig(-x) = 1: the lash model with j = 0 is the linear model for any width
    d = np.linspace(-30e-6, 30e-6, 1201)
    dd = np.linspace(-0.3, 0.2, 1201)
    lin = mesh_force(d, dd, K, C)["force_N"]
    for w in (1e-9, 1e-7, 1e-6):
        lash = mesh_force(d, dd, K, C, backlash_m=0.0, contact_width_m=w)["force_N"]
        np.testing.assert_allclose(lash, lin, rtol=0, atol=1e-9 * np.max(np.abs(lin)))


def test_dead_zone_converges_to_the_exact_piecewise_force():
    # exact dead zone (Kahraman & Singh 1990): F = k (d) for d > 0, 0 in the gap, k (d + j) for d < -j;
    # the smooth force differs by at most k w ln 2 (numerics.softplus bound)
    d = np.linspace(-300e-6, 100e-6, 4001)
    exact = np.where(d > 0, K * d, np.where(d < -J_BACK, K * (d + J_BACK), 0.0))
    for w in (1e-6, 1e-7, 1e-8):
        f = mesh_force(d, 0.0 * d, K, C, backlash_m=J_BACK, contact_width_m=w)
        err = np.max(np.abs(f["force_N"] - exact))
        assert err <= K * w * math.log(2) * (1 + 1e-9)
        assert err >= 0.5 * K * w * math.log(2)     # the bound is attained at the contact points
    inside = (d < -40 * 1e-8) & (d > -J_BACK + 40 * 1e-8)
    f = mesh_force(d, 0.1 + 0 * d, K, C, backlash_m=J_BACK, contact_width_m=1e-8)
    assert np.max(np.abs(f["force_N"][inside])) < 1e-3       # free flight: no force, no damping
    assert np.all(f["drive_contact"][d > 1e-7] > 0.99) and np.all(f["back_contact"][d < -J_BACK - 1e-7] > 0.99)


def test_flank_forces_split_the_signed_force():
    f = mesh_force(np.array([20e-6, -J_BACK - 20e-6]), np.array([0.0, 0.0]), K, C, backlash_m=J_BACK,
                   contact_width_m=W)
    assert f["drive_force_N"][0] == pytest.approx(K * 20e-6, rel=1e-9)
    assert f["back_force_N"][1] == pytest.approx(K * 20e-6, rel=1e-9)
    assert f["force_N"][1] == pytest.approx(-K * 20e-6, rel=1e-9)
    lin = mesh_force(np.array([20e-6, -20e-6]), np.zeros(2), K, C)
    assert lin["drive_force_N"].tolist() == pytest.approx([K * 20e-6, 0.0])
    assert lin["back_force_N"].tolist() == pytest.approx([0.0, K * 20e-6])


def test_mesh_force_derivatives_match_finite_differences():
    # every kernel that may feed an NLP: CasADi derivatives (SX) against central differences
    z = ca.SX.sym("z", 5)  # delta, delta_dot, k, c, j
    f = mesh_force(z[0], z[1], z[2], z[3], backlash_m=z[4], contact_width_m=0.2e-6)["force_N"]
    jac = ca.Function("dforce", [z], [ca.jacobian(f, z)])
    fun = ca.Function("f", [z], [f])
    scale = np.array([1e-6, 1e-2, 1e6, 10.0, 1e-6])
    for point in ([2e-6, 0.05, K, C, J_BACK], [-J_BACK - 0.1e-6, -0.02, K, C, J_BACK], [0.05e-6, 0.1, K, C, J_BACK]):
        x = np.array(point)
        num = np.array([(float(fun(x + h * e)) - float(fun(x - h * e))) / (2 * h)
                        for e, h in zip(np.eye(5), 1e-4 * scale)])
        ana = np.array(jac(x)).ravel()
        np.testing.assert_allclose(ana, num, rtol=1e-5, atol=1e-6 * np.max(np.abs(num)))


def test_axial_force_is_ft_tan_beta():
    # ISO 21771: tan(beta_b) = tan(beta) cos(alpha_t) and F_t = F_bt cos(alpha_t) at the reference circle
    pair = go.load_default_train("helical").pairs["crank-cam"]
    g = pair.geometry()
    f_bt = 4000.0
    f_t = f_bt * math.cos(math.radians(g["transverse_pressure_angle_deg"]))
    assert axial_force_N(f_bt, g["base_helix_angle_deg"]) == pytest.approx(
        f_t * math.tan(math.radians(g["helix_angle_deg"])), rel=1e-12)
    assert axial_force_N(f_bt, 0.0) == 0.0


def test_restitution_limits_and_bad_input():
    assert restitution_coefficient(0.0) == 1.0
    assert restitution_coefficient(0.08) == pytest.approx(math.exp(-math.pi * 0.08 / math.sqrt(1 - 0.0064)))
    with pytest.raises(GearoptInputError, match="damping_ratio"):
        restitution_coefficient(1.0)
    with pytest.raises(GearoptInputError, match="backlash_m=-1e-05"):
        mesh_force(0.0, 0.0, K, C, backlash_m=-1e-5)
    with pytest.raises(GearoptInputError, match="stiffness_N_per_m"):
        mesh_force(0.0, 0.0, -1.0, C)
