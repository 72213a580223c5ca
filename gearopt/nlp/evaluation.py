"""Evaluation of a :class:`~gearopt.nlp.problem.Problem` at a point and the reports made from it: the pre-solve
check of the start point (:class:`~gearopt.nlp.precheck.InitialGuessReport`), Ipopt's last iterate (also when it
never started) and the plain-data :class:`~gearopt.nlp.result.ProblemResult`.

:class:`Evaluation` is a mixin of :class:`~gearopt.nlp.problem.Problem`, which owns the state it reads.
"""

from __future__ import annotations

from typing import Any, Callable

import casadi as ca
import numpy as np

from gearopt.nlp import failures
from gearopt.nlp.conflicts import SimpleRow, separate_conflicts
from gearopt.nlp.entries import ConstraintEntry, ParameterEntry, VariableEntry, as_mx, last_line
from gearopt.nlp.precheck import InitialGuessReport, ipopt_start_point, nonfinite, outside_bounds
from gearopt.nlp.result import (ProblemResult, constraint_table, multipliers_by_name, variable_table,
                                   violations_from_tables)
from gearopt.errors import GearoptInputError


class Evaluation:
    """The evaluating and reporting methods of :class:`~gearopt.nlp.problem.Problem` (mixin)."""

    _name: str
    _active_tol: float
    _opti: ca.Opti
    _variables: dict[str, VariableEntry]
    _parameters: dict[str, ParameterEntry]
    _constraints: dict[str, ConstraintEntry]
    _objective: ca.MX
    _sense: float
    _objective_scale: float
    _ng: int
    _version: int
    _probe: ca.Function | None
    _probe_version: int

    def _symbols(self) -> list[ca.MX]:
        return [v.symbol for v in self._variables.values()] + [p.symbol for p in self._parameters.values()]

    def _parameter_args(self) -> list[np.ndarray]:
        return [p.value for p in self._parameters.values()]

    def _probe_function(self) -> ca.Function:
        """``(x_s..., p...) -> (g, f, dg·1, df·1)``: unscaled constraints and objective and their forward
        derivatives along a vector of ones (a NaN/Inf anywhere in a Jacobian row shows up in that row)."""
        if self._probe is not None and self._probe_version == self._version:
            return self._probe
        exprs = [c.expr for c in self._constraints.values()]
        g = ca.vertcat(*exprs) if exprs else ca.MX(0, 1)
        x = ca.vertcat(*[v.symbol for v in self._variables.values()])
        ones = ca.DM.ones(x.numel())
        try:
            self._probe = ca.Function("probe", self._symbols(),
                                      [g, self._objective, ca.jtimes(g, x, ones), ca.jtimes(self._objective, x, ones)])
        except RuntimeError as exc:
            raise GearoptInputError(f"problem '{self._name}': an expression depends on symbols not declared through "
                                    f"Problem.variable/parameter: {last_line(exc)}") from exc
        self._probe_version = self._version
        return self._probe

    def _evaluate(self, x_scaled: dict[str, np.ndarray]) -> list[np.ndarray]:
        args = [x_scaled[name] for name in self._variables] + self._parameter_args()
        return [np.asarray(out.full(), dtype=float).ravel() for out in self._probe_function().call(args)]

    def _check(self, start: dict[str, np.ndarray], bound_push: float, bound_frac: float) -> InitialGuessReport:
        if not self._variables:
            raise GearoptInputError(f"problem '{self._name}' has no variables; limit: at least one")
        pushed = {name: ipopt_start_point(start[name], v.lower / v.scale, v.upper / v.scale,
                                          bound_push=bound_push, bound_frac=bound_frac)
                  for name, v in self._variables.items()}
        g, f, dg, df = self._evaluate(pushed)
        constraints = list(self._constraints.values())
        table = constraint_table(constraints, g, np.zeros(self._ng), objective_factor=0.0, tol=self._active_tol)
        return InitialGuessReport(
            problem=self._name,
            nonfinite_values=nonfinite(constraints, g, float(f[0]), "value"),
            nonfinite_derivatives=nonfinite(constraints, dg, float(df[0]), "derivative"),
            outside_bounds=outside_bounds(list(self._variables.values()),
                                          {n: start[n] * v.scale for n, v in self._variables.items()}),
            violated=violations_from_tables(table, None, self._active_tol))

    def _evaluator(self, x_scaled: dict[str, np.ndarray]) -> Callable[[Any], np.ndarray]:
        """A function evaluating any expression of the problem's symbols at the given point (and the current
        parameter values), detached from later changes of the problem."""
        symbols = self._symbols()
        args = [x_scaled[name] for name in self._variables] + [a.copy() for a in self._parameter_args()]
        name = self._name

        def evaluate(expr: Any) -> np.ndarray:
            mx = as_mx(expr, "expression", allow_constant=True)
            try:
                fn = ca.Function("value", symbols, [mx])
            except RuntimeError as exc:
                raise GearoptInputError(f"expression is not a function of problem '{name}' variables and "
                                        f"parameters: {last_line(exc)}") from exc
            return np.asarray(fn.call(args)[0].full(), dtype=float)

        return evaluate

    def _debug_array(self, expr: ca.MX, size: int) -> np.ndarray:
        if size == 0:
            return np.zeros(0)
        return np.atleast_1d(np.asarray(self._opti.debug.value(expr), dtype=float)).ravel()

    def _last_iterate(self, stats: dict[str, Any], start: dict[str, np.ndarray],
                      lam0: np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """Scaled variables and constraint multipliers of Ipopt's last iterate. If Ipopt never started iterating
        (CasADi's debug values are then meaningless) the start point, with variables whose simple bounds conflict
        moved into the gap so that the conflicting constraints show as violated."""
        status = str(stats["return_status"])
        if status in failures.NOT_STARTED_STATUSES:
            return self._separate_conflicts(start, stats), lam0
        sizes = [v.size for v in self._variables.values()]
        x_all = self._debug_array(ca.vertcat(*[v.symbol for v in self._variables.values()]), sum(sizes))
        bounds = np.cumsum([0] + sizes)
        x_scaled = {name: x_all[bounds[i]:bounds[i + 1]].copy() for i, name in enumerate(self._variables)}
        return x_scaled, self._debug_array(self._opti.lam_g, self._ng)

    def _separate_conflicts(self, start: dict[str, np.ndarray], stats: dict[str, Any]) -> dict[str, np.ndarray]:
        """Apply :func:`separate_conflicts` to the rows CasADi turned into simple bounds (from its stats)."""
        is_simple = list(stats.get("detect_simple_bounds_is_simple", []))
        targets = list(stats.get("detect_simple_bounds_target_x", []))
        if len(is_simple) != self._ng or sum(is_simple) != len(targets) or not targets:
            return start
        g, _, dg, _ = self._evaluate(start)
        data: dict[int, tuple[float, float, float, float]] = {}
        for v in self._variables.values():
            if v.bound_rows is not None:
                for i, row in enumerate(v.bound_rows):
                    data[int(row)] = (start[v.name][i], 1.0, v.lower[i] / v.scale[i], v.upper[i] / v.scale[i])
        offset = 0
        for c in self._constraints.values():
            for i, row in zip(c.passed, c.rows):
                data[int(row)] = (g[offset + i], dg[offset + i], c.lower[i], c.upper[i])
            offset += c.size
        simple_rows = [row for row, flag in enumerate(is_simple) if flag]
        rows = [SimpleRow(int(j), *data[row]) for row, j in zip(simple_rows, targets)]
        sizes = [v.size for v in self._variables.values()]
        x_all = separate_conflicts(np.concatenate([start[n] for n in self._variables]), rows)
        bounds = np.cumsum([0] + sizes)
        return {name: x_all[bounds[i]:bounds[i + 1]] for i, name in enumerate(self._variables)}

    def _result(self, stats: dict[str, Any], x_scaled: dict[str, np.ndarray], lam: np.ndarray,
                start: dict[str, np.ndarray], solve_s: float, build_s: float) -> ProblemResult:
        """Build the plain-data result at the scaled point ``x_scaled`` with multipliers ``lam``."""
        status = str(stats["return_status"])
        started = status not in failures.NOT_STARTED_STATUSES
        iterations = max(int(stats.get("iter_count", 0)), 0) if started else 0
        g, f, _, _ = self._evaluate(x_scaled)
        factor = -self._sense * self._objective_scale
        variables = list(self._variables.values())
        constraints = list(self._constraints.values())
        values = {n: x_scaled[n] * v.scale for n, v in self._variables.items()}
        inits = {n: start[n] * v.scale for n, v in self._variables.items()}
        ctable = constraint_table(constraints, g, lam, objective_factor=factor, tol=self._active_tol)
        vtable = variable_table(variables, values, inits, lam, objective_factor=factor, tol=self._active_tol)
        return ProblemResult(
            problem=self._name, status=status, success=bool(stats.get("success", False)), objective=float(f[0]),
            iterations=iterations, solve_time_s=solve_s, build_time_s=build_s,
            values={n: (x.copy() if v.vector else float(x[0])) for (n, x), v in zip(values.items(), variables)},
            parameters={n: (p.value.copy() if p.vector else float(p.value[0])) for n, p in self._parameters.items()},
            multipliers=multipliers_by_name(constraints, ctable), constraints=ctable, variables=vtable,
            active_tol=self._active_tol, _evaluate=self._evaluator(x_scaled))
