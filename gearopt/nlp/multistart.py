"""Multi-start for any :class:`~gearopt.nlp.problem.Problem`: Latin-hypercube starting points, every start
recorded (typed failures included), success rate, best optimum.

Ipopt finds a local optimum; which one depends on the start. :func:`multistart` solves the same (unchanged, not
rebuilt) problem from ``n`` starting points drawn by Latin-hypercube sampling (McKay, Beckman & Conover,
Technometrics 21 (1979) 239): each randomised dimension is cut into ``n`` equal strata and every stratum holds
exactly one start, with the strata of different dimensions paired by independent random permutations.

Dimensions are the scalar elements of the chosen variables:

- an element with finite lower and upper bounds is sampled uniformly (per stratum) inside them;
- an element with a missing bound keeps its declared initial guess, unless ``span`` is given: it is then sampled
  in ``init +- span * scale`` (``scale`` the variable's declared magnitude), cut at the finite bound if it has one.

Each start changes only the initial guesses (:meth:`Problem.set_initial`); the declared guesses are restored at the
end. A start that fails keeps its typed error (:class:`~gearopt.errors.SolveError` subclass, or
:class:`~gearopt.errors.BadInitialGuessError` when the model is NaN/Inf at that start) in :attr:`MultiStartResult.
errors` and its status in the table; nothing is dropped. If every start fails, the error of the start that ended
closest to feasibility is raised again, with the count of statuses and the table attached.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from gearopt.nlp.entries import element_names
from gearopt.nlp.result import ProblemResult
from gearopt.errors import BadInitialGuessError, GearoptInputError, SolveError

if TYPE_CHECKING:  # pragma: no cover
    Problem = Any  # gearopt.nlp.problem.Problem: it delegates here, so this module does not import it


@dataclass
class MultiStartResult:
    """Outcome of :func:`multistart`.

    Attributes:
        problem: problem name.
        best: the successful result with the best objective (lowest for a minimisation, highest for a
            maximisation).
        best_start: row index in :attr:`table` of ``best``.
        table: one row per start: ``start`` (index), ``origin`` (``"initial"``, ``"latin_hypercube"`` or the
            label of given ``points``), one ``<element>_init`` column per randomised element (variable units), ``status`` (Ipopt status, or
            ``"bad_initial_guess"``), ``success``, ``error`` (typed error class name, ``""`` on success),
            ``objective`` (objective units; the last iterate's for a failed solve, NaN if it never started),
            ``iterations``, ``solve_time_s`` (Ipopt), ``wall_time_s`` (the whole ``solve()`` call).
        dimensions: names of the randomised elements (``x`` or ``x[i]``), in column order.
        starts: the starting points, shape (starts, dimensions), variable units.
        results: per start, the :class:`ProblemResult` (None for a failed start).
        errors: per start, the typed error (None for a successful start).
    """

    problem: str
    best: ProblemResult
    best_start: int
    table: pd.DataFrame = field(repr=False)
    dimensions: list[str]
    starts: np.ndarray = field(repr=False)
    results: list[ProblemResult | None] = field(repr=False)
    errors: list[Exception | None] = field(repr=False)

    @property
    def n_starts(self) -> int:
        """Number of starts solved."""
        return len(self.table)

    @property
    def success_rate(self) -> float:
        """Fraction of starts that converged (0..1)."""
        return float(self.table["success"].mean())

    def status_counts(self) -> dict[str, int]:
        """Ipopt status -> number of starts."""
        return dict(Counter(self.table["status"]))


def latin_hypercube(n: int, dims: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` points in ``[0, 1)^dims``, one per stratum ``[k/n, (k+1)/n)`` in every dimension (McKay et al. 1979).

    Each column is an independent random permutation of the strata plus a uniform offset inside the stratum.
    """
    if dims == 0:
        return np.zeros((n, 0))
    strata = np.column_stack([rng.permutation(n) for _ in range(dims)])
    return (strata + rng.random((n, dims))) / n


def multistart(problem: Problem, n: int, *, seed: int | None = 0, variables: Sequence[str] | None = None,
               span: float | Mapping[str, float] | None = None, include_initial: bool = False,
               points: np.ndarray | None = None, origin: str = "given", **solve_options: Any) -> MultiStartResult:
    """Solve ``problem`` from ``n`` Latin-hypercube starting points (plus, optionally, its declared guess).

    Args:
        problem: the problem (declared once; only its initial guesses change, and are restored afterwards).
        n: number of Latin-hypercube starts (>= 1).
        seed: seed of ``numpy.random.default_rng``; the same seed gives the same starts.
        variables: names of the variables to randomise (default: all); the others keep their declared guess.
        span: for elements without two finite bounds: sample in ``init +- span * scale`` (a number for all, or a
            dict by variable name); default None keeps their declared guess.
        include_initial: also solve from the declared initial guess (first row, origin ``"initial"``).
        points: the starting points themselves instead of Latin-hypercube ones: shape ``(n, dimensions)``, one
            column per sampled element in :attr:`MultiStartResult.dimensions` order (variable units; e.g. the best
            designs of an exact screen), each row inside the bounds; their ``origin`` labels the table rows.
        solve_options: passed to :meth:`Problem.solve` at every start (``max_iter=...``, ``verbose`` ...);
            ``warm_start`` is not allowed (every start is a cold start by design).

    Returns:
        :class:`MultiStartResult`.

    Raises:
        GearoptInputError: bad ``n``, unknown variable names, a bad ``span``, nothing to randomise, ``warm_start``.
        SolveError or BadInitialGuessError: every start failed; the error (same class) of the start that ended
            closest to feasibility, with ``.multistart`` (the table) attached and the status counts in its message.
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise GearoptInputError(f"n={n!r} is below its limit: must be an integer >= 1")
    if "warm_start" in solve_options:
        raise GearoptInputError("multistart: warm_start is not allowed (each start is solved from its own guess)")
    entries = problem._variables
    chosen = list(entries) if variables is None else list(variables)
    unknown = [name for name in chosen if name not in entries]
    if unknown:
        raise GearoptInputError(f"variables {unknown} are not declared in problem '{problem.name}'; declared "
                                f"variables: {', '.join(entries) or 'none'}")
    spans = _spans(span, chosen)

    dims: list[tuple[str, int, float, float]] = []     # (variable, element, low, high)
    labels: list[str] = []
    for name in chosen:
        v = entries[name]
        for i, label in enumerate(element_names(name, v.size, v.vector)):
            lo, hi = float(v.lower[i]), float(v.upper[i])
            if not (np.isfinite(lo) and np.isfinite(hi)):
                if spans.get(name) is None:
                    continue
                half = spans[name] * float(v.scale[i])
                lo, hi = max(lo, float(v.init[i]) - half), min(hi, float(v.init[i]) + half)
            dims.append((name, i, lo, hi))
            labels.append(label)
    if not dims:
        raise GearoptInputError(f"multistart on problem '{problem.name}': none of the variables {chosen} has two "
                                f"finite bounds; give span= to sample around their initial guesses")

    low = np.array([d[2] for d in dims])
    high = np.array([d[3] for d in dims])
    if points is None:
        points = low + latin_hypercube(int(n), len(dims), np.random.default_rng(seed)) * (high - low)
        origins = ["latin_hypercube"] * int(n)
    else:
        points = _given_points(points, int(n), labels, low, high)
        origins = [origin] * int(n)
    declared = {name: v.init.copy() for name, v in entries.items()}
    if include_initial:
        first = np.array([declared[name][i] for name, i, _, _ in dims])
        points = np.vstack([first, points])
        origins = ["initial"] + origins

    rows, results, errors = [], [], []
    try:
        for k, point in enumerate(points):
            guess = {name: declared[name].copy() for name in chosen}
            for (name, i, _, _), value in zip(dims, point):
                guess[name][i] = value
            for name, value in guess.items():
                problem.set_initial(name, value)
            row: dict[str, Any] = {"start": k, "origin": origins[k]}
            row.update({f"{label}_init": float(value) for label, value in zip(labels, point)})
            t0 = time.perf_counter()
            try:
                res = problem.solve(**solve_options)
                err: Exception | None = None
            except SolveError as exc:
                res, err = None, exc
            except BadInitialGuessError as exc:
                res, err = None, exc
            wall = time.perf_counter() - t0
            row.update(_outcome(res, err, wall))
            rows.append(row)
            results.append(res)
            errors.append(err)
    finally:
        for name, value in declared.items():
            problem.set_initial(name, value)

    table = pd.DataFrame(rows)
    ok = [k for k, r in enumerate(results) if r is not None]
    if not ok:
        raise _all_failed(problem, errors, table)
    best_k = min(ok, key=lambda k: problem._sense * results[k].objective)
    return MultiStartResult(problem=problem.name, best=results[best_k], best_start=best_k, table=table,
                            dimensions=labels, starts=points, results=results, errors=errors)


def _given_points(points, n: int, labels: list[str], low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """``points`` checked: ``n`` finite rows of one value per sampled element, inside the bounds."""
    arr = np.asarray(points, dtype=float)
    if arr.ndim != 2 or arr.shape != (n, len(labels)):
        raise GearoptInputError(f"points has shape {arr.shape}: must be (n={n}, {len(labels)}) for the elements "
                                f"{labels}")
    outside = ~np.isfinite(arr) | (arr < low - 1e-12 * np.maximum(1.0, abs(low)))\
        | (arr > high + 1e-12 * np.maximum(1.0, abs(high)))
    if outside.any():
        row, col = (int(i) for i in np.argwhere(outside)[0])
        raise GearoptInputError(f"points[{row}] {labels[col]}={float(arr[row, col])!r} is outside its bounds "
                                f"[{low[col]:.6g}, {high[col]:.6g}]")
    return np.clip(arr, low, high)


def _spans(span: float | Mapping[str, float] | None, chosen: list[str]) -> dict[str, float | None]:
    if span is None:
        return {}
    if isinstance(span, Mapping):
        unknown = sorted(set(span) - set(chosen))
        if unknown:
            raise GearoptInputError(f"span names variables {unknown} that are not randomised ({chosen})")
        items = dict(span)
    else:
        items = {name: span for name in chosen}
    out: dict[str, float | None] = {}
    for name, value in items.items():
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise GearoptInputError(f"span[{name!r}]={value!r} is not a number") from None
        if not (np.isfinite(number) and number > 0):
            raise GearoptInputError(f"span[{name!r}]={value!r} is below its limit: must be > 0 and finite "
                                    f"(multiples of the variable's scale)")
        out[name] = number
    return out


def _outcome(res: ProblemResult | None, err: Exception | None, wall: float) -> dict[str, Any]:
    if res is not None:
        return {"status": res.status, "success": True, "error": "", "objective": res.objective,
                "iterations": res.iterations, "solve_time_s": res.solve_time_s, "wall_time_s": wall}
    partial = getattr(err, "result", None)
    status = getattr(err, "status", "") or ("bad_initial_guess" if isinstance(err, BadInitialGuessError) else "")
    return {"status": status, "success": False, "error": type(err).__name__,
            "objective": partial.objective if partial is not None else np.nan,
            "iterations": partial.iterations if partial is not None else 0,
            "solve_time_s": partial.solve_time_s if partial is not None else 0.0, "wall_time_s": wall}


def _infeasibility(err: Exception) -> float:
    """Largest violation / scale at a failed start's last iterate (inf without a partial result)."""
    partial = getattr(err, "result", None)
    if partial is None:
        return np.inf
    worst = 0.0
    for table in (partial.constraints, partial.variables):
        if table.empty:
            continue
        value, lo, hi = (table[c].to_numpy(dtype=float) for c in ("value", "lower", "upper"))
        if np.any(~np.isfinite(value)):
            return np.inf
        excess = np.maximum.reduce([lo - value, value - hi, np.zeros_like(value)]) / table["scale"].to_numpy(float)
        worst = max(worst, float(excess.max(initial=0.0)))
    return worst


def _all_failed(problem: Problem, errors: list[Exception | None], table: pd.DataFrame) -> Exception:
    """The error of the start closest to feasibility (ties: lower objective), re-raised with the start count."""
    def rank(k: int) -> tuple[float, float]:
        objective = problem._sense * float(table["objective"][k])
        return _infeasibility(errors[k]), (objective if np.isfinite(objective) else np.inf)

    order = sorted(range(len(errors)), key=rank)
    k = order[0]
    err = errors[k]
    counts = ", ".join(f"{status or 'unknown'}: {count}" for status, count in Counter(table["status"]).items())
    first_line = str(err).split("\n", 1)[0]
    message = (f"problem '{problem.name}': all {len(errors)} multi-start runs failed ({counts}); "
               f"start {k} ({table['origin'][k]}) ended closest to feasibility: {first_line}")
    if isinstance(err, SolveError):
        new: Exception = type(err)(message, status=err.status, hint=err.hint, violated=err.violated,
                                   result=err.result)
    else:
        new = type(err)(message + "\n" + "\n".join(str(err).split("\n")[1:]))
    new.multistart = table
    return new


__all__ = ["MultiStartResult", "latin_hypercube", "multistart"]
