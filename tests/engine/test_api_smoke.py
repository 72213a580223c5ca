"""Dual typing of the engine API: floats, numpy arrays, SX and MX give the same numbers."""

import math

import casadi as ca
import numpy as np
import pytest

from gearopt import engine as eng
from gearopt.data import load_system

SYSTEM = load_system()


@pytest.fixture(scope="module")
def excitation():
    return eng.EngineExcitation.from_data(SYSTEM, speed_rpm=2500.0)


def test_total_torque_same_value_for_float_array_sx_mx(excitation):
    th = np.array([0.1, 1.3, 2.9, 7.0])
    w, a = 262.0, 150.0
    ref = excitation.total_torque_Nm(th, w, a)
    for sym in (ca.SX, ca.MX):
        x, v, acc = sym.sym("x"), sym.sym("v"), sym.sym("a")
        f = ca.Function("f", [x, v, acc], [excitation.total_torque_Nm(x, v, acc)])
        got = np.array([float(f(t, w, a)) for t in th])
        np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-9)
    assert excitation.total_torque_Nm(float(th[1]), w, a) == pytest.approx(ref[1], rel=1e-12)


def test_per_throw_angles_equal_shared_angle(excitation):
    th, w = 0.77, 250.0
    shared = excitation.cylinder_torques_Nm(th, w)
    per = excitation.cylinder_torques_Nm([th] * 6, [w] * 6, [0.0] * 6)
    np.testing.assert_allclose(per, shared, rtol=1e-12, atol=1e-9)
    x = ca.SX.sym("x", 6)
    f = ca.Function("f", [x], [ca.vertcat(*excitation.cylinder_torques_Nm([x[i] for i in range(6)], w))])
    np.testing.assert_allclose(np.array(f([th] * 6)).ravel(), shared, rtol=1e-12, atol=1e-9)


def test_accessory_maps_symbolic_equals_numeric():
    for fun in (eng.camshaft_torque_Nm, eng.fuel_pump_torque_Nm, eng.air_compressor_torque_Nm,
                eng.lube_pump_torque_Nm):
        x = ca.SX.sym("x")
        f = ca.Function("f", [x], [fun(x, SYSTEM)])
        assert float(f(1.234)) == pytest.approx(float(fun(1.234, SYSTEM)), rel=1e-12, abs=1e-12)
        assert float(fun(1.234 + 2 * math.pi, SYSTEM)) == pytest.approx(float(fun(1.234, SYSTEM)), rel=1e-10, abs=1e-10)


def test_single_cylinder_api_and_pressure_options(excitation):
    th, w, a = 1.7, 240.0, 300.0
    per = excitation.cylinder_torques_Nm(th, w, a)
    for c in range(1, 7):
        assert excitation.cylinder_torque_Nm(c, th, w, a) == pytest.approx(per[c - 1], rel=1e-12, abs=1e-9)
    # pressures evaluated at a separate (nominal) angle, and scaled: gas torque scales as (f p - p_cc)
    gas1, _ = excitation.cylinder_torque_parts_Nm(th, w, pressure_angle_rad=th + 0.01)
    gas2, inertia2 = excitation.cylinder_torque_parts_Nm(th, w, pressure_angle_rad=th + 0.01, pressure_scale=0.5)
    p = excitation.cylinder_pressures_bar(th + 0.01)
    for i in range(6):
        ratio = (0.5 * p[i] - excitation.crankcase_pressure_bar) / (p[i] - excitation.crankcase_pressure_bar)
        assert gas2[i] == pytest.approx(ratio * gas1[i], rel=1e-12, abs=1e-9)
        assert excitation.cylinder_torque_Nm(i + 1, th, w, pressure_angle_rad=th + 0.01, pressure_scale=0.5) == \
            pytest.approx(gas2[i] + inertia2[i], rel=1e-12, abs=1e-9)
        assert p[i] == pytest.approx(excitation.cylinder_pressure_bar(i + 1, th + 0.01), rel=1e-12)
    # a symbolic pressure scale (an integrator parameter) gives the same numbers
    f = ca.SX.sym("f")
    g = ca.Function("g", [f], [excitation.total_torque_Nm(th, w, pressure_scale=f)])
    assert float(g(0.5)) == pytest.approx(excitation.total_torque_Nm(th, w, pressure_scale=0.5), rel=1e-12)
