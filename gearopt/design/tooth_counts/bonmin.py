"""Cross-check of the enumeration with a relaxed mixed-integer model solved by CasADi's Bonmin. Part of
:mod:`gearopt.design.tooth_counts`."""

from __future__ import annotations

import math
import os
import sys
import time
from contextlib import contextmanager
from typing import Any, Mapping

import casadi as ca
import numpy as np
import pandas as pd

from ... import numerics as nm
from ...errors import GearoptInputError
from ...geometry import involute as inv
from ...geometry.shift import sum_of_profile_shifts
from .candidates import _NO_LIMIT, _RATIO_EPS_PERCENT, _rack_angles, _tree_order
from .enumeration import ToothCountEnumeration


# ----------------------------------------------------------------------------------------------------------------
# Bonmin cross-check on a relaxed mixed-integer model
# ----------------------------------------------------------------------------------------------------------------

def _iso_limits_relaxed(z, iso: bool):
    """ISO/TR 4467 recommended shift range (thesis Eqs. 3.8-3.12) as continuous piecewise-linear functions of a
    relaxed tooth count (continuous at z = 20 and 50); +-_NO_LIMIT where the standard gives no value."""
    if not iso:
        return -_NO_LIMIT, _NO_LIMIT
    lower = nm.where(z <= 12, -_NO_LIMIT, nm.where(z <= 20, 0.0375 * (20 - z),
                                                   nm.where(z <= 50, (20 - z) / 60.0, -0.5)))
    upper = nm.where(z <= 10, _NO_LIMIT, nm.where(z <= 50, 0.5 + 0.01 * z, 1.0))
    return lower, upper


@contextmanager
def _quiet_native_stdout(quiet: bool):
    """Silence the C-level stdout while Bonmin runs (its per-node NLP lines ignore the log-level options)."""
    if not quiet:
        yield
        return
    sys.stdout.flush()
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # no real file descriptor (e.g. captured): nothing to silence
        yield
        return
    saved = os.dup(fd)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), fd)
            yield
    finally:
        os.dup2(saved, fd)
        os.close(saved)


def bonmin_cross_check(enumeration: ToothCountEnumeration, *, options: Mapping[str, Any] | None = None,
                       verbose: bool = False) -> dict:
    """Cross-check the enumeration with CasADi's Bonmin on a relaxed mixed-integer model.

    Variables: the teeth of every gear (integer, within the enumeration's ranges), the root gear's shift x_root and
    an epigraph variable t. Constraints: every mesh's and every toleranced gear's speed-ratio error within its
    tolerance (linear in the teeth: ``z1 - (1 +- tol) q z2``), the centre distance reachable
    (``cos 45 deg <= a_d(z) cos(alpha_t)/a < 1``), the sums of shifts x1 + x2 (ISO 21771 eqs. 44/46 with the tooth
    sum relaxed to a real number), the shifts propagated from x_root through the tree, and
    ``t <= x_g - x_lower(z_g)``, ``t <= x_upper(z_g) - x_g`` for every gear (undercut limit and ISO/TR 4467 limits
    as functions of the relaxed z, :func:`_iso_limits_relaxed`). Objective: maximise t, i.e. the widest margin to the
    per-gear shift limits. The enumeration's counterpart is each candidate's ``shift_margin`` (half the width of its
    root-shift interval, exact for the linear limits), over every candidate that passed the ``shift_limits`` stage
    (admissible or rejected only by the sampled precheck). The contact-ratio and tip-thickness limits are not in
    the relaxed model.

    Bonmin's default B-BB algorithm is exact for convex relaxations only; this model is nonconvex (the involute
    relation), so agreement is evidence, not proof. Returns a dict: ``status``, ``teeth``, ``shift_margin``,
    ``root_profile_shift``, ``enumeration_teeth`` (best by shift margin, ties: all listed),
    ``enumeration_shift_margin``,
    ``agrees`` (Bonmin's teeth among the enumeration's best and margins equal within 1e-6), ``solve_time_s``.
    ``options``: extra Bonmin options (``bonmin.`` names without the prefix); ``verbose``: keep Bonmin's log.
    Raises ``GearoptInputError`` if this CasADi has no Bonmin.
    """
    if not ca.has_nlpsol("bonmin"):
        raise GearoptInputError("bonmin_cross_check: this CasADi build has no Bonmin plugin "
                                "(casadi.has_nlpsol('bonmin') is False)")
    train = enumeration.train
    gears = list(train.gears)
    iso = bool(enumeration.limits["iso_tr_4467_limits"])
    alpha_n, beta, alpha_t, h_ff = _rack_angles(train)
    m_t = float(inv.transverse_module(float(train.rack.module_mm), beta))
    z = nm.symbol("teeth", len(gears))
    x_root = nm.symbol("root_profile_shift")
    t = nm.symbol("shift_margin")
    zg = {g: z[i] for i, g in enumerate(gears)}
    ref = enumeration.reference_ratios
    g_exprs, g_lo, g_hi = [], [], []

    def con(expr, lo, hi):
        g_exprs.append(expr)
        g_lo.append(lo)
        g_hi.append(hi)

    for name, mesh in train.meshes.items():
        g1, g2 = mesh.gears
        q = ref[g2] / ref[g1]
        tol = enumeration.mesh_tolerance_percent[name] / 100.0 + _RATIO_EPS_PERCENT / 100.0
        con(zg[g1] - (1.0 + tol) * q * zg[g2], -math.inf, 0.0)
        con(zg[g1] - (1.0 - tol) * q * zg[g2], 0.0, math.inf)
    root = train.root_gear
    for g, tol_pc in enumeration.gear_tolerance_percent.items():
        tol = tol_pc / 100.0 + _RATIO_EPS_PERCENT / 100.0
        con(zg[root] - (1.0 + tol) * ref[g] * zg[g], -math.inf, 0.0)
        con(zg[root] - (1.0 - tol) * ref[g] * zg[g], 0.0, math.inf)
    x = {root: x_root}
    for gear, mesh_name, parent in _tree_order(train)[1:]:
        g1, g2 = train.meshes[mesh_name].gears
        a = float(train.meshes[mesh_name].centre_distance_mm)
        c = 0.5 * (zg[g1] + zg[g2]) * m_t * math.cos(alpha_t) / a
        con(c, math.cos(math.radians(45.0)), 1.0 - 1e-9)
        alpha_wt = nm.acos_safe(c, 1e-12)
        x[gear] = sum_of_profile_shifts(zg[g1] + zg[g2], alpha_wt, alpha_t, alpha_n) - x[parent]
    for g in gears:
        x_u = inv.undercut_limit_profile_shift(zg[g], alpha_t, beta, h_ff)
        lo_iso, hi_iso = _iso_limits_relaxed(zg[g], iso)
        con(x[g] - x_u - t, 0.0, math.inf)
        con(x[g] - lo_iso - t, 0.0, math.inf)
        con(hi_iso - x[g] - t, 0.0, math.inf)
    con(3.0 - x_root - t, 0.0, math.inf)
    con(x_root + 3.0 - t, 0.0, math.inf)
    w = nm.vertcat(z, x_root, t)
    nlp = {"x": w, "f": -t, "g": nm.vertcat(*g_exprs)}
    opts = {"discrete": [True] * len(gears) + [False, False], "print_time": False,
            "bonmin": {"print_level": 0, "bb_log_level": 0, "nlp_log_level": 0, "algorithm": "B-BB"}}
    opts["bonmin"].update(dict(options or {}))
    solver = ca.nlpsol("tooth_count_bonmin", "bonmin", nlp, opts)
    lbx = [enumeration.teeth_ranges[g][0] for g in gears] + [-3.0, -_NO_LIMIT]
    ubx = [enumeration.teeth_ranges[g][1] for g in gears] + [3.0, _NO_LIMIT]
    x0 = [min(max(train.gears[g].teeth, lbx[i]), ubx[i]) for i, g in enumerate(gears)]
    x0 += [float(train.profile_shifts[root]) if nm.is_numeric(train.profile_shifts[root]) else 0.0, 0.0]
    t0 = time.perf_counter()
    with _quiet_native_stdout(not verbose):
        sol = solver(x0=x0, lbx=lbx, ubx=ubx, lbg=g_lo, ubg=g_hi)
    elapsed = time.perf_counter() - t0
    stats = solver.stats()
    wv = np.asarray(sol["x"]).reshape(-1)
    teeth = {g: int(round(wv[i])) for i, g in enumerate(gears)}
    # the enumeration's candidates that passed the shift-limits stage
    cols = [f"teeth_{g}" for g in gears] + ["shift_margin"]
    pool = [enumeration.admissible[cols]] if not enumeration.admissible.empty else []
    pre = enumeration.rejected[enumeration.rejected["stage"] == "precheck"]
    if not pre.empty:
        pool.append(pre[cols])
    both = pd.concat(pool, ignore_index=True) if pool else pd.DataFrame(columns=cols)
    if both.empty:
        best_teeth, best_margin = [], float("nan")
    else:
        best_margin = float(both["shift_margin"].max())
        tops = both[both["shift_margin"] >= best_margin - 1e-9]
        best_teeth = [{g: int(r[f"teeth_{g}"]) for g in gears} for _, r in tops.iterrows()]
    margin = float(wv[-1])
    success = bool(stats.get("success", False))
    return {"status": str(stats.get("return_status", "")), "success": success, "teeth": teeth,
            "shift_margin": margin, "root_profile_shift": float(wv[len(gears)]),
            "enumeration_teeth": best_teeth, "enumeration_shift_margin": best_margin,
            "agrees": success and teeth in best_teeth and abs(margin - best_margin) <= 1e-6,
            "solve_time_s": elapsed}
