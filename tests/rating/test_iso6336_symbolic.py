"""rate_iso6336 is dual-typed: one symbolic evaluation equals the numeric one, and the CasADi derivatives of the
factor chain an NLP would use (K_v -> K_Hbeta -> K_Halpha -> S_H, S_F, S_B, S_intS) match central differences."""

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.rating import rate_iso6336


def _outputs(r):
    return [r.factors["K_v"], r.factors["K_Hbeta"], r.factors["K_Fbeta"], r.factors["K_Halpha"],
            r.factors["Z_v"][0], r.safety_factors["S_H"][0], r.safety_factors["S_H"][1],
            r.safety_factors["S_F"][0], r.safety_factors["S_F"][1], r.safety_factors["S_B"],
            r.safety_factors["S_intS"]]


def _rate(b, torque, x1, speed=2500.0):
    pair = go.GearPair.from_profile_shifts(teeth=(38, 76), profile_shifts=(x1, 0.1), module_mm=3.0,
                                           face_width_mm=b)
    return rate_iso6336(pair, torque, speed, accuracy_grade=7, tip_relief_um=6.0, life_h=5000.0)


@pytest.fixture(scope="module")
def symbolic():
    b, t, x1 = ca.SX.sym("b"), ca.SX.sym("T"), ca.SX.sym("x1")
    f = ca.Function("rating", [ca.vertcat(b, t, x1)], [ca.vertcat(*_outputs(_rate(b, t, x1)))])
    return f


def test_symbolic_evaluation_equals_numeric(symbolic):
    z = [28.0, 350.0, 0.25]
    sym = np.array(symbolic(z)).ravel()
    num = np.array([float(v) for v in _outputs(_rate(*z))])
    assert np.all(np.isfinite(num))
    np.testing.assert_allclose(sym, num, rtol=1e-10)


def test_derivatives_match_central_differences(symbolic):
    z0 = np.array([28.0, 350.0, 0.25])
    zs = ca.SX.sym("z", 3)
    jfun = ca.Function("J", [zs], [ca.jacobian(symbolic(zs), zs)])
    jac = np.array(jfun(z0))
    steps = np.array([1e-4, 1e-3, 1e-6])
    for k in range(3):
        dz = np.zeros(3)
        dz[k] = steps[k]
        fd = (np.array(symbolic(z0 + dz)).ravel() - np.array(symbolic(z0 - dz)).ravel()) / (2 * steps[k])
        np.testing.assert_allclose(jac[:, k], fd, rtol=2e-5, atol=1e-8 * max(1.0, np.abs(fd).max()))
    assert np.abs(jac[:, 0]).max() > 0 and np.abs(jac[:, 1]).max() > 0  # the factors do depend on b and T
