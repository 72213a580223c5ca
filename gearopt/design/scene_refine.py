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
3. if any difference exceeds ``refine_tolerance`` (relative) and ``refine_abs_tolerance_um`` (absolute, a floor for
   near-zero PPTE: :func:`ppte_disagreement`), split it: the smooth model's PPTE on the exact check's
   own dense grid at the same design measures the error of the *discretisation* (dense smooth vs exact: the contact
   smoothing and, for a helical mesh, the face slicing), the rest is the error of the *sampling* (NLP vs dense
   smooth). Sampling error above half the tolerance: add the exact TE's peaks and troughs of every load case
   (:func:`~gearopt.design.positions.extreme_fractions`) to the mesh's set. Discretisation error above half the
   tolerance on a helical mesh:
   raise the smooth model's face slices (``helical_slices`` to ``2 n - 1``, so the old slice centres stay, up to
   ``max_helical_slices``; the exact check slices the face :func:`gearopt.contact.layout.default_slices` times, at
   least 11 and more as the overlap ratio grows). On a spur mesh (or with the slices at their cap): halve the contact smoothing
   width (not below ``min_smoothing_um``; the softplus contact law lowers the TE by up to ``w ln 2`` where gaps just
   close, which matters against a sub-micron optimum). Re-solve from the previous optimum (a primal warm start:
   the new NLP has more constraints, so its multipliers do not carry over). The maximum contact stress, root
   stress and contact temperature are maxima over the same continuum: where one differs from the exact value by
   more than ``refine_stress_tolerance`` (1 %), the exact model's peak positions of each (``stress_fractions`` of the exact check)
   join the set; if the NLP already samples them (a helical mesh), the face slices are raised instead. A lower
   limit the exact LTCA breaks by more than ``refine_stress_tolerance`` (the loaded contact ratio:
   :func:`exact_lower_limit_shortfalls`), or an upper limit on the PPTE over the relief tolerances
   (:data:`BACKED_OFF_UPPER_LIMITS`), is tightened by 1.25 times the shortfall for the re-solve, and a solve that
   breaks one is not admissible;
4. stop when all agree (PPTE and stresses; for a minimax PPTE objective -- the largest PPTE of several meshes or
   load cases -- the smooth and the exact objective agree, :func:`ppte_agrees`), after ``max_refinements`` re-solves, when no remedy applies, or when a re-solve fails or
   overruns its iteration budget (:data:`RESOLVE_BUDGET_FACTOR` times the longest solve so far; reported); with ``stop_without_progress`` (off
   by default) also as soon as a re-solve neither lowers the best exact objective so far by more than
   ``refine_tolerance`` nor gives the first admissible design (faster; a design that a later re-solve would have
   repaired and lowered is then missed); with ``stop_on_divergence`` (on by default) as soon as a re-solve lowers
   neither the best exact objective nor the largest smooth-vs-exact PPTE error below the smallest before it and
   breaks no exact limit that a backed-off re-solve would repair (a loop moving away from both the design and the
   agreement: it would not converge);
5. return the *best verified* design. Every solve is re-evaluated by the exact LTCA, so each has an exact objective
   (its PPTE terms from the exact model); a solve is admissible when it meets every limit and its exact stresses,
   temperatures and (where PPTE is limited) PPTE agree with the smooth ones within the tolerance. The result is the
   admissible solve with the lowest exact objective -- not necessarily the last: the re-solves change the positions,
   slices and smoothing, so a later local optimum is not always better on the exact model. Between designs whose
   exact objectives lie within the tolerance of the best, one whose smooth PPTE agreed with the exact one is
   preferred (its NLP quantities can then be read at face value). For a warm-started scene
   (e.g. from the sequential answer) the start competes too when it is admissible, so the result is never worse
   than it. Likewise the exact screen's best design competes when it meets every exact limit (the exact model has
   the last word: an NLP optimum reached from it that is worse on the exact model does not replace it; chosen
   ``"exact screen's best design ..."``). ``refinement.attrs["chosen"]`` says which design was returned,
   ``attrs["verified_objective"]`` its exact objective and ``attrs["verified"]`` whether its smooth PPTE agreed
   with the exact one within the tolerance;
6. where the scene is in the exact search's scope (:func:`~gearopt.design.scene_search.search_scope`), polish that
   design on the exact model (:func:`~gearopt.design.scene_search.exact_polish`; ``attrs["polish"]``): the first
   solve's starts came from the exact screen, and the polish takes the smooth model's last offset out of the
   optimum. ``attrs["verified"]`` then says whether the smooth model agrees with the exact one at the polished
   design (its ``quantities`` are the smooth model's there; its ``exact_check`` holds the exact values).

Every solve is a row of ``SceneResult.refinement`` (positions, slices, smoothing, smooth objective, exact
objective, errors, admissibility, times).
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
import pandas as pd

from ..errors import GearoptInputError, SolveError
from .positions import extreme_fractions, new_fractions, peak_fractions
from .scene_search import exact_geometry_violations, exact_limit_violation, exact_polish, rank_key, search_scope
from .scene_terms import quantity_kind

RESOLVE_BUDGET_FACTOR, RESOLVE_BUDGET_MIN_ITERATIONS = 4, 50
"""Iteration budget of a re-solve: this many times the Ipopt iterations of the longest solve of the refinement so
far, at least the minimum. A warm re-solve on more positions (and, for a helical mesh, more face slices) normally
needs no more iterations than the solves before it; one that runs much longer is usually in Ipopt's restoration
phase heading for "infeasible" (seen on the timing train's co-design: a low-helix re-solve ran 278 iterations to an
infeasible stop, 182 CPU-s, after a first solve of 56), and the refinement keeps its best admissible design instead.
The re-solves of one refinement may grow steadily as positions are added and the smoothing halves: on the co-design
scene of ``benchmarks/bench_codesign.py`` (root shift and two reliefs, 40 positions to start) they took 40, 138,
193, 252, 101 and 38 iterations after a first solve of 35 -- a budget of 4 times the *first* solve stopped the third
and kept a design 3.4 % worse on the exact LTCA (0.4171 against 0.4032 um at 1280 positions). Counted in iterations,
not seconds (issue 28): the result does not depend on how busy the machine is."""


def resolve_budget(iterations, max_iter=None) -> int:
    """Ipopt's ``max_iter`` for the next re-solve of a refinement whose solves so far took ``iterations``:
    :data:`RESOLVE_BUDGET_FACTOR` times the longest, at least :data:`RESOLVE_BUDGET_MIN_ITERATIONS`, and no more
    than the caller's ``max_iter`` where given."""
    iterations = [int(i) for i in iterations]
    if not iterations or min(iterations) < 0:
        raise GearoptInputError(f"resolve_budget: iterations={iterations!r} must name the solves so far (counts >= 0)")
    budget = max(RESOLVE_BUDGET_MIN_ITERATIONS, RESOLVE_BUDGET_FACTOR * max(iterations))
    return int(min(int(max_iter), budget)) if max_iter is not None else int(budget)


REUSED_MODELS = ("data:", "dynamics:", "simulation:")
"""Models a re-solve takes over from the previous build (they do not depend on the positions)."""


def ppte_disagreement(ex: pd.DataFrame, smooth_column: str, tol: float, abs_tol_um: float) -> pd.Series:
    """Per exact-check row, how far the smooth PPTE (``smooth_column``) is from the exact one, in units of the
    allowed difference: the relative tolerance ``tol`` or the absolute ``abs_tol_um``, whichever allows more
    (<= 1 agrees). The absolute floor keeps a near-zero PPTE (a well-relieved helical mesh: hundredths of a micron)
    from demanding agreement finer than any TE measurement resolves."""
    diff = (ex[smooth_column] - ex["ppte_um"]).abs()
    allowed = np.maximum(tol * ex["ppte_um"].abs(), abs_tol_um)
    return diff / allowed


def _admissible(built, quantities, exact, tol: float) -> bool:
    """Every limit met (smooth quantities, as the NLP states them) and the exact model agreeing with the smooth one
    on every limited or rated LTCA quantity other than an unlimited PPTE (whose exact value is used): a PPTE limit
    within ``tol``, stresses and temperatures within ``refine_stress_tolerance``."""
    lim = quantities[quantities["role"] == "limit"]
    bounds = np.maximum(1.0, np.abs(np.nan_to_num(lim["upper"].astype(float).fillna(lim["lower"].astype(float)))))
    if not bool((lim["margin"].astype(float) >= -1e-6 * bounds).all()):
        return False
    if not len(exact):
        return True
    if exact_limit_shortfalls(built, exact, built.options.refinement.refine_stress_tolerance):
        return False
    if (lim["quantity"] == "ppte_um").any() and float(ppte_disagreement(
            exact, "smooth_ppte_um", tol, built.options.refinement.refine_abs_tolerance_um).max()) > 1.0:
        return False
    return bool((_stress_errors(exact) <= built.options.refinement.refine_stress_tolerance).all())


def _minimax_ppte(built) -> bool:
    """Whether every PPTE term of the objective enters it through a maximum (each PPTE objective aggregated by
    ``"max"`` over its load cases, and one objective or ``objective_aggregate="max"``) and no limit is on PPTE."""
    objectives = built.scene.objectives
    ppte = [o for o in objectives if o.quantity == "ppte_um"]
    return bool(ppte) and all(o.aggregate == "max" for o in ppte) \
        and (len(objectives) == 1 or built.scene.objective_aggregate == "max") \
        and not any(lim.quantity == "ppte_um" for lim in built.scene.limits)


def ppte_agrees(built, quantities, ex: pd.DataFrame, tol: float, abs_tol_um: float) -> bool:
    """Whether the NLP's PPTE is confirmed by the exact LTCA: every mesh and load case within the tolerance
    (:func:`ppte_disagreement`), or, for a minimax objective (:func:`_minimax_ppte`), the objective itself -- the
    largest PPTE, the number the design is judged by -- from the smooth values within ``tol`` of the same objective
    from the exact ones. A mesh below the largest may then differ more (its exact value is in the exact check; were
    it the largest, the two objectives would differ)."""
    if not len(ex) or float(ppte_disagreement(ex, "smooth_ppte_um", tol, abs_tol_um).max()) <= 1.0:
        return True
    if not _minimax_ppte(built):
        return False
    exact = _verified_objective(built, quantities, ex)
    smooth = _verified_objective(built, quantities, ex, column="smooth_ppte_um")
    return abs(smooth - exact) <= tol * abs(exact)


def _verified_objective(built, quantities, exact, column: str = "ppte_um") -> float:
    """The scene's objective with every PPTE term taken from the exact LTCA (``column`` of the exact check: the
    smooth model's at the NLP's positions with ``"smooth_ppte_um"``), summed, or their largest for
    ``objective_aggregate="max"``."""
    terms = []
    for obj in built.scene.objectives:
        q = quantities[(quantities["role"] == "objective") & (quantities["quantity"] == obj.quantity)
                       & (quantities["target"] == obj.target)]
        vals = q["value"].to_numpy()
        if obj.quantity == "ppte_um" and len(exact):
            rows = exact[(exact["mesh"] == obj.target) & exact["load_case"].isin(q["load_case"])]
            vals = rows[column].to_numpy()
        agg = float(vals.mean() if obj.aggregate == "mean" else vals.max())
        terms.append(obj.weight / (obj.scale or quantity_kind(obj.quantity).scale) * (agg if obj.sense == "min"
                                                                                     else -agg))
    return max(terms) if built.scene.objective_aggregate == "max" else sum(terms)




def exact_best_start(built, ms):
    """The multistart candidate the exact model prefers (issue 28: the exact model has the last word): each
    successful start's optimum checked by the exact LTCA; the best one meeting every exact limit (within
    :data:`~gearopt.design.scene_search.EXACT_RANK_TOLERANCE`), else the least violating, by the exact objective
    (:func:`_verified_objective`). Returns ``(result, table)`` with the table's ``exact_objective``,
    ``exact_violation`` and ``chosen`` columns."""
    table = ms.table.copy()
    table["exact_objective"] = np.nan
    table["exact_violation"] = np.nan
    best, best_key = None, None
    for i, solved in enumerate(ms.results):
        if solved is None:
            continue
        values = built.values_of(solved)
        exact = built.exact_check(values)
        objective = _verified_objective(built, built.transcription.quantity_table(solved), exact)
        violation = exact_limit_violation(built, exact)
        table.loc[table.index[i], ["exact_objective", "exact_violation"]] = [objective, violation]
        key = rank_key(objective, violation)
        if best_key is None or key < best_key:
            best, best_key = i, key
    table["chosen"] = [i == best for i in range(len(table))]
    return (ms.results[best] if best is not None else ms.best), table


def exact_lower_limit_shortfalls(built, exact: pd.DataFrame, tolerance: float) -> dict[str, float]:
    """Lower limits on an LTCA quantity of the exact check (the loaded contact ratio) that the exact LTCA breaks by
    more than ``tolerance`` (relative; the refinement uses ``refine_stress_tolerance``, the agreement it asks of
    stresses): limit label -> shortfall in the quantity's unit. The smooth model's loaded contact ratio counts a pair
    whose gap has just closed as partly loaded, so an optimum can sit on the limit while the exact count lies
    below it."""
    return _exact_breaks(built, exact, tolerance, lambda lim: lim.lower is not None, "lower")


BACKED_OFF_UPPER_LIMITS = ("ppte_um_toleranced",)
"""Upper limits on exact-check quantities the NLP carries in a form the exact check does not reproduce (the smooth
PPTE bound of the blended relief variants against the exact PPTE of every variant, sharp starts included): where
the exact LTCA breaks one by more than ``refine_stress_tolerance``, the re-solve lowers it by 1.25 times the
excess, as it raises a broken lower limit."""


def exact_limit_shortfalls(built, exact: pd.DataFrame, tolerance: float) -> dict[str, float]:
    """:func:`exact_lower_limit_shortfalls` and the excess over each upper limit of
    :data:`BACKED_OFF_UPPER_LIMITS` the exact LTCA breaks by more than ``tolerance`` (relative): limit label ->
    amount in the quantity's unit (the back-off of the re-solve, :meth:`LTCAOptions.backoff`)."""
    upper = _exact_breaks(built, exact, tolerance,
                          lambda lim: lim.quantity in BACKED_OFF_UPPER_LIMITS and lim.upper is not None, "upper")
    return {**exact_lower_limit_shortfalls(built, exact, tolerance), **upper}


def _exact_breaks(built, exact: pd.DataFrame, tolerance: float, applies, side: str) -> dict[str, float]:
    """Limit label -> amount by which the exact check breaks the ``side`` bound of each scene limit ``applies``
    selects, beyond ``tolerance`` (relative), per load case."""
    out: dict[str, float] = {}
    if not len(exact):
        return out
    for lim in built.scene.limits:
        if lim.quantity not in exact.columns or not applies(lim):
            continue
        bound = lim.lower if side == "lower" else lim.upper
        for _, row in exact[exact["mesh"] == lim.target].iterrows():
            if lim.load_cases is not None and row["load_case"] not in lim.load_cases:
                continue
            amount = (bound - float(row[lim.quantity])) if side == "lower" else (float(row[lim.quantity]) - bound)
            if amount > tolerance * abs(bound):
                out[f"{lim.quantity}[{lim.target}]@{row['load_case']}"] = amount
    return out


def _stress_errors(ex: pd.DataFrame) -> pd.Series:
    """Per exact-check row, the largest relative smooth-vs-exact error of a stress or temperature (0 if none)."""
    columns = [c for c in ex.columns if c.endswith("_error") and c != "ppte_um_error"]
    return ex[columns].max(axis=1) if columns else pd.Series(np.zeros(len(ex)), index=ex.index)


def _remedies(current, ex, tol: float, raise_slices: bool = False) -> dict:
    """Options of the next build that cut the discretisation error (module docstring, step 3); ``raise_slices``:
    a helical mesh's stress misses its exact peak at positions the NLP already samples."""
    if not len(ex):
        return {}
    disc = ppte_disagreement(ex, "smooth_dense_ppte_um", tol, current.options.refinement.refine_abs_tolerance_um)
    helical = ex["slices"] > 1 if "slices" in ex else np.zeros(len(ex), dtype=bool)
    o, options = current.options, {}
    n, n_max = o.model.helical_slices, o.refinement.max_helical_slices
    spur_left = bool((disc[~helical] > 0.5).any())
    if raise_slices or bool((disc[helical] > 0.5).any()):
        if n < n_max:
            options["helical_slices"] = min(2 * n - 1, n_max)
        else:
            spur_left = True
    w, w_min = o.model.smoothing_um, o.refinement.min_smoothing_um
    if spur_left and w > w_min:
        options["smoothing_um"] = max(0.5 * w, w_min)
    return options


class SceneRefinement:
    """The semi-infinite refinement of a built scene (module docstring): :meth:`solve` solves ``built`` (a
    :class:`~gearopt.design.scene.BuiltScene`) with the exchange method and returns the best verified
    :class:`~gearopt.design.scene_result.SceneResult` with ``refinement`` filled in.

    It uses the built scene's public interface only: ``options`` (the tolerances and limits of the refinement),
    ``scene``, ``variable_names``, ``initial_overrides``, ``initial_values()``, ``ltca_meshes()``,
    ``positions_of()``, ``quantities_at()``, ``evaluator_at()``, ``exact_check()``, ``microgeometry_at()``,
    ``models``, ``solve_once()`` and ``rebuild()`` (the next build: more positions, other options, the models of
    :data:`REUSED_MODELS` taken over).
    """

    def __init__(self, built):
        self.built = built

    def solve(self, *, starts: int = 1, seed: int = 0, verbose: bool = False, warm_start=None, **ipopt):
        """Solve with the exchange method (module docstring, steps 1-6). With ``starts`` > 1 every start is a whole
        local solve -- its first solve refined and polished like a single start's -- and the best on the exact
        model is returned (:func:`exact_final_key`), so that more starts never give a worse exact design (the
        starts nest: those of a larger ``starts`` include those of a smaller one). ``SceneResult.starts`` then has
        each start's ``refined_exact_objective``, ``refined_exact_violation`` and ``refined_ipopt_iterations`` (its
        first solve and re-solves) and the ``chosen`` one."""
        if starts <= 1:
            return self._refine(None, seed=seed, verbose=verbose, warm_start=warm_start, **ipopt)
        firsts, table, screen = self.built.solve_starts(starts=starts, seed=seed, verbose=verbose, **ipopt)
        finals = [None if first is None else self._refine(first, seed=seed, verbose=verbose, **ipopt)
                  for first in firsts]
        keys = [None if r is None else exact_final_key(r) for r in finals]
        best = min((k for k in range(len(finals)) if finals[k] is not None), key=lambda k: (keys[k], k))
        table["refined_exact_objective"] = [np.nan if k is None else k[2] for k in keys]
        table["refined_exact_violation"] = [np.nan if k is None else k[1] for k in keys]
        table["refined_ipopt_iterations"] = [0 if r is None else int(r.refinement["ipopt_iterations"].sum())
                                             for r in finals]
        table["chosen"] = [k == best for k in range(len(finals))]
        result = dataclasses.replace(finals[best], starts=table, screen=screen)
        result.refinement = finals[best].refinement
        return result

    def _refine(self, first, *, seed: int = 0, verbose: bool = False, warm_start=None, **ipopt):
        """The exchange method from one start: ``first`` (a :class:`~gearopt.design.scene.SceneResult` of the
        build's first solve from one start) or ``None`` (the build's own first solve, screened where it applies;
        ``warm_start`` a :class:`~gearopt.nlp.WarmStartPoint` of that solve)."""
        built, starts = self.built, 1
        refinement = built.options.refinement
        tol, abs_tol = refinement.refine_tolerance, refinement.refine_abs_tolerance_um
        stress_tol = refinement.refine_stress_tolerance
        candidates = []                      # (exact objective, not verified, label, result or start tuple)
        keys = set(built.variable_names)
        built_positions = {m: built.positions_of(m) for m in built.ltca_meshes()}
        if keys & set(built.initial_overrides):       # a warm start: its design (the rest at the declared starts)
            start = built.initial_values()
            q0 = built.quantities_at(start)
            ex0 = built.exact_check(start, built.evaluator_at(start))
            if _admissible(built, q0, ex0, tol):
                verified = ppte_agrees(built, q0, ex0, tol, abs_tol)
                candidates.append((_verified_objective(built, q0, ex0), not verified, "start", (start, q0, ex0)))
        max_refinements = refinement.max_refinements
        rows, current, status, first_screen, first_starts = [], built, "max_refinements reached", None, None
        t_start = time.perf_counter()
        for it in range(max_refinements + 1):
            t0 = time.perf_counter()
            options = dict(ipopt)
            if it > 0:     # a re-solve that runs several times the longest solve so far will not pay (step 4)
                options["max_iter"] = resolve_budget([r["ipopt_iterations"] for r in rows], ipopt.get("max_iter"))
            try:
                result = first if it == 0 and first is not None else current.solve_once(
                    starts=starts, seed=seed, verbose=verbose, check=True, screened=it == 0,
                    warm_start=warm_start if it == 0 else None, **options)
            except SolveError as exc:
                if it == 0:
                    raise
                status = f"re-solve {it} failed ({type(exc).__name__}: {exc.status}); kept the best verified design"
                break
            if it == 0:
                first_screen, first_starts = result.screen, result.starts
            ex = result.exact_check
            err = float(ex["ppte_um_error"].max()) if len(ex) else 0.0
            stress_err = _stress_errors(ex)
            shortfalls = exact_limit_shortfalls(current, ex, stress_tol)
            agrees = ppte_agrees(current, result.quantities, ex, tol, abs_tol) \
                and bool((stress_err <= stress_tol).all()) and not shortfalls
            worst = ex.loc[ex["ppte_um_error"].idxmax()] if len(ex) else None
            exact = ex["ppte_um"].abs().clip(lower=1e-12) if len(ex) else None
            smoothing_err = float(((ex["smooth_dense_ppte_um"] - ex["ppte_um"]).abs() / exact).max()) \
                if len(ex) else 0.0
            sampling_err = (ex["smooth_dense_ppte_um"] - ex["smooth_ppte_um"]).abs() / exact if len(ex) else None
            admissible = _admissible(current, result.quantities, ex, tol)
            exact_objective = _verified_objective(current, result.quantities, ex)
            prior_best = min((c[0] for c in candidates), default=None)
            if admissible:
                candidates.append((exact_objective, not agrees, f"solve {it}", result))
            rows.append({"iteration": it, "positions": int(sum(len(p) for p in result.positions.values())),
                         "helical_slices": current.options.model.helical_slices,
                         "smoothing_um": current.options.model.smoothing_um,
                         "objective": float(result.solve.objective), "exact_objective": exact_objective,
                         "admissible": admissible, "max_ppte_error": err,
                         "max_stress_error": float(stress_err.max()) if len(ex) else 0.0,
                         "exact_limit_shortfalls": ", ".join(f"{k} {v:.4g}" for k, v in shortfalls.items()),
                         "smoothing_error": smoothing_err,
                         "sampling_error": float(sampling_err.max()) if sampling_err is not None else 0.0,
                         "worst_mesh": "" if worst is None else str(worst["mesh"]),
                         "worst_load_case": "" if worst is None else str(worst["load_case"]),
                         "ipopt_iterations": int(result.solve.iterations),
                         "solve_time_s": float(result.solve.solve_time_s or 0.0),
                         "wall_time_s": time.perf_counter() - t0})
            if agrees:
                status = "converged"
                break
            if it == max_refinements:
                break
            lowered = prior_best is not None and admissible and \
                exact_objective < prior_best - tol * max(abs(prior_best), 1e-12)
            if it > 0 and refinement.stop_without_progress and prior_best is not None and not lowered:
                status = (f"stopped: re-solve {it} did not lower the best exact objective by more than "
                          f"{100 * tol:g} % (stop_without_progress)")
                break
            closest = min((r["max_ppte_error"] for r in rows[:-1]), default=err)   # the agreement so far
            if it > 0 and refinement.stop_on_divergence and prior_best is not None and not lowered \
                    and not shortfalls and err > closest:
                status = (f"stopped: re-solve {it} lowered neither the best exact objective nor the smooth model's "
                          f"largest PPTE error ({err:.3g} against {closest:.3g} before; stop_on_divergence)")
                break
            sets, added, stress_sliced = {}, 0, False
            for mesh, fractions in result.positions.items():
                rows_m = ex["mesh"] == mesh
                sampling = ppte_disagreement(ex[rows_m].assign(ppte_um=ex.loc[rows_m, "smooth_dense_ppte_um"]),
                                             "smooth_ppte_um", tol, abs_tol)
                worst_positions = [f for fr in ex.loc[rows_m, "worst_fractions"] for f in fr] \
                    if (sampling > 0.5).any() else []
                stressed = rows_m & (stress_err > stress_tol)
                stress_new = new_fractions(fractions, [f for fr in ex.loc[stressed, "stress_fractions"] for f in fr]) \
                    if "stress_fractions" in ex else []
                # a stress peak the NLP already samples and still misses: the face slicing (helical) is to blame
                stress_sliced |= bool(stressed.any() and not stress_new and (ex.loc[stressed, "slices"] > 1).any())
                new = new_fractions(fractions, worst_positions + stress_new)
                added += len(new)
                sets[mesh] = np.sort(np.concatenate([fractions, new]))
            options = _remedies(current, ex, tol, raise_slices=stress_sliced)
            if shortfalls:      # tighten each broken limit by 1.25x its exact shortfall (excess) for the re-solve
                backoff = dict(current.options.limit_backoff)
                lazy = current.options.tolerance.toleranced_ppte_lazy
                for label, amount in shortfalls.items():
                    if lazy and label.startswith("ppte_um_toleranced[") and label not in backoff:
                        backoff[label] = 0.0        # a lazy limit the NLP did not carry: carried as stated
                    else:
                        backoff[label] = backoff.get(label, 0.0) + 1.25 * amount
                options["limit_backoff"] = backoff
            if not added and not options:
                status = "stalled: the exact worst positions are in the NLP's sets and the discretisation at its limits"
                break
            reuse = {k: v for k, v in current.models.items() if k.startswith(REUSED_MODELS)}
            current = current.rebuild(positions=sets, initial=result.values, reuse=reuse, options=options)
        if first_screen is not None:
            candidates += _screen_candidate(built, first_screen, candidates, tol, abs_tol)
        chosen, verified, objective = f"solve {len(rows) - 1} (last, not admissible)", False, float("nan")
        if candidates:
            best_objective = min(c[0] for c in candidates)
            slack = tol * max(abs(best_objective), 1e-12)
            verified_near = [c for c in candidates if not c[1] and c[0] <= best_objective + slack]
            objective, unverified, chosen, best = min(verified_near or candidates, key=lambda c: c[0])
            verified = not unverified
            if chosen in ("start", "screen"):
                start, q0, ex0 = best
                result = dataclasses.replace(
                    result, values=start, quantities=q0, exact_check=ex0, positions=built_positions, source=built,
                    microgeometry={m: built.microgeometry_at(start, m) for m in built.ltca_meshes()})
                chosen = "start (no verified solve improved on it)" if chosen == "start" else \
                    "exact screen's best design (no solve improved on it)"
            else:
                result = best
        polish = None
        if candidates and search_scope(built) is None and built.options.search.polish_evaluations_per_variable:
            result, polish = _polished(result)
            if bool(polish["accepted"].iloc[0]):
                objective = float(polish["polished_objective"].iloc[0])
                chosen += " + exact polish"
                verified = ppte_agrees(result.source, result.quantities, result.exact_check, tol, abs_tol)
        if first_screen is not None or first_starts is not None:    # the re-solves are warm (one start, not
            result = dataclasses.replace(result, screen=first_screen, starts=first_starts)   # screened): the first's
        table = pd.DataFrame(rows)
        table.attrs.update(status=status, tolerance=tol, total_time_s=time.perf_counter() - t_start, chosen=chosen,
                           verified=verified, verified_objective=objective if candidates else float("nan"),
                           polish=polish)
        result.refinement = table
        return result


def exact_final_key(result) -> tuple[bool, float, float]:
    """Rank of a refined design among starts (:func:`~gearopt.design.scene_search.rank_key`): its exact objective
    (``refinement.attrs["verified_objective"]``) and its exact violation -- the exact check's limits plus, where the
    exact search applies, the closed-form geometry's (:func:`~gearopt.design.scene_search.exact_geometry_violations`);
    a start without an admissible design ranks last."""
    built = result.source
    objective = float(result.refinement.attrs.get("verified_objective", np.nan))
    violation = exact_limit_violation(built, result.exact_check)
    if search_scope(built) is None:
        violation += float(sum(exact_geometry_violations(built, result.values).values()))
    if not np.isfinite(objective):
        return True, float("inf"), float("inf")
    return rank_key(objective, violation)


def _screen_candidate(built, screen: pd.DataFrame, candidates: list, tol: float, abs_tol: float) -> list:
    """The exact screen's best design as a refinement candidate (a list of none or one), when it meets every exact
    limit (within :data:`~gearopt.design.scene_search.EXACT_RANK_TOLERANCE`) and its exact objective is below every
    solve's: an NLP optimum reached from it may be a worse local optimum on the exact model."""
    if not len(screen):
        return []
    top = screen.iloc[0]
    objective, violation = float(top["exact_objective"]), float(top["exact_violation"])
    if rank_key(objective, violation)[0] or any(c[0] <= objective for c in candidates):
        return []
    values = {n: float(top[n]) for n in built.variable_names}
    q0, ex0 = built.quantities_at(values), built.exact_check(values, built.evaluator_at(values))
    if rank_key(objective, exact_limit_violation(built, ex0))[0]:    # the screen leaves out the relief variants
        return []
    return [(objective, not ppte_agrees(built, q0, ex0, tol, abs_tol), "screen", (values, q0, ex0))]


def _polished(result):
    """``(result, summary)``: ``result`` at its exact polish (:func:`~gearopt.design.scene_search.exact_polish`),
    its quantities (smooth) and exact check re-evaluated there by the build that solved it, when the polish is
    accepted."""
    source = result.source
    values, summary = exact_polish(source, result.values)
    if not bool(summary["accepted"].iloc[0]):
        return result, summary
    return dataclasses.replace(
        result, values=values, quantities=source.quantities_at(values),
        exact_check=source.exact_check(values, source.evaluator_at(values)),
        microgeometry={m: source.microgeometry_at(values, m) for m in source.ltca_meshes()}), summary



def solve_refined(built, *, starts: int = 1, seed: int = 0, verbose: bool = False, **ipopt):
    """Solve ``built`` (a :class:`~gearopt.design.scene.BuiltScene`) with the exchange method
    (:meth:`SceneRefinement.solve`)."""
    return SceneRefinement(built).solve(starts=starts, seed=seed, verbose=verbose, **ipopt)

__all__ = ["SceneRefinement", "solve_refined", "exact_final_key", "ppte_disagreement", "ppte_agrees", "exact_lower_limit_shortfalls",
           "exact_limit_shortfalls", "BACKED_OFF_UPPER_LIMITS", "resolve_budget", "RESOLVE_BUDGET_FACTOR",
           "RESOLVE_BUDGET_MIN_ITERATIONS",
           "extreme_fractions", "peak_fractions", "new_fractions", "REUSED_MODELS"]
