"""Engine excitation against published numbers: a textbook crank-effort example and the thesis' Table 3.5 shapes."""

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from gearopt.data import load_system
from gearopt.engine import EngineExcitation, crank_torque, slider_crank

SYSTEM = load_system()
DATA = SYSTEM.data
T35 = DATA["thesis"]["table_3_5"]
DEG = np.array(T35["crank_deg"], dtype=float)

IN_MM, PSI_BAR, LBFFT_NM = 25.4, 0.0689475729, 1.3558179483


def test_bevan_turning_moment_example():
    # T. Bevan, The Theory of Machines, ch. 12 (Dynamics of machines, turning moment), Example 3, as worked in the
    # FOSSEE Python Textbook Companion: steam engine, bore 9 in, stroke 24 in, piston rod 2 in, connecting rod 60 in,
    # crank 40 deg from dead centre, 160 psi on the cover side, 32 psi on the crank side (annulus). Published torque
    # on the crankshaft: 6110 lb ft, computed with the approximate lever arm r (sin t + sin 2t / 2n).
    bore, stroke, rod = 9.0, 24.0, 60.0
    force_lbf = math.pi / 4 * bore ** 2 * 160.0 - math.pi / 4 * (bore ** 2 - 2.0 ** 2) * 32.0
    p_eq_psi = force_lbf / (math.pi / 4 * bore ** 2)           # same net force as one pressure on the full piston
    gas, _ = crank_torque(40.0, 120.0, bore * IN_MM, stroke * IN_MM, rod * IN_MM, 0.0, p_eq_psi * PSI_BAR)
    torque_lbft = gas / LBFFT_NM
    assert torque_lbft == pytest.approx(6110.0, rel=2e-3)      # ours (exact lever arm): 6117.6 lb ft
    # the gap to the published value is the approximation's error: exact minus approximate lever arm, O(lambda^3)
    lam, t = 12.0 / 60.0, math.radians(40.0)
    approx_arm = 12.0 * (math.sin(t) + math.sin(2 * t) / (2 * 5.0))
    exact_arm = slider_crank(t, 12.0, 60.0)["ds_dtheta_mm"]
    assert torque_lbft - 6110.0 == pytest.approx(force_lbf * (exact_arm - approx_arm) / 12.0, abs=1.0)
    assert abs(exact_arm - approx_arm) < 12.0 * lam ** 3


def _normalised_inertia(lam, deg):
    k = slider_crank(np.radians(deg), 1.0, 1.0 / lam)
    kf = slider_crank(np.radians(np.arange(0.0, 720.0, 1.0)), 1.0, 1.0 / lam)
    return -k["ds_dtheta_mm"] * k["d2s_dtheta2_mm"] / np.max(np.abs(kf["ds_dtheta_mm"] * kf["d2s_dtheta2_mm"]))


def test_thesis_table_3_5_inertia_column_shape():
    # Thesis Table 3.5 (normalised per column; docs/source-study.md sec. 1: fits lambda ~0.295). Our exact constant-speed
    # inertia torque, normalised by its maximum over the cycle on a 1 deg grid, against the column.
    ti = np.array(T35["inertia_torque_normalised"])
    assert np.max(np.abs(_normalised_inertia(0.295, DEG) - ti)) < 0.015          # 0.0118 measured
    best = minimize_scalar(lambda lam: np.sum((_normalised_inertia(lam, DEG) - ti) ** 2), bounds=(0.1, 0.5),
                           method="bounded").x
    assert best == pytest.approx(0.295, abs=0.005)                                # 0.2970
    # the default engine's lambda 0.323 fits worse: the thesis engine's rod is relatively longer
    assert np.max(np.abs(_normalised_inertia(0.3229, DEG) - ti)) > 0.03


def test_thesis_table_3_5_gas_torque_is_pressure_times_exact_lever_arm():
    # Gas torque / pressure in the table must be proportional to the exact s'(theta) (T_g = p A s'): one constant
    # fits all 13 non-dead-centre rows to 0.3 % of the peak; the printed (garbled) Eq. 3.21 lever arm
    # [sin t + q sin t cos t]/(1 - q^2 sin^2 t) cannot (residual 0.059) -- docs/source-study.md sec. 2.
    p = np.array(T35["cylinder_pressure_normalised"])
    g = np.array(T35["gas_torque_normalised"])
    mask = DEG % 360.0 != 0.0
    t = np.radians(DEG[mask])
    lam = 0.295
    arm = slider_crank(t, 1.0, 1.0 / lam)["ds_dtheta_mm"]
    c = np.sum(g[mask] / p[mask] * arm) / np.sum(arm ** 2)
    assert np.max(np.abs(g[mask] - c * arm * p[mask])) < 0.004                  # 0.0032 measured
    garbled = (np.sin(t) + lam * np.sin(t) * np.cos(t)) / (1 - (lam * np.sin(t)) ** 2)
    c2 = np.sum(g[mask] / p[mask] * garbled) / np.sum(garbled ** 2)
    assert np.max(np.abs(g[mask] - c2 * garbled * p[mask])) > 0.05


@pytest.mark.parametrize("pressure, corr_min, max_diff", [("wiebe", 0.999, 0.03), ("table", 0.99, 0.13)])
def test_thesis_table_3_5_gas_column_shape_from_our_pressure(pressure, corr_min, max_diff):
    # Our single-cylinder gas torque at rated speed (firing TDC at 360 deg as in the table), normalised by its
    # maximum on a 1 deg grid, against the thesis column: the double-Wiebe trace peaks at 384 deg like the table
    # (corr 0.9997, max diff 0.018); the measured Mendes trace (another engine) is broader (corr 0.993, 0.118).
    ex = EngineExcitation.from_data(SYSTEM, speed_rpm=2500.0, pressure=pressure)
    g = np.array(T35["gas_torque_normalised"])

    def gas(deg):
        return crank_torque(deg - 360.0, 2500.0, ex.bore_mm, ex.stroke_mm, ex.rod_length_mm, 0.0,
                            ex.pressure.pressure_bar(deg))[0]
    fine = np.arange(0.0, 720.0, 1.0)
    ours = gas(DEG) / np.max(gas(fine))
    assert np.corrcoef(ours, g)[0, 1] > corr_min
    assert np.max(np.abs(ours - g)) < max_diff
    assert fine[np.argmax(gas(fine))] == pytest.approx(384.0, abs=3.0)
