"""Semi-infinite refinement of a scene's PPTE: solve on a coarse set of mesh positions, let the exact model find the
worst positions, add them, re-solve warm -- until the smooth and the exact PPTE agree.

The PPTE of a design is ``max_s TE(s) - min_s TE(s)`` over the continuum of mesh positions ``s`` in one base pitch:
an objective or limit over infinitely many positions (a semi-infinite program). The NLP samples a finite set; a
minimiser then tends to put the TE's extremes *between* the samples, so its PPTE claims too little (on a user pair,
40 positions claimed 3.60 um where the exact LTCA of the same design gives 4.41 um). The exchange method (Hettich &
Kortanek, "Semi-infinite programming: theory, methods, and applications", SIAM Review 35 (1993), sec. 7) fixes it
without a dense grid everywhere:

1. solve the NLP on the present position sets;
2. re-evaluate the optimum by the exact LTCA at its converged resolution (``check_positions``) for every mesh and
   load case, and compare the PPTE of the smooth model at the NLP's positions with the exact PPTE;
3. if any relative difference exceeds ``refine_tolerance``, split it: the smooth model's PPTE on the exact check's
   own dense grid at the same design measures the error of the *smoothing* (dense smooth vs exact), the rest is the
   error of the *sampling* (NLP vs dense smooth). Sampling error above half the tolerance: add the exact TE's peaks
   and troughs of every load case (:func:`extreme_fractions`) to the mesh's set.
   Smoothing error above half the tolerance: halve the contact smoothing width (not below ``min_smoothing_um``;
   the softplus contact law lowers the TE by up to ``w ln 2`` where gaps just close, which matters against a
   sub-micron optimum). Re-solve from the previous optimum (a primal warm start: the new NLP has more constraints,
   so its multipliers do not carry over);
4. stop when all agree, after ``max_refinements`` re-solves, or when neither remedy applies (reported).

Every solve is a row of ``SceneResult.refinement``.
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

REUSED_MODELS = ("data:", "dynamics:", "simulation:")
"""Models a re-solve takes over from the previous build (they do not depend on the positions)."""


def extreme_fractions(te: np.ndarray, fractions: np.ndarray, per_side: int = 3, band: float = 0.25,
                      neighbours: int = 6) -> tuple:
    """Mesh positions of the TE's peaks and troughs: the global maximum and minimum first, then further local
    maxima (minima) in the top (bottom) ``band`` of the range, most extreme first, up to ``per_side`` each, each with
    ``neighbours`` grid points on either side (an extreme moves a little when the design does; its neighbours keep
    the NLP from sliding it between two samples). The TE is periodic over the base pitch."""
    te = np.asarray(te, dtype=float)
    lo, hi = te.min(), te.max()
    span = max(hi - lo, 1e-12)
    prev, nxt = np.roll(te, 1), np.roll(te, -1)
    peaks = [i for i in np.argsort(-te) if te[i] >= prev[i] and te[i] >= nxt[i] and te[i] >= hi - band * span]
    troughs = [i for i in np.argsort(te) if te[i] <= prev[i] and te[i] <= nxt[i] and te[i] <= lo + band * span]
    idx = [int(np.argmax(te)), int(np.argmin(te))] + peaks[:per_side] + troughs[:per_side]
    out = []
    for i in idx:
        for j in range(i - neighbours, i + neighbours + 1):
            f = float(fractions[j % te.size])
            if f not in out:
                out.append(f)
    return tuple(out)


def new_fractions(existing: np.ndarray, candidates, tol: float = 1e-9) -> list[float]:
    out = []
    for f in candidates:
        d = np.abs(np.asarray(existing) - f)
        if np.min(np.minimum(d, 1.0 - d)) > tol and all(abs(f - o) > tol for o in out):
            out.append(float(f))
    return out


def solve_refined(built, *, starts: int = 1, seed: int = 0, verbose: bool = False, **ipopt):
    """Solve ``built`` (a :class:`~gearopt.design.scene.BuiltScene`) with the exchange method (module docstring);
    returns the last :class:`~gearopt.design.scene.SceneResult` with ``refinement`` filled in."""
    from .scene import BuiltScene

    tol = float(built._opts["refine_tolerance"])
    max_refinements = int(built._opts["max_refinements"])
    rows, current, status = [], built, "max_refinements reached"
    t_start = time.perf_counter()
    for it in range(max_refinements + 1):
        t0 = time.perf_counter()
        result = current.solve_once(starts=starts if it == 0 else 1, seed=seed, verbose=verbose, check=True, **ipopt)
        ex = result.exact_check
        err = float(ex["ppte_um_error"].max()) if len(ex) else 0.0
        worst = ex.loc[ex["ppte_um_error"].idxmax()] if len(ex) else None
        exact = ex["ppte_um"].abs().clip(lower=1e-12) if len(ex) else None
        smoothing_err = float(((ex["smooth_dense_ppte_um"] - ex["ppte_um"]).abs() / exact).max()) if len(ex) else 0.0
        sampling_err = (ex["smooth_dense_ppte_um"] - ex["smooth_ppte_um"]).abs() / exact if len(ex) else None
        rows.append({"iteration": it, "positions": int(sum(len(p) for p in result.positions.values())),
                     "smoothing_um": float(current._opts["smoothing_um"]),
                     "objective": float(result.solve.objective), "max_ppte_error": err,
                     "smoothing_error": smoothing_err,
                     "sampling_error": float(sampling_err.max()) if sampling_err is not None else 0.0,
                     "worst_mesh": "" if worst is None else str(worst["mesh"]),
                     "worst_load_case": "" if worst is None else str(worst["load_case"]),
                     "ipopt_iterations": int(result.solve.iterations),
                     "solve_time_s": float(result.solve.solve_time_s or 0.0),
                     "wall_time_s": time.perf_counter() - t0})
        if err <= tol:
            status = "converged"
            break
        if it == max_refinements:
            break
        sets, added = {}, 0
        for mesh, fractions in result.positions.items():
            rows_m = ex["mesh"] == mesh
            candidates = [f for fr in ex.loc[rows_m, "worst_fractions"] for f in fr] \
                if (sampling_err[rows_m] > 0.5 * tol).any() or (ex.loc[rows_m, "ppte_um_error"] > tol).any() else []
            new = new_fractions(fractions, candidates)
            added += len(new)
            sets[mesh] = np.sort(np.concatenate([fractions, new]))
        options = {}
        w = float(current._opts["smoothing_um"])
        w_min = float(current._opts["min_smoothing_um"])
        if smoothing_err > 0.5 * tol and w > w_min:
            options["smoothing_um"] = max(0.5 * w, w_min)
        if not added and not options:
            status = "stalled: the exact worst positions are in the NLP's sets and the smoothing is at its floor"
            break
        reuse = {k: v for k, v in current.models.items() if k.startswith(REUSED_MODELS)}
        current = BuiltScene(current.scene, positions=sets, initial=result.values, reuse=reuse,
                             options={**current._options_override, **options})
    table = pd.DataFrame(rows)
    table.attrs.update(status=status, tolerance=tol, total_time_s=time.perf_counter() - t_start)
    result.refinement = table
    return result


__all__ = ["solve_refined", "extreme_fractions", "new_fractions", "REUSED_MODELS"]
