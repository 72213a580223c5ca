"""Sensitivities of a periodic response to network parameters through the CasADi integrator (forward sensitivities),
with a finite-difference check.

The response is a statistic of one output over the last of ``cycles`` integrated cycles -- the peak of its samples,
their RMS or their mean -- e.g. the peak or RMS force of one mesh. The initial state is the end of a numeric
run-in (``run_in_cycles``, not differentiated), then ``cycles`` cycles are integrated inside a CasADi graph whose
Jacobian with respect to the chosen parameters CasADi evaluates with CVODES forward sensitivities (one direction per
parameter); the dependence of the run-in state on the parameters decays over the differentiated cycles (at the
default trains' damping, transients fall by about e^-5 per cycle at rated speed), so ``cycles >= 2`` approximates the
periodic steady state's sensitivity.

``peak``: the derivative of the largest *sample* is that sample's derivative (valid where the maximising sample
does not switch; the finite-difference check shows it). With lash, a rattling (non-periodic, chaotic) response has
no meaningful derivative: the finite-difference check then disagrees, and the result says so (``fd_relative_error``).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pandas as pd

from ..errors import GearoptInputError
from .network import OFFSET_PARAMETER

STATISTICS = ("peak", "rms", "mean")


def _statistics(samples: np.ndarray) -> dict:
    return {"peak": float(np.max(samples)), "rms": float(np.sqrt(np.mean(samples ** 2))),
            "mean": float(np.mean(samples))}


def response_sensitivities(simulator, speed_rpm: float, parameters, output: tuple[str, str] | None = None,
                           cycles: int = 2, run_in_cycles: int = 3, overrides: dict | None = None,
                           fd_check: bool = True, fd_relative_step: float = 1e-4) -> pd.DataFrame:
    """Derivatives of the peak, RMS and mean of ``output`` over the last cycle with respect to ``parameters``.

    ``simulator``: a :class:`~gearopt.dynamics.simulate.Simulator` (its integrator is reused); ``speed_rpm`` [rpm];
    ``parameters``: names from :meth:`TorsionalNetwork.parameters` (e.g. ``"pinion-wheel.stiffness_N_per_m"``,
    ``"pinion-wheel.damping_N_s_per_m"``, ``"pinion-wheel.backlash_mm"``, ``"damper.damping_Nms_per_rad"``);
    ``output``: (quantity, element) of the simulator's outputs (default: the force of the network's first mesh);
    ``overrides``: other parameter values.

    Returns one row per parameter: ``parameter``, ``value``, ``peak``/``rms``/``mean`` (the response, in the
    output's unit), ``d_peak``/``d_rms``/``d_mean`` (per unit of the parameter), and with ``fd_check`` the central
    differences ``fd_d_*`` (step ``fd_relative_step`` x value) and ``fd_relative_error`` (larger relative gap of the
    peak and RMS derivatives, relative to the larger magnitude, with an absolute floor of 1e-9 x response/value; the
    mean's derivative is nearly zero in a periodic state -- the mean mesh force is fixed by the torque balance --
    so its relative gap is not meaningful and it is left out).
    """
    names = simulator.eq.parameter_names
    params = list(parameters)
    unknown = [p for p in params if p not in names]
    if unknown:
        raise GearoptInputError(f"unknown parameters {unknown}; known: {names}")
    if output is None:
        meshes = [o for o in simulator.eq.output_names if o[0] == "mesh_force_N"]
        if not meshes:
            raise GearoptInputError("output=None: the simulator has no mesh force; give output=(quantity, element)")
        output = meshes[0]
    quantity, element = output
    try:
        idx = simulator.eq.output_names.index((quantity, element))
    except ValueError:
        raise GearoptInputError(f"output {output!r} not among the simulator's outputs") from None
    base = simulator.parameter_vector(speed_rpm, overrides)
    x0 = simulator.run(speed_rpm, 1, parameters=overrides, run_in_cycles=max(0, run_in_cycles - 1)).final_state \
        if run_in_cycles > 0 else simulator.static_state(speed_rpm, overrides)
    i_off = names.index(OFFSET_PARAMETER)
    offset0 = run_in_cycles * simulator.cycle_rad
    cols = [names.index(p) for p in params]
    out_fun = ca.Function("response", [simulator.eq.tau, simulator.eq.x, simulator.eq.p],
                          [simulator.eq.outputs[idx]], {"cse": True}).map(simulator.n_out)

    sym = ca.MX.sym("theta", len(params))
    pieces = [ca.MX(float(v)) for v in base]
    for j, c in enumerate(cols):
        pieces[c] = sym[j]
    x = ca.MX(x0)
    samples = None
    for k in range(cycles):
        pk = list(pieces)
        pk[i_off] = ca.MX(offset0 + k * simulator.cycle_rad)
        pvec = ca.vertcat(*pk)
        xs = simulator.integrator(x0=x, p=pvec)["xf"]
        x = xs[:, -1]
        if k == cycles - 1:
            samples = out_fun(ca.DM(simulator.grid_rad).T, xs, ca.repmat(pvec, 1, simulator.n_out))
    fun = ca.Function("sens", [sym], [samples.T, ca.jacobian(samples.T, sym)])
    value_fun = ca.Function("response_samples", [sym], [samples.T])
    theta = base[cols]
    f_val, jac = (np.array(v) for v in fun(theta))
    f_val = f_val.ravel()
    stats = _statistics(f_val)
    k_peak = int(np.argmax(f_val))
    rms = stats["rms"]
    d = {"peak": jac[k_peak], "rms": (f_val @ jac) / (f_val.size * rms) if rms > 0 else np.zeros(len(params)),
         "mean": jac.mean(axis=0)}
    rows = []
    for j, name in enumerate(params):
        row = {"parameter": name, "value": float(theta[j]), **stats,
               **{f"d_{s}": float(d[s][j]) for s in STATISTICS}}
        if fd_check:
            h = fd_relative_step * (abs(theta[j]) if theta[j] != 0 else 1.0)
            vals = []
            for sign in (1.0, -1.0):
                t = theta.copy()
                t[j] += sign * h
                vals.append(_statistics(np.array(value_fun(t)).ravel()))
            worst = 0.0
            for s in STATISTICS:
                fd = (vals[0][s] - vals[1][s]) / (2 * h)
                row[f"fd_d_{s}"] = fd
                if s != "mean":
                    floor = 1e-9 * max(abs(stats[s]), 1.0) / max(abs(theta[j]), 1e-300)
                    worst = max(worst, abs(fd - row[f"d_{s}"]) / max(abs(fd), abs(row[f"d_{s}"]), floor))
            row["fd_relative_error"] = worst
        rows.append(row)
    return pd.DataFrame(rows)


__all__ = ["response_sensitivities", "STATISTICS"]
