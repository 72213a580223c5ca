"""Elastic mode: the smallest relaxation of a problem's constraints that makes it feasible, named and in units.

When Ipopt reports an infeasible problem it stops at a point of local infeasibility, and its violated constraints
depend on where it stopped. Elastic mode (the l1 "phase 1" of SQP codes, e.g. SNOPT's elastic mode, Gill, Murray &
Saunders, SIAM Review 47 (2005) 99, section 6) answers the design question instead: *which* limits must move, and
by how much, for a solution to exist.

Every finite bound of every constraint element gets a non-negative relaxation ``r`` in the constraint's own units::

    lower <= expr + r_lower - r_upper <= upper,     r_lower, r_upper >= 0

and the NLP minimises the weighted l1 norm of the relaxations in scaled units, ``sum w * r / scale`` (``scale`` is
the constraint's declared scale, so a relaxation costs in proportion to what it means for that constraint;
``w`` defaults to 1). Modes:

- ``"lexicographic"`` (default): first minimise the relaxation (phase 1), then minimise the problem's own objective
  over the points whose weighted relaxation stays within ``relaxation_tol`` of that minimum (phase 2). For a
  feasible problem phase 1 gives zero and phase 2 is the original problem.
- ``"relaxation"``: phase 1 only (the point is any point of least relaxation).
- ``"penalty"``: one solve of ``objective/objective_scale + penalty * sum w r/scale`` (the exact l1 penalty,
  SNOPT's composite objective); it meets the constraints exactly when ``penalty`` exceeds the largest scaled
  multiplier, and otherwise trades constraint violation against the objective.

Variable bounds are **not** relaxed: they are hard (they usually guard model domains, e.g. a relief amount >= 0).
A problem whose variable bounds conflict cannot be relaxed and fails in phase 1 like the original.

The reported relaxation of an element is its violation recomputed from the original constraint expressions at the
returned point (``max(lower - value, 0)`` or ``max(value - upper, 0)``), not the slack variable, so it is what a
designer must concede.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import casadi as ca
import numpy as np
import pandas as pd

from gearopt.nlp.result import ProblemResult
from gearopt.errors import GearoptInputError, SolveError
from gearopt.nlp.entries import check_positive

if TYPE_CHECKING:  # pragma: no cover
    Problem = Any  # the Problem class; elastic builds its mirror with ``type(problem)`` (no import cycle)

MODES = ("lexicographic", "relaxation", "penalty")
"""Elastic modes, see the module docstring."""

ELASTIC_COLUMNS = ["name", "base", "element", "bound_side", "bound", "value", "relaxation", "scaled_relaxation",
                   "weight", "scale", "unit", "source"]
"""Columns of :attr:`ElasticResult.table`."""

RELAX_SUFFIX = {"lower": "__relax_lower", "upper": "__relax_upper"}
"""Name suffixes of the relaxation variables in the elastic problem (``<constraint>__relax_lower`` ...)."""


@dataclass
class ElasticResult:
    """Outcome of :func:`solve_elastic`.

    Attributes:
        problem: name of the original problem.
        mode: the elastic mode used.
        feasible: True when every relaxation is within ``feasibility_tol * scale`` (the original problem is
            feasible, to that tolerance, at :attr:`values`).
        table: one row per finite bound of every constraint element, largest ``scaled_relaxation`` first:
            ``name`` (``c`` or ``c[i]``), ``base`` (declared name), ``element`` (index in the constraint),
            ``bound_side`` (``"lower"``/``"upper"``), ``bound`` and ``value`` (constraint units), ``relaxation``
            (how far the bound must move, constraint units, >= 0), ``scaled_relaxation`` (relaxation / scale),
            ``weight``, ``scale``, ``unit``, ``source`` (declaration line).
        values: variable name -> value at the relaxed point (variable units; arrays for vector variables).
        objective: the original objective at the relaxed point (its own units).
        total_relaxation: least weighted relaxation ``sum w r / scale`` found in phase 1 (``"penalty"``: at the
            returned point).
        solve: :class:`ProblemResult` of the last elastic solve (its tables include the relaxation variables).
        relaxation_solve: :class:`ProblemResult` of phase 1 (the same object as ``solve`` for ``"relaxation"``
            and ``"penalty"``).
        phase2_error: the typed error of phase 2 if it failed (the phase-1 point is then returned), else None.
        feasibility_tol: tolerance on ``scaled_relaxation`` used for :attr:`feasible` and :attr:`relaxed`.
    """

    problem: str
    mode: str
    feasible: bool
    table: pd.DataFrame = field(repr=False)
    values: dict[str, Any]
    objective: float
    total_relaxation: float
    solve: ProblemResult = field(repr=False)
    relaxation_solve: ProblemResult = field(repr=False)
    phase2_error: SolveError | None = field(default=None, repr=False)
    feasibility_tol: float = 1e-6

    @property
    def relaxed(self) -> pd.DataFrame:
        """The rows of :attr:`table` that must be relaxed (scaled relaxation above ``feasibility_tol``)."""
        return self.table[self.table["scaled_relaxation"] > self.feasibility_tol].reset_index(drop=True)

    def relaxation(self, name: str) -> float:
        """Largest relaxation (constraint units) over the elements and sides of the constraint ``name`` (declared
        name, e.g. ``"contact_ratio_margin"``, or element name, e.g. ``"stress[2]"``)."""
        rows = self.table[(self.table["base"] == name) | (self.table["name"] == name)]
        if rows.empty:
            known = ", ".join(dict.fromkeys(self.table["base"])) or "none"
            raise KeyError(f"no constraint named {name!r} in problem '{self.problem}'; constraints: {known}")
        return float(rows["relaxation"].max())

    def summary(self, n: int = 5) -> str:
        """One line per relaxed bound (at most ``n``), e.g.
        ``contact_ratio_margin: lower bound 0 -> -0.279 (relax by 0.279)``; or a line saying none is needed."""
        rows = self.relaxed
        if rows.empty:
            return (f"elastic mode: every constraint of problem '{self.problem}' can be met (largest scaled "
                    f"relaxation <= {self.feasibility_tol:g})")
        lines = [(f"elastic mode ({self.mode}, l1 over scaled relaxations): {len(rows)} bound(s) must move for "
                  f"problem '{self.problem}' to be feasible:")]
        for row in rows.head(n).itertuples(index=False):
            unit = f" {row.unit}" if row.unit else ""
            moved = row.bound - row.relaxation if row.bound_side == "lower" else row.bound + row.relaxation
            lines.append(f"  - {row.name}: {row.bound_side} bound {row.bound:.6g}{unit} -> {moved:.6g}{unit} "
                         f"(relax by {row.relaxation:.4g}{unit})" + (f"  [{row.source}]" if row.source else ""))
        if len(rows) > n:
            lines.append(f"  ... and {len(rows) - n} more (error.relaxations / ElasticResult.table)")
        return "\n".join(lines)


def solve_elastic(problem: Problem, *, weights: Mapping[str, Any] | None = None, mode: str = "lexicographic",
                  penalty: float = 100.0, feasibility_tol: float = 1e-6, relaxation_tol: float = 1e-7,
                  warm_start: bool = False, verbose: bool = False, casadi_options: dict[str, Any] | None = None,
                  **ipopt_options: Any) -> ElasticResult:
    """Relax ``problem``'s constraints by the least weighted amount that makes it feasible (see the module doc).

    The original problem is not modified: a separate elastic :class:`Problem` is built on a CasADi ``Function`` of
    the original constraint expressions and objective, with the same variables (init, bounds, scales, units), the
    current parameter values and one relaxation variable per finite constraint bound.

    Args:
        problem: the problem to relax (at least one constraint).
        weights: constraint name -> positive weight (scalar or one per element); default 1 for every constraint.
            A relaxation ``r`` of a constraint with scale ``c`` and weight ``w`` costs ``w * r / c``.
        mode: ``"lexicographic"``, ``"relaxation"`` or ``"penalty"`` (module docstring).
        penalty: weight of the relaxation against the scaled objective in ``"penalty"`` mode (> 0).
        feasibility_tol: a bound counts as relaxed when ``relaxation / scale`` exceeds this (scaled units).
        relaxation_tol: phase 2 may raise any scaled relaxation by at most ``relaxation_tol * max(1, phase1)``
            over the least total found in phase 1 (the weighted total is bounded by phase 1 + that times the
            smallest weight). When phase 1 relaxes nothing (within ``feasibility_tol``), phase 2 is the original
            problem itself, started at the phase-1 point.
        warm_start: start from the problem's previous successful solution instead of its initial guesses.
        verbose, casadi_options, ipopt_options: as for :meth:`Problem.solve` (used by every elastic solve).

    Returns:
        :class:`ElasticResult`.

    Raises:
        GearoptInputError: no constraints, unknown weight names, bad weights/mode/tolerances.
        SolveError: phase 1 itself failed (typed as for :meth:`Problem.solve`; e.g. NaN in a model, or variable
            bounds that conflict). A failed phase 2 does not raise: see :attr:`ElasticResult.phase2_error`.
    """
    if mode not in MODES:
        raise GearoptInputError(f"mode={mode!r} must be one of {MODES}")
    check_positive(penalty, owner="solve_elastic", what="penalty")
    check_positive(feasibility_tol, owner="solve_elastic", what="feasibility_tol")
    check_positive(relaxation_tol, owner="solve_elastic", what="relaxation_tol")
    problem._check_solvable()
    constraints = list(problem._constraints.values())
    if not constraints:
        raise GearoptInputError(f"problem '{problem.name}' has no constraints to relax; limit: at least one")
    if not problem._variables:
        raise GearoptInputError(f"problem '{problem.name}' has no variables; limit: at least one")
    w = _weights(constraints, weights)
    variables = list(problem._variables.values())

    start = problem._start(warm_start)
    solve_opts = dict(verbose=verbose, casadi_options=casadi_options, **ipopt_options)
    ep, total, objective = _mirror(problem, constraints, w, start, relax=True)
    phase2_error = None
    if mode == "penalty":
        ep.minimize(objective + penalty * total)
        first = last = ep.solve(**solve_opts)
        least = float(last.value(total))
    else:
        ep.minimize(total)
        first = last = ep.solve(**solve_opts)
        least = float(first.objective)
        if mode == "lexicographic":
            if _scaled_relaxations(problem, constraints, w, first).max(initial=0.0) <= feasibility_tol:
                # nothing to relax: phase 2 is the original problem, started from the phase-1 point
                ep2, _, objective2 = _mirror(problem, constraints, w, _scaled_start(first, variables), relax=False)
            else:
                ep2, objective2 = ep, objective
                # per scaled relaxation, phase 2 may add at most relaxation_tol * max(1, least) over phase 1
                slack = relaxation_tol * max(1.0, least) * min(float(wc.min()) for wc in w)
                ep2.subject_to("elastic_total_relaxation", total, upper=least + slack, scale=max(1.0, least))
                for name, value in first.values.items():
                    entry = ep2._variables[name]
                    ep2.set_initial(name, np.clip(value, entry.lower, entry.upper))  # Ipopt may end a hair outside
            ep2.minimize(objective2)
            try:
                last = ep2.solve(**solve_opts)
            except SolveError as exc:
                phase2_error = exc

    x_scaled = {v.name: np.atleast_1d(np.asarray(last.values[v.name], dtype=float)) / v.scale for v in variables}
    g_final, f_final, _, _ = problem._evaluate(x_scaled)
    table = _relaxation_table(constraints, w, g_final)
    feasible = bool((table["scaled_relaxation"] <= feasibility_tol).all())
    values = {v.name: (x_scaled[v.name] * v.scale if v.vector else float(x_scaled[v.name][0] * v.scale[0]))
              for v in variables}
    return ElasticResult(problem=problem.name, mode=mode, feasible=feasible, table=table, values=values,
                         objective=float(f_final[0]), total_relaxation=least, solve=last, relaxation_solve=first,
                         phase2_error=phase2_error, feasibility_tol=float(feasibility_tol))


def _mirror(problem: Problem, constraints: list, w: list[np.ndarray], start: dict[str, np.ndarray], *,
            relax: bool) -> tuple[Problem, ca.MX, ca.MX]:
    """A new Problem with ``problem``'s variables (started at the scaled point ``start``) and constraints, built on
    one CasADi Function of the original constraints and objective at the current parameter values; with ``relax``
    every finite bound gets a relaxation variable. Returns it, the weighted scaled relaxation (0 without
    ``relax``) and the original objective as Ipopt sees it (sense and scale applied)."""
    variables = list(problem._variables.values())
    parameters = list(problem._parameters.values())
    model = ca.Function("elastic_model", [v.symbol for v in variables] + [p.symbol for p in parameters],
                        [ca.vertcat(*[c.expr for c in constraints]), problem._objective])
    g0 = np.nan_to_num(problem._evaluate(start)[0], nan=0.0, posinf=0.0, neginf=0.0)
    ep = type(problem)(f"{problem.name} (elastic)", active_tol=problem._active_tol)
    for v in variables:
        ep.variable(v.name, init=start[v.name] * v.scale, lower=_bound(v.lower), upper=_bound(v.upper),
                    scale=v.scale, unit=v.unit, n=v.size if v.vector else None)
    g, f = model.call([ep._variables[v.name].symbol for v in variables] + [ca.DM(p.value) for p in parameters])
    total = ca.MX(0.0)
    offset = 0
    for c, wc in zip(constraints, w):
        gc, g0c = g[offset:offset + c.size], g0[offset:offset + c.size]
        offset += c.size
        relaxed = gc
        for side, bound, sign in (("lower", c.lower, 1.0), ("upper", c.upper, -1.0)):
            idx = np.flatnonzero(np.isfinite(bound))
            if not relax or idx.size == 0:
                continue
            init = np.maximum(sign * (bound[idx] - g0c[idx]), 0.0)
            r = ep.variable(c.name + RELAX_SUFFIX[side], init=init, lower=0.0, scale=c.scale[idx], unit=c.unit,
                            n=int(idx.size))
            select = ca.DM(ca.Sparsity.triplet(c.size, int(idx.size), [int(i) for i in idx],
                                               list(range(idx.size))), 1.0)
            relaxed = relaxed + sign * ca.mtimes(select, r)
            total = total + ca.dot(ca.DM(wc[idx] / c.scale[idx]), r)
        ep.subject_to(c.name, relaxed, lower=_bound(c.lower), upper=_bound(c.upper), scale=c.scale, unit=c.unit,
                      source=c.source)
    return ep, total, problem._sense * f / problem._objective_scale


def _scaled_start(result: ProblemResult, variables: list) -> dict[str, np.ndarray]:
    """Scaled point of the original variables at ``result`` (clipped into their bounds)."""
    return {v.name: np.clip(np.atleast_1d(np.asarray(result.values[v.name], dtype=float)), v.lower, v.upper)
            / v.scale for v in variables}


def _scaled_relaxations(problem: Problem, constraints: list, w: list[np.ndarray],
                        result: ProblemResult) -> np.ndarray:
    """Scaled relaxation of every finite bound, recomputed from the original constraints at ``result``."""
    g = problem._evaluate(_scaled_start(result, list(problem._variables.values())))[0]
    return _relaxation_table(constraints, w, g)["scaled_relaxation"].to_numpy(dtype=float)


def attach_elastic(problem: Problem, error: SolveError, **elastic_options: Any) -> SolveError:
    """A copy of the typed solve ``error`` (same class, status, hint, violations, partial result) whose message
    adds the elastic relaxation and which carries it: ``.relaxations`` (the :attr:`ElasticResult.table`, or None
    if the elastic solve failed too) and ``.elastic`` (the :class:`ElasticResult` or that second error)."""
    first_line = str(error).split("\n", 1)[0]
    try:
        elastic: ElasticResult | SolveError = solve_elastic(problem, **elastic_options)
        relaxations = elastic.table
        if elastic.feasible:
            note = (f"{elastic.summary()}; the failure is not an infeasibility: try starting from "
                    f"error.elastic.values")
        else:
            note = elastic.summary()
    except SolveError as exc:
        elastic, relaxations = exc, None
        note = f"elastic mode failed too (Ipopt status {exc.status})"
    new = type(error)(f"{first_line}\n{note}", status=error.status, hint=error.hint, violated=error.violated,
                      result=error.result)
    new.relaxations = relaxations
    new.elastic = elastic
    return new


def _bound(values: np.ndarray) -> np.ndarray | None:
    """A declared bound array as :meth:`Problem.variable`/``subject_to`` take it (None where it is absent)."""
    return None if not np.isfinite(values).any() else values


def _weights(constraints: list, weights: Mapping[str, Any] | None) -> list[np.ndarray]:
    """Per-element weights (default 1) of every constraint; unknown names and non-positive weights raise."""
    weights = dict(weights or {})
    names = {c.name for c in constraints}
    unknown = sorted(set(weights) - names)
    if unknown:
        raise GearoptInputError(f"weights name constraints {unknown} that are not declared; declared constraints: "
                                f"{', '.join(c.name for c in constraints)}")
    out = []
    for c in constraints:
        raw = np.asarray(weights.get(c.name, 1.0), dtype=float)
        if raw.size not in (1, c.size):
            raise GearoptInputError(f"weights['{c.name}'] has {raw.size} elements; limit: 1 or {c.size}")
        wc = np.broadcast_to(raw.reshape(-1), (c.size,)).astype(float) if raw.size == 1 else raw.reshape(-1)
        bad = ~(np.isfinite(wc) & (wc > 0))
        if bad.any():
            raise GearoptInputError(f"weights['{c.name}']={float(wc[bad][0])!r} is below its limit: must be > 0 and finite")
        out.append(wc)
    return out


def _relaxation_table(constraints: list, weights: list[np.ndarray], g: np.ndarray) -> pd.DataFrame:
    rows = []
    offset = 0
    for c, wc in zip(constraints, weights):
        values = g[offset:offset + c.size]
        offset += c.size
        for i, label in enumerate(c.element_names()):
            for side, bound in (("lower", c.lower[i]), ("upper", c.upper[i])):
                if not np.isfinite(bound):
                    continue
                violation = bound - values[i] if side == "lower" else values[i] - bound
                relaxation = float(max(violation, 0.0)) if np.isfinite(violation) else float("nan")
                rows.append({"name": label, "base": c.name, "element": i, "bound_side": side, "bound": float(bound),
                             "value": float(values[i]), "relaxation": relaxation,
                             "scaled_relaxation": relaxation / float(c.scale[i]), "weight": float(wc[i]),
                             "scale": float(c.scale[i]), "unit": c.unit, "source": c.source})
    table = pd.DataFrame(rows, columns=ELASTIC_COLUMNS)
    return table.sort_values("scaled_relaxation", ascending=False, kind="stable").reset_index(drop=True)


__all__ = ["ELASTIC_COLUMNS", "MODES", "ElasticResult", "attach_elastic", "solve_elastic"]
