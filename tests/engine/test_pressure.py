"""Cylinder pressure: Fourier fit of the measured trace (error stated), the double-Wiebe model against the data's
expected peak and IMEP and against thermodynamic limits, peak scaling, the speed-load map, bad input."""

import math

import casadi as ca
import numpy as np
import pytest

from gearopt.data import load_system
from gearopt.engine import (
    CylinderPressure,
    FourierSeries,
    double_wiebe_cycle,
    imep_bar,
    indicated_work_J,
    motored_peak_pressure_bar,
    peak_pressure_bar,
    slider_crank,
)
from gearopt.errors import GearoptInputError

SYSTEM = load_system()
DATA = SYSTEM.data
ENG = DATA["engine"]
GEOM = (ENG["bore_mm"], ENG["stroke_mm"], ENG["connecting_rod_length_mm"])


@pytest.fixture(scope="module")
def table():
    return CylinderPressure.from_data(SYSTEM)


@pytest.fixture(scope="module")
def wiebe_cycle():
    return double_wiebe_cycle(system=SYSTEM, **ENG["combustion"])


@pytest.fixture(scope="module")
def wiebe(wiebe_cycle):
    return CylinderPressure.from_double_wiebe(system=SYSTEM, **ENG["combustion"])


# ----------------------------------------------------------------------------------------------------------------
def test_fourier_series_reproduces_a_trigonometric_polynomial_exactly():
    f = lambda x: 3.0 + 2.0 * np.cos(2 * np.pi * x / 7.0) - 0.5 * np.sin(3 * 2 * np.pi * x / 7.0)
    s = FourierSeries.fit_function(f, 7.0, 5, samples=64)
    x = np.linspace(-10, 10, 57)
    np.testing.assert_allclose(s(x), f(x), atol=1e-13)
    w = 2 * np.pi / 7.0
    np.testing.assert_allclose(s.derivative(x), -2.0 * w * np.sin(w * x) - 1.5 * w * np.cos(3 * w * x), atol=1e-12)
    np.testing.assert_allclose(s.shifted(1.3)(x), f(x + 1.3), atol=1e-13)
    xs = ca.SX.sym("x")
    d = ca.Function("d", [xs], [ca.jacobian(s(xs), xs)])
    np.testing.assert_allclose([float(d(v)) for v in x[:5]], s.derivative(x[:5]), atol=1e-12)


def test_table_fit_error_against_raw_points(table):
    # The fitted series against the 72 raw points of the digitised Mendes 2008 trace (stated in the module docs):
    x = np.array(ENG["pressure_trace_crank_deg"])
    y = 10.0 * np.array(ENG["pressure_trace_MPa"])
    err = np.asarray(table.pressure_bar(x)) - y
    assert np.max(np.abs(err)) == pytest.approx(table.fit_max_error_bar)
    assert table.fit_max_error_bar < 3.0            # 2.82 bar, at 337.8 deg (8.7 bar jump between two points)
    assert table.fit_rms_error_bar < 0.85            # 0.80 bar
    assert table.peak_bar == pytest.approx(y.max(), rel=0.006)   # 151.2 vs 152.0 bar
    assert table.peak_angle_deg == pytest.approx(x[np.argmax(y)], abs=1.0)
    # periodic, no undershoot below the intake-stroke pressure level by more than the fit error
    grid = np.linspace(0, 720, 7201)
    p = np.asarray(table.pressure_bar(grid))
    assert p.min() > y.min() - table.fit_max_error_bar
    assert float(table.pressure_bar(1000.0)) == pytest.approx(float(table.pressure_bar(280.0)), abs=1e-9)


def test_more_harmonics_converge():
    fits = [CylinderPressure.from_data(SYSTEM, harmonics=h) for h in (24, 48, 96, 160)]
    rms = [f.fit_rms_error_bar for f in fits]
    assert rms == sorted(rms, reverse=True)
    assert rms[0] > 2.0 * rms[-1]
    # the peak converges to the table's peak
    assert abs(fits[-1].peak_bar - 151.99) < abs(fits[0].peak_bar - 151.99)


def test_peak_scaling_is_exact_and_proportional(table):
    p = CylinderPressure.from_data(SYSTEM, peak_bar=170.0)
    assert p.peak_bar == pytest.approx(170.0, rel=1e-12)
    _, _, smax, _ = p.series.extrema(samples=72000)
    assert smax == pytest.approx(170.0, rel=1e-6)
    th = np.linspace(0, 720, 101)
    np.testing.assert_allclose(p.pressure_bar(th), table.pressure_bar(th) * 170.0 / table.peak_bar, rtol=1e-12)
    assert p.scale == pytest.approx(170.0 / table.peak_bar)


def test_wiebe_reproduces_data_expected_values_within_stated_tolerance(wiebe_cycle):
    # Data (engine.combustion, [C] docs/default-data.md sec. 2.5): p_max ~167 bar at ~10 deg ATDC, closed-cycle IMEP ~20.7 bar.
    # This model with IVC/EVO at BDC gives 180.1 bar at 9.1 deg ATDC, closed-cycle IMEP 21.00 bar and net IMEP 20.74
    # bar (after the blowdown loss). Stated tolerance: peak within 10 %, IMEP within 3 %. The 8 % peak gap is the
    # data's approximate [C] figure (details of its calculation are not recorded); see the report to the lead.
    c = ENG["combustion"]
    assert wiebe_cycle["peak_bar"] == pytest.approx(c["expected_peak_pressure_bar"], rel=0.10)
    assert wiebe_cycle["peak_angle_deg_atdc"] == pytest.approx(10.0, abs=2.0)
    assert wiebe_cycle["closed_cycle_imep_bar"] == pytest.approx(c["expected_imep_bar"], rel=0.03)
    assert wiebe_cycle["imep_bar"] == pytest.approx(c["expected_imep_bar"], rel=0.03)
    assert wiebe_cycle["imep_bar"] < wiebe_cycle["closed_cycle_imep_bar"]       # blowdown costs work


def test_wiebe_solution_satisfies_the_single_zone_equation(wiebe_cycle):
    # residual of dp/dtheta = (gamma-1)/V dQ/dtheta - gamma p/V dV/dtheta on the returned closed-cycle trace
    # (Heywood, Internal Combustion Engine Fundamentals, eq. 9.25 without heat transfer), central differences
    c = ENG["combustion"]
    th = wiebe_cycle["crank_deg"] - 360.0
    p = wiebe_cycle["pressure_bar"] * 1e5
    q = wiebe_cycle["heat_release_J"]
    k = slider_crank(np.radians(th), GEOM[1] / 2, GEOM[2])
    area = math.pi / 4 * GEOM[0] ** 2 * 1e-6
    v_c = area * GEOM[1] * 1e-3 / (ENG["compression_ratio"] - 1.0)
    v = v_c + area * k["piston_displacement_mm"] * 1e-3
    dv = area * k["ds_dtheta_mm"] * 1e-3 * math.pi / 180.0
    h = th[1] - th[0]
    i = np.nonzero((th > -170) & (th < 170) & (np.abs(th - c["start_of_combustion_deg_atdc"]) > 2 * h))[0]
    dp = (p[i + 1] - p[i - 1]) / (2 * h)
    dq = (q[i + 1] - q[i - 1]) / (2 * h)
    g = c["ratio_of_specific_heats"]
    rhs = (g - 1.0) / v[i] * dq - g * p[i] / v[i] * dv[i]
    # central differences on a 0.088 deg grid: measured 1.7e-5 of the largest slope (gamma 1.30 instead of 1.34
    # would give 0.12)
    assert np.max(np.abs(dp - rhs)) < 1e-4 * np.max(np.abs(dp))


def test_wiebe_limits_motored_and_constant_volume(wiebe_cycle):
    # no heat release: isentropic compression and expansion, p_TDC = p_IVC CR^gamma exactly, zero net work
    c = dict(ENG["combustion"], heat_release_per_cylinder_kJ=0.0)
    m = double_wiebe_cycle(system=SYSTEM, **c)
    gamma, cr = c["ratio_of_specific_heats"], ENG["compression_ratio"]
    assert m["peak_bar"] == pytest.approx(c["pressure_at_ivc_bar"] * cr ** gamma, rel=1e-7)
    assert m["peak_angle_deg_atdc"] == pytest.approx(0.0, abs=0.05)
    assert m["closed_cycle_imep_bar"] == pytest.approx(0.0, abs=1e-6)
    # near-instant combustion at TDC approaches the constant-volume (Otto) cycle: efficiency 1 - CR^(1-gamma)
    fast = dict(ENG["combustion"], start_of_combustion_deg_atdc=-0.5, premixed_fraction=1.0, premixed_duration_deg=1.0)
    o = double_wiebe_cycle(system=SYSTEM, **fast)
    v_d = math.pi / 4 * ENG["bore_mm"] ** 2 * ENG["stroke_mm"] * 1e-9
    eta = o["closed_cycle_imep_bar"] * 1e5 * v_d / (fast["heat_release_per_cylinder_kJ"] * 1e3)
    assert eta == pytest.approx(1.0 - cr ** (1.0 - gamma), rel=0.01)
    # the real heat release timing (SOC -4, 55 deg diffusion) loses efficiency against Otto
    eta_data = wiebe_cycle["closed_cycle_imep_bar"] * 1e5 * v_d / (ENG["combustion"]["heat_release_per_cylinder_kJ"] * 1e3)
    assert eta_data < eta


def test_wiebe_fit_and_imep_by_p_dv(wiebe, wiebe_cycle):
    assert wiebe.fit_max_error_bar < 4.5                  # 4.36 bar at the premixed-burn rise (stated in docs)
    assert wiebe.fit_rms_error_bar < 0.45
    assert wiebe.peak_bar == pytest.approx(wiebe_cycle["peak_bar"], rel=0.005)
    # IMEP of the fitted series by the integral of p dV (the integrand's s' from the exact kinematics) against the
    # raw model's IMEP: the fit keeps the work to 0.1 %
    assert imep_bar(wiebe, *GEOM) == pytest.approx(wiebe_cycle["imep_bar"], rel=1e-3)
    # integration by parts: closed integral of p dV = - closed integral of V dp (independent of s')
    th = np.arange(14400) * 0.05
    s = slider_crank(np.radians(th - 360.0), GEOM[1] / 2, GEOM[2])["piston_displacement_mm"]
    v = math.pi / 4 * GEOM[0] ** 2 * s * 1e-9
    dp = np.asarray(wiebe.dpressure_dangle_bar_per_deg(th)) * 1e5
    w_parts = -np.sum(v * dp) * 0.05
    assert indicated_work_J(wiebe, *GEOM) == pytest.approx(w_parts, rel=1e-9)


def test_pressure_symbolic_equals_numeric_and_derivative(wiebe):
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [wiebe.pressure_bar(x), ca.jacobian(wiebe.pressure_bar(x), x)])
    for th in (10.0, 355.0, 367.0, 500.0):
        v, d = f(th)
        assert float(v) == pytest.approx(float(wiebe.pressure_bar(th)), rel=1e-12)
        fd = (float(wiebe.pressure_bar(th + 1e-4)) - float(wiebe.pressure_bar(th - 1e-4))) / 2e-4
        assert float(d) == pytest.approx(fd, rel=1e-6, abs=1e-6)


# ----------------------------------------------------------------------------------------------------------------
def test_peak_pressure_map():
    # full load 170 bar [E] up to 2200 rpm, Mendes derate shape stretched to high idle, held beyond
    assert float(peak_pressure_bar(750.0, 1.0, SYSTEM)) == pytest.approx(170.0)
    assert float(peak_pressure_bar(2200.0, 1.0, SYSTEM)) == pytest.approx(170.0)
    mendes = DATA["engine"]["mendes_2008"]
    ratio_end = mendes["peak_pressure_MPa"][-1] / 15.1
    assert float(peak_pressure_bar(2850.0, 1.0, SYSTEM)) == pytest.approx(170.0 * ratio_end)
    assert float(peak_pressure_bar(3000.0, 1.0, SYSTEM)) == pytest.approx(170.0 * ratio_end)
    # the Mendes 2300 rpm point (13.5/15.1) maps to 2200 + 100 * 650/350 rpm
    assert float(peak_pressure_bar(2200.0 + 100.0 * 650.0 / 350.0, 1.0, SYSTEM)) == pytest.approx(170.0 * 13.5 / 15.1)
    n = np.linspace(500, 3200, 271)
    p = peak_pressure_bar(n, 1.0, SYSTEM)
    assert np.all(np.diff(p) <= 1e-12)                       # non-increasing with speed at full load
    # part load: motored peak at load 0, linear in load
    p_mot = motored_peak_pressure_bar(17.3, 1.34)
    assert p_mot == pytest.approx(17.3 ** 1.34)
    assert float(peak_pressure_bar(1500.0, 0.0, SYSTEM)) == pytest.approx(p_mot)
    assert float(peak_pressure_bar(1500.0, 0.5, SYSTEM)) == pytest.approx(0.5 * (p_mot + 170.0))
    # dual-typed: same numbers from SX, derivative -> slope of the active segment
    s = ca.SX.sym("n")
    f = ca.Function("f", [s], [peak_pressure_bar(s, 1.0, SYSTEM), ca.jacobian(peak_pressure_bar(s, 1.0, SYSTEM), s)])
    v, d = f(2500.0)
    assert float(v) == pytest.approx(float(peak_pressure_bar(2500.0, 1.0, SYSTEM)))
    fd = (float(peak_pressure_bar(2501.0, 1.0, SYSTEM)) - float(peak_pressure_bar(2499.0, 1.0, SYSTEM))) / 2.0
    assert float(d) == pytest.approx(fd, rel=1e-9)


@pytest.mark.parametrize("kwargs, word", [({"speed_rpm": -100.0}, "speed_rpm"), ({"speed_rpm": 0.0}, "speed_rpm"),
                                          ({"speed_rpm": 1000.0, "load": 1.2}, "load"),
                                          ({"speed_rpm": 1000.0, "load": -0.1}, "load")])
def test_map_bad_input(kwargs, word):
    with pytest.raises(GearoptInputError, match=word):
        peak_pressure_bar(**{"load": 1.0, **kwargs}, system=SYSTEM)


def test_table_and_wiebe_bad_input():
    with pytest.raises(GearoptInputError, match="increasing"):
        CylinderPressure.from_table([0, 100, 50, 700], [1, 2, 3, 4])
    with pytest.raises(GearoptInputError, match="spans"):
        CylinderPressure.from_table([0, 100, 500, 800], [1, 2, 3, 4])
    with pytest.raises(GearoptInputError, match="pressure_bar"):
        CylinderPressure.from_table([0, 100, 500, 700], [1, -2, 3, 4])
    with pytest.raises(GearoptInputError, match="peak_bar"):
        CylinderPressure.from_table([0, 100, 500, 700], [1, 2, 3, 4], peak_bar=-5.0)
    with pytest.raises(GearoptInputError, match="harmonics"):
        CylinderPressure.from_table([0, 100, 500, 700], [1, 2, 3, 4], harmonics=5000)
    with pytest.raises(GearoptInputError, match="unknown"):
        double_wiebe_cycle(system=SYSTEM, bogus_parameter=1.0)
    with pytest.raises(GearoptInputError, match="premixed_fraction"):
        double_wiebe_cycle(system=SYSTEM, premixed_fraction=1.5)
    with pytest.raises(GearoptInputError, match="compression_ratio"):
        double_wiebe_cycle(system=SYSTEM, compression_ratio=0.8)
