"""Exact slider-crank kinematics: derivatives against numerical differentiation, the force-transmission identity,
the classical series of the piston acceleration (analytic limit), symbolic derivatives, bad input."""

import math

import casadi as ca
import numpy as np
import pytest

from gearopt.engine import reciprocating_inertia_kgm2, slider_crank
from gearopt.errors import GearoptInputError

R, L = 62.0, 192.0


def test_end_positions_and_stroke():
    k = slider_crank(np.array([0.0, math.pi, 2 * math.pi]), R, L)
    np.testing.assert_allclose(k["piston_displacement_mm"], [0.0, 2 * R, 0.0], atol=1e-12)
    np.testing.assert_allclose(k["ds_dtheta_mm"], [0.0, 0.0, 0.0], atol=1e-12)
    # s'' at TDC/BDC: r(1 + lambda), r(-1 + lambda) (textbook limits of cos t + lambda cos 2t)
    np.testing.assert_allclose(k["d2s_dtheta2_mm"][:2], [R * (1 + R / L), R * (-1 + R / L)], rtol=1e-14)


@pytest.mark.parametrize("lam", [0.05, 0.25, 0.3229, 0.5, 0.9])
def test_derivatives_match_numerical_differentiation(lam):
    th = np.linspace(-7.0, 7.0, 301)
    h = 1e-4
    r, rod = 50.0, 50.0 / lam
    s = lambda t: slider_crank(t, r, rod)["piston_displacement_mm"]
    k = slider_crank(th, r, rod)
    # 4th-order central differences: truncation ~h^4 s^(5) ~ 1e-16 r, rounding ~ eps r / h ~ 1e-10 r
    d1 = (-s(th + 2 * h) + 8 * s(th + h) - 8 * s(th - h) + s(th - 2 * h)) / (12 * h)
    d2 = (-s(th + 2 * h) + 16 * s(th + h) - 30 * s(th) + 16 * s(th - h) - s(th - 2 * h)) / (12 * h * h)
    np.testing.assert_allclose(k["ds_dtheta_mm"], d1, atol=1e-8 * r)
    np.testing.assert_allclose(k["d2s_dtheta2_mm"], d2, atol=2e-5 * r)


def test_force_transmission_identity():
    # s' = r sin(theta + beta) / cos(beta), beta the rod angle (the classical crank-effort lever arm)
    th = np.linspace(0.0, 2 * math.pi, 181)
    k = slider_crank(th, R, L)
    beta = k["rod_angle_rad"]
    np.testing.assert_allclose(k["ds_dtheta_mm"], R * np.sin(th + beta) / np.cos(beta), atol=1e-12 * R)
    np.testing.assert_allclose(np.sin(beta), R / L * np.sin(th), atol=1e-15)


def test_piston_acceleration_series_coefficients():
    # Classical harmonic series of the piston acceleration (Den Hartog, Mechanical Vibrations, sec. 5.5; Taylor,
    # The Internal Combustion Engine in Theory and Practice, vol. 2 ch. 8):
    # s''/r = cos t + A2 cos 2t + A4 cos 4t + A6 cos 6t + ..., A2 = l + l^3/4 + 15 l^5/128, A4 = -(l^3/4 + 3 l^5/16),
    # A6 = 9 l^5/128, with omitted terms O(l^7). The exact s'' must reproduce them to that order.
    for lam in (0.1, 0.2, 0.3):
        n = 1024
        th = np.arange(n) * 2 * math.pi / n
        a = np.fft.rfft(slider_crank(th, 1.0, 1.0 / lam)["d2s_dtheta2_mm"]).real * 2 / n
        assert a[1] == pytest.approx(1.0, abs=1e-13)
        assert a[3] == pytest.approx(0.0, abs=1e-13) and a[5] == pytest.approx(0.0, abs=1e-13)   # odd orders vanish
        tol = 2 * lam ** 7
        assert a[2] == pytest.approx(lam + lam ** 3 / 4 + 15 * lam ** 5 / 128, abs=tol)
        assert a[4] == pytest.approx(-(lam ** 3 / 4 + 3 * lam ** 5 / 16), abs=tol)
        assert a[6] == pytest.approx(9 * lam ** 5 / 128, abs=tol)


def test_inertia_torque_fourier_coefficients_reference_data():
    # docs/default-data.md sec. 2.4 (lambda 0.3): sine coefficients of T_i / (m r^2 w^2) = -(s'/r)(s''/r) are
    # +0.0768, -0.5003, -0.2330, -0.0236, +0.0046 (k = 1..5), against the common approximation
    # lambda/4, -1/2, -3 lambda/4, -lambda^2/4 = 0.075, -0.5, -0.225, -0.0225 (Den Hartog).
    n = 1024
    th = np.arange(n) * 2 * math.pi / n
    k = slider_crank(th, 1.0, 1.0 / 0.3)
    b = -np.fft.rfft(-k["ds_dtheta_mm"] * k["d2s_dtheta2_mm"]).imag * 2 / n
    np.testing.assert_allclose(b[1:6], [0.0768, -0.5003, -0.2330, -0.0236, 0.0046], atol=6e-5)
    # leading-order agreement with the textbook approximation, error O(lambda^3)
    np.testing.assert_allclose(b[1:5], [0.075, -0.5, -0.225, -0.0225], atol=0.3 ** 3 * 0.35)


def test_reciprocating_inertia_mean():
    # mean of m s'^2 over a revolution = m r^2 (1/2 + lambda^2/8) + O(lambda^4) (from s'/r = sin t + lambda/2 sin 2t)
    n = 2048
    th = np.arange(n) * 2 * math.pi / n
    j = reciprocating_inertia_kgm2(th, R, L, 2.5)
    lam = R / L
    assert j.mean() == pytest.approx(2.5 * (R * 1e-3) ** 2 * (0.5 + lam ** 2 / 8), rel=lam ** 4)


def test_symbolic_derivatives_match_finite_differences():
    x = ca.SX.sym("theta")
    r = ca.SX.sym("r")
    k = slider_crank(x, r, L)
    out = ca.vertcat(k["piston_displacement_mm"], k["ds_dtheta_mm"], k["d2s_dtheta2_mm"])
    f = ca.Function("f", [x, r], [out])
    jac = ca.Function("j", [x, r], [ca.jacobian(out, ca.vertcat(x, r))])
    for th0 in (0.0, 0.4, 1.9, 3.3, 5.9):
        h = 1e-6
        fd_t = (np.array(f(th0 + h, R)) - np.array(f(th0 - h, R))) / (2 * h)
        fd_r = (np.array(f(th0, R + h)) - np.array(f(th0, R - h))) / (2 * h)
        jj = np.array(jac(th0, R))
        np.testing.assert_allclose(jj[:, 0:1], fd_t, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(jj[:, 1:2], fd_r, rtol=1e-6, atol=1e-6)
    # s' is d s/d theta and s'' is d s'/d theta exactly (symbolically)
    assert float(ca.Function("g", [x, r], [ca.jacobian(k["piston_displacement_mm"], x) - k["ds_dtheta_mm"]])(1.1, R)) \
        == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("r, rod, word", [(62.0, 50.0, "rod_length_mm"), (62.0, 62.0, "rod_length_mm"),
                                          (0.0, 192.0, "crank_radius_mm"), (-5.0, 192.0, "crank_radius_mm"),
                                          (62.0, float("nan"), "rod_length_mm")])
def test_bad_geometry_raises(r, rod, word):
    with pytest.raises(GearoptInputError, match=word):
        slider_crank(0.3, r, rod)


def test_negative_mass_raises():
    with pytest.raises(GearoptInputError, match="reciprocating_mass_kg"):
        reciprocating_inertia_kgm2(0.3, R, L, -1.0)
