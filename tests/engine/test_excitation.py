"""Crank torques: gas-torque identity and a hand value, the general inertia torque against the power balance of the
reciprocating mass, energy check (mean gas torque x 4 pi = indicated work by -closed int V dp), firing-order
phasing, CasADi derivatives against finite differences, bad input."""

import math

import casadi as ca
import numpy as np
import pytest

from gearopt.data import load_system
from gearopt.engine import EngineExcitation, crank_torque, slider_crank
from gearopt.errors import GearoptInputError

SYSTEM = load_system()
DATA = SYSTEM.data
B, S, L, M = 107.0, 124.0, 192.0, 2.5
R = S / 2


@pytest.fixture(scope="module")
def ex():
    return EngineExcitation.from_data(SYSTEM, speed_rpm=2500.0)


def test_gas_torque_hand_value_and_identity():
    # at 90 deg ATDC s' = r exactly, so T = p A r: 100 bar x 8992.0 mm^2 x 62 mm = 5575.1 N m
    gas, inertia = crank_torque(90.0, 0.0, B, S, L, M, 100.0)
    assert gas == pytest.approx(10.0 * math.pi / 4 * B ** 2 * R * 1e-3, rel=1e-12)
    assert inertia == 0.0
    # T_g = F r sin(theta + beta) / cos(beta) (crank-effort form, beta = asin(lambda sin theta))
    th = np.linspace(-350.0, 350.0, 141)
    p = 20.0 + 50.0 * np.cos(np.radians(th)) ** 2
    gas, _ = crank_torque(th, 1500.0, B, S, L, M, p, crankcase_pressure_bar=1.0)
    t = np.radians(th)
    beta = np.arcsin(R / L * np.sin(t))
    f = (p - 1.0) * 0.1 * math.pi / 4 * B ** 2
    np.testing.assert_allclose(gas, f * R * 1e-3 * np.sin(t + beta) / np.cos(beta), rtol=1e-12, atol=1e-9)


def test_inertia_torque_general_form_is_the_power_balance_of_the_reciprocating_mass():
    # Along any crank motion theta(t), T_i * theta' = -d/dt (m v^2 / 2), v = s'(theta) theta' (Lagrange); this checks
    # both the velocity term and the crank-acceleration term -m s'^2 theta'' of the general form.
    w0, a, om = 260.0, 0.05, 900.0
    theta = lambda t: w0 * t + a * np.sin(om * t)
    dtheta = lambda t: w0 + a * om * np.cos(om * t)
    ddtheta = lambda t: -a * om * om * np.sin(om * t)

    def kinetic(t):
        v = slider_crank(theta(t), R, L)["ds_dtheta_mm"] * 1e-3 * dtheta(t)
        return 0.5 * M * v * v

    t = np.linspace(0.0, 0.05, 201)
    h = 1e-7
    dke = (kinetic(t + h) - kinetic(t - h)) / (2 * h)
    _, ti = crank_torque(np.degrees(theta(t)), dtheta(t) * 30 / math.pi, B, S, L, M, 0.0,
                         crank_acceleration_rad_s2=ddtheta(t))
    np.testing.assert_allclose(ti * dtheta(t), -dke, rtol=1e-6, atol=1e-6 * np.max(np.abs(dke)))
    # constant speed: the textbook T_i = -m r^2 w^2 (s'/r)(s''/r), zero mean over a revolution
    _, ti0 = crank_torque(np.arange(360.0), 2500.0, B, S, L, M, 0.0)
    assert abs(ti0.mean()) < 1e-9 * np.max(np.abs(ti0))
    # peak reciprocating torque, docs/default-data.md sec. 2.5 ([C]): ~450 N m at 2500 rpm, ~650 N m at 3000 rpm (m 2.5 kg)
    assert np.max(np.abs(ti0)) == pytest.approx(450.0, rel=0.03)
    _, ti3 = crank_torque(np.arange(360.0), 3000.0, B, S, L, M, 0.0)
    assert np.max(np.abs(ti3)) == pytest.approx(650.0, rel=0.03)


def test_energy_mean_gas_torque_times_4pi_is_indicated_work(ex):
    # work of all cylinders per cycle from the torque (mean over 720 deg x 4 pi) against the indicated work by
    # integration by parts, -closed int V dp (uses V from s, not s'); the crankcase pressure does no net work.
    n = 14400
    th = np.arange(n) * 4 * math.pi / n
    gas, inertia = ex.cylinder_torque_parts_Nm(th, 2500 * math.pi / 30)
    work_torque = np.mean(np.sum(gas, axis=0)) * 4 * math.pi
    deg = np.arange(n) * 720.0 / n
    s = slider_crank(np.radians(deg - 360.0), R, L)["piston_displacement_mm"]
    vol = math.pi / 4 * B ** 2 * s * 1e-9
    dp = np.asarray(ex.pressure.dpressure_dangle_bar_per_deg(deg)) * 1e5
    work_vdp = -np.sum(vol * dp) * 720.0 / n
    assert work_torque == pytest.approx(6 * work_vdp, rel=1e-9)
    assert ex.mean_torque_Nm() * 4 * math.pi == pytest.approx(work_torque, rel=1e-9)
    assert abs(np.mean(np.sum(inertia, axis=0))) < 1e-9 * np.max(np.abs(inertia))
    # against the public rating (202 kW brake at 2500 rpm, ISBe 5.9 sibling): mechanical efficiency 0.75..0.95
    assert 0.75 < 202.0 / ex.indicated_power_kW() < 0.95


def test_firing_order_phasing(ex):
    # each cylinder's gas torque peaks at the same angle after its own firing TDC; TDCs 0,120,..600 deg in 1-5-3-6-2-4
    assert [ex.firing_tdc_deg(c) for c in (1, 5, 3, 6, 2, 4)] == [0.0, 120.0, 240.0, 360.0, 480.0, 600.0]
    deg = np.arange(0.0, 720.0, 0.25)
    gas, _ = ex.cylinder_torque_parts_Nm(np.radians(deg), 2500 * math.pi / 30)
    offsets = [((deg[np.argmax(g)] - ex.firing_tdc_deg(c + 1)) % 720.0) for c, g in enumerate(gas)]
    assert max(offsets) - min(offsets) <= 0.25
    assert 10.0 < offsets[0] < 40.0                        # peak gas torque 10-40 deg after firing TDC
    # pressures: cylinder c at its firing TDC + offset equals cylinder 1's trace there
    for c in range(1, 7):
        a = math.radians(ex.firing_tdc_deg(c) + 12.0)
        assert float(ex.cylinder_pressure_bar(c, a)) == pytest.approx(float(ex.pressure.pressure_bar(372.0)), rel=1e-12)
    # the six cylinders' torques are the same function shifted by their firing TDC
    shift = round(ex.firing_tdc_deg(3) / 0.25)
    np.testing.assert_allclose(np.roll(gas[0], shift), gas[2], rtol=1e-9, atol=1e-6)


def test_casadi_derivatives_match_finite_differences(ex):
    x, w, a = ca.SX.sym("x"), ca.SX.sym("w"), ca.SX.sym("a")
    tq = ca.vertcat(*ex.cylinder_torques_Nm(x, w, a), ex.total_torque_Nm(x, w, a))
    f = ca.Function("f", [x, w, a], [tq])
    jac = ca.Function("j", [x, w, a], [ca.jacobian(tq, ca.vertcat(x, w, a))])
    for x0, w0, a0 in ((0.2, 262.0, 0.0), (6.4, 300.0, 2000.0), (11.0, 80.0, -500.0)):
        j = np.array(jac(x0, w0, a0))
        for col, d in enumerate(np.eye(3)):
            h = (1e-6, 1e-4, 1e-2)[col]
            fd = (np.array(f(*(np.array([x0, w0, a0]) + h * d))) - np.array(f(*(np.array([x0, w0, a0]) - h * d)))) / (2 * h)
            np.testing.assert_allclose(j[:, col:col + 1], fd, rtol=1e-5, atol=1e-4)
    # acceptance API on SX too
    th = ca.SX.sym("th")
    g, i = crank_torque(th, 2500.0, B, S, L, M, 80.0)
    fg = ca.Function("g", [th], [g, i, ca.jacobian(g + i, th)])
    v = fg(30.0)
    ref = crank_torque(30.0, 2500.0, B, S, L, M, 80.0)
    assert float(v[0]) == pytest.approx(ref[0], rel=1e-12) and float(v[1]) == pytest.approx(ref[1], rel=1e-12)
    fd = (sum(crank_torque(30.0 + 1e-5, 2500.0, B, S, L, M, 80.0)) - sum(crank_torque(30.0 - 1e-5, 2500.0, B, S, L, M,
                                                                                        80.0))) / 2e-5
    assert float(v[2]) == pytest.approx(fd, rel=1e-6)


def test_wiebe_and_unscaled_options():
    w = EngineExcitation.from_data(SYSTEM, speed_rpm=1500.0, pressure="wiebe")
    assert w.pressure.peak_bar == pytest.approx(170.0, rel=1e-9)
    raw = EngineExcitation.from_data(SYSTEM, speed_rpm=1500.0, pressure="wiebe", scale_to_map=False)
    assert raw.pressure.peak_bar == pytest.approx(180.1, rel=0.005)
    part = EngineExcitation.from_data(SYSTEM, speed_rpm=1500.0, load=0.5)
    assert part.pressure.peak_bar < w.pressure.peak_bar
    assert w.reciprocating_inertia_kgm2(1, 0.7) == pytest.approx(M * (slider_crank(0.7, R, L)["ds_dtheta_mm"]
                                                                     * 1e-3) ** 2)


@pytest.mark.parametrize("args, word", [
    ((30.0, -10.0, B, S, L, M, 50.0), "speed_rpm"),
    ((30.0, 1000.0, B, S, 50.0, M, 50.0), "rod_length_mm"),
    ((30.0, 1000.0, -B, S, L, M, 50.0), "bore_mm"),
    ((30.0, 1000.0, B, 0.0, L, M, 50.0), "stroke_mm"),
    ((30.0, 1000.0, B, S, L, -M, 50.0), "reciprocating_mass_kg"),
    ((30.0, 1000.0, B, S, L, M, float("inf")), "cylinder_pressure_bar"),
])
def test_crank_torque_bad_input(args, word):
    with pytest.raises(GearoptInputError, match=word):
        crank_torque(*args)


def test_excitation_bad_input(ex):
    with pytest.raises(GearoptInputError, match="speed_rad_s"):
        ex.total_torque_Nm(0.3, -5.0)
    with pytest.raises(GearoptInputError, match="crank_angle_rad"):
        ex.cylinder_torques_Nm([0.1, 0.2], 100.0)
    with pytest.raises(GearoptInputError, match="firing_order"):
        EngineExcitation(B, S, L, M, ex.pressure, firing_order=(1, 2, 2, 4, 5, 6))
    with pytest.raises(GearoptInputError, match="firing_interval_deg"):
        EngineExcitation(B, S, L, M, ex.pressure, firing_interval_deg=100.0)
    with pytest.raises(GearoptInputError, match="pressure"):
        EngineExcitation.from_data(SYSTEM, speed_rpm=2000.0, pressure="measured")
    with pytest.raises(GearoptInputError, match="speed_rpm"):
        EngineExcitation.from_data(SYSTEM, speed_rpm=-1.0)
    with pytest.raises(GearoptInputError, match="cylinder"):
        ex.firing_tdc_deg(7)
