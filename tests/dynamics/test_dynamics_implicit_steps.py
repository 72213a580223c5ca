"""Fixed-step BDF2 of independent blocks (gearopt.dynamics.implicit_steps): second order against the closed-form
solution of a stiff linear ODE, a stick-slip law with a key against SciPy's LSODA at a tight tolerance, blocks kept
apart, bad input named."""

import math

import casadi as ca
import numpy as np
import pytest
from scipy.integrate import solve_ivp

from gearopt.dynamics.implicit_steps import implicit_steps
from gearopt.errors import GearoptInputError


def run(blocks, forcing_symbols, p_symbols, table, p, h, start, tolerance=1e-12, iterations=8, substeps=None):
    fun, _ = implicit_steps("test_steps", blocks, forcing_symbols, p_symbols, table.shape[1], tolerance=tolerance,
                            newton_iterations=iterations)
    trajectory, residuals, redone = fun(start, table, p, h)
    if substeps is not None:
        substeps.append(np.array(redone).ravel())
    return np.array(trajectory), np.array(residuals).ravel()


def test_second_order_on_a_stiff_linear_ode():
    """u' = -lam (u - F(t)), F = b t, u(0) = 1: closed form u = b t - (b/lam)(1 - e^(-lam t)) + e^(-lam t). The
    largest error over the steps falls by about 4 per halving of h (BDF2) once lam h <= 1 (the backward-Euler
    start step's local error is of the same order)."""
    u, f, lam = ca.SX.sym("u"), ca.SX.sym("F"), ca.SX.sym("lam")
    b, lam_value, t_end = 2.0, 5.0, 1.0
    errors = []
    for n in (40, 80, 160, 320):
        h = t_end / n
        t = h * np.arange(1, n + 1)
        exact = b * t - (b / lam_value) * (1 - np.exp(-lam_value * t)) + np.exp(-lam_value * t)
        traj, res = run([(u, -lam * (u - f))], f, lam, (b * t)[None, :], [lam_value], h, [1.0, 1.0, 0.0, 0.0])
        errors.append(np.max(np.abs(traj[0] - exact)))
        assert res.max() <= 1e-12
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.0) & (ratios < 5.0)), ratios


def slip_rate(u, torque, capacity=1000.0, clearance=0.01, stiffness=1e5, speed=50.0, np_=np):
    """A keyed hub's slip rate (viscoplastic Coulomb against a key in a dead zone; a gearopt-independent copy of
    the law): demand D = T - k dz(u), rate = V max(|D|/C - 1, 0) sign(D)."""
    dz = np_.fmax(u - clearance, 0.0) - np_.fmax(-u - clearance, 0.0)
    d = torque - stiffness * dz
    mag = np_.sqrt(d ** 2 + 1e-12)
    return speed * np_.fmax(mag / capacity - 1.0, 0.0) * d / mag


def test_stick_slip_against_the_key_matches_lsoda():
    """A hub driven by a torque swinging through +-2.5 capacities: it sticks, slips across the key clearance, rides
    the key and slips back. Two copies (different capacities) in one call, each its own block. Against SciPy's
    LSODA (ODEPACK) at rtol 1e-9 on the same forcing (linear between the grid points): every step converged (none
    redone by substeps); the largest
    state error over the grid falls by at least 2 when the grid is halved (first order where a step crosses a kink
    of the law, second between) and is below 0.5 % of the slip range on the finer grid."""
    redone = []
    t_end, fine = 1.0, 2000
    t = (t_end / fine) * np.arange(fine + 1)
    torque = 2500.0 * np.sin(2 * math.pi * t) + 300.0 * np.sin(14 * math.pi * t)
    f = ca.SX.sym("T")
    caps = (1000.0, 1800.0)
    blocks = []
    for k, c in enumerate(caps):
        s = ca.SX.sym(f"u{k}")
        blocks.append((s, slip_rate(s, f, capacity=c, np_=ca)))
    runs = {}
    for every in (2, 1):                                    # the grid of 1000 steps, then of 2000
        traj, res = run(blocks, f, ca.SX.sym("unused"), torque[None, every::every], [0.0], every * t[1], [0.0] * 6,
                        tolerance=1e-13, substeps=redone)
        assert res.max() <= 1e-13 and redone[-1].sum() == 0
        runs[every] = traj
    ref = solve_ivp(lambda tt, y: [slip_rate(y[0], np.interp(tt, t, torque), capacity=caps[0])], (0.0, t_end),
                    [0.0], method="LSODA", t_eval=t[1:], rtol=1e-9, atol=1e-12)
    assert ref.success
    span = ref.y[0].max() - ref.y[0].min()
    assert span > 0.02                                              # it crosses the clearance both ways
    coarse = np.max(np.abs(runs[2][0] - ref.y[0][1::2]))
    finer = np.max(np.abs(runs[1][0] - ref.y[0]))
    assert finer < 0.55 * coarse and finer < 5e-3 * span, (coarse / span, finer / span)
    # two Newton iterations per step: the steps they do not resolve are redone by backward-Euler substeps (first
    # order there); every step still converges, within 1 % of the slip range
    redone = []
    few, res = run(blocks[:1], f, ca.SX.sym("unused"), torque[None, 1:], [0.0], t[1], [0.0] * 4, tolerance=1e-13,
                   iterations=2, substeps=redone)
    assert redone[0].sum() > 0 and res.max() <= 1e-13
    assert np.max(np.abs(few[0] - ref.y[0])) < 1e-2 * span
    alone, _ = run(blocks[1:], f, ca.SX.sym("unused"), torque[None, 1:], [0.0], t[1], [0.0] * 4, tolerance=1e-13)
    assert np.allclose(alone[0], runs[1][1], rtol=0.0, atol=1e-12)    # the other copy: as if integrated alone
    assert not np.allclose(runs[1][0], runs[1][1])


def test_bad_input_is_named():
    u, f = ca.SX.sym("u"), ca.SX.sym("F")
    with pytest.raises(GearoptInputError, match="steps"):
        implicit_steps("x", [(u, -u + f)], f, ca.SX.sym("p"), 0, tolerance=1e-9)
    with pytest.raises(GearoptInputError, match="tolerance"):
        implicit_steps("x", [(u, -u + f)], f, ca.SX.sym("p"), 10, tolerance=0.0)
    with pytest.raises(GearoptInputError, match="blocks"):
        implicit_steps("x", [], f, ca.SX.sym("p"), 10, tolerance=1e-9)
