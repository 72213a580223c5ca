"""`Problem`: a thin wrapper of :class:`casadi.Opti` with named, scaled variables, named parameters and named,
scaled constraints, a pre-solve check, typed failures and a plain-data result.

Scaling: a variable declared with ``scale=s`` is the expression ``s * x_s`` where ``x_s`` is the decision variable
Ipopt sees, so a good ``scale`` (the expected magnitude) makes ``x_s`` O(1). A constraint ``lower <= e <= upper``
with ``scale=c`` is imposed as ``0 <= (e - lower)/c <= (upper - lower)/c`` (``(e - upper)/c <= 0`` without a lower
bound), so ``c`` should be the magnitude of a meaningful change of ``e``. An objective ``f`` with ``scale=F`` is
minimised as ``f/F``. Results are always reported unscaled, in the units the user declared.

The problem is built once; parameters (:meth:`Problem.set_parameter`) and initial guesses
(:meth:`Problem.set_initial`) change between solves without rebuilding the NLP solver.

Example::

    p = Problem("two_circles")
    x = p.variable("x", init=0.0, lower=-2.0, upper=2.0)
    y = p.variable("y", init=0.0)
    p.subject_to("sum_min", x + y, lower=1.0)
    p.minimize(x**2 + y**2)
    res = p.solve()            # res.values == {"x": 0.5, "y": 0.5}, res.multipliers["sum_min"] == 1.0
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from contextlib import contextmanager
from typing import Any, Callable, Iterator

import casadi as ca
import numpy as np

from gearopt.nlp import failures
from gearopt.nlp.conflicts import SimpleRow, separate_conflicts
from gearopt.nlp.entries import (ArrayLike, ConstraintEntry, ParameterEntry, VariableEntry, as_bound, as_elements,
                                    caller_source, check_name, check_ordered, check_positive)
from gearopt.nlp.precheck import (IPOPT_BOUND_FRAC, IPOPT_BOUND_PUSH, InitialGuessReport, ipopt_start_point,
                                     nonfinite, outside_bounds)
from gearopt.nlp.elastic import ElasticResult, attach_elastic, solve_elastic
from gearopt.nlp.multistart import MultiStartResult, multistart
from gearopt.nlp.result import (ProblemResult, constraint_table, multipliers_by_name, variable_table,
                                   violations_from_tables)
from gearopt.errors import (GearoptInputError, InfeasibleProblemError, NumericalSolveError,
                            ViolatedConstraint)


DEFAULT_IPOPT_OPTIONS: dict[str, Any] = {
    "print_level": 0, "sb": "yes", "max_iter": 1000, "tol": 1e-8, "mu_strategy": "adaptive", "max_wall_time": 600.0}
"""Ipopt options used unless overridden by keyword arguments of :meth:`Problem.solve`. The budgets ``max_iter`` and
``max_wall_time`` [s] stop a solve that does not converge with :class:`~gearopt.errors.IterationLimitError` (status
``Maximum_Iterations_Exceeded`` / ``Maximum_WallTime_Exceeded``, naming the option to raise)."""

DEFAULT_CASADI_OPTIONS: dict[str, Any] = {
    "print_time": False, "record_time": True, "detect_simple_bounds": True}
"""CasADi ``nlpsol`` options. ``detect_simple_bounds`` hands variable bounds (and constraints affine in a single
variable) to Ipopt as true bounds, which its iterates never leave; ``record_time`` gives the solve wall time."""


@dataclass(frozen=True)
class ConstantConstraint:
    """A declared constraint that does not depend on the design variables (it holds; not passed to Ipopt)."""

    name: str
    value: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    unit: str
    source: str


class Problem:
    """A named optimal-design problem on top of one :class:`casadi.Opti` instance.

    Args:
        name: problem name used in reports and error messages.
        active_tol: tolerance in scaled units: a constraint is *active* when its margin divided by its scale is
            within ``active_tol`` and its scaled multiplier exceeds ``active_tol``; a variable is *at bound*
            when its distance to a bound divided by its scale is within ``active_tol``.
    """

    def __init__(self, name: str = "problem", *, active_tol: float = 1e-6) -> None:
        self._name = check_name(name, "problem")
        if not (np.isfinite(active_tol) and active_tol > 0):
            raise GearoptInputError(f"active_tol={active_tol!r} is below its limit: must be > 0 and finite")
        self._active_tol = float(active_tol)
        self._opti = ca.Opti()
        self._variables: dict[str, VariableEntry] = {}
        self._parameters: dict[str, ParameterEntry] = {}
        self._constraints: dict[str, ConstraintEntry] = {}
        self._constant_constraints: dict[str, ConstantConstraint] = {}
        self._objective: ca.MX = ca.MX(0.0)
        self._sense = 1.0
        self._objective_scale = 1.0
        self._ng = 0
        self._version = 0
        self._probe: ca.Function | None = None
        self._probe_version = -1
        self._solver_key: str | None = None
        self._solver_dirty = True
        self._solver_builds = 0
        self._pending_build_s = 0.0
        self._previous_x: dict[str, np.ndarray] = {}
        self._previous_lam: np.ndarray | None = None

    # ------------------------------------------------------------------ introspection

    @property
    def name(self) -> str:
        """Problem name."""
        return self._name

    @property
    def opti(self) -> ca.Opti:
        """The underlying :class:`casadi.Opti` (for inspection; declare everything through this class)."""
        return self._opti

    @property
    def solver_builds(self) -> int:
        """How many times CasADi's NLP solver has been constructed (1 for a problem re-solved unchanged)."""
        return self._solver_builds

    @property
    def variable_names(self) -> tuple[str, ...]:
        """Names of the variables, in declaration order."""
        return tuple(self._variables)

    @property
    def parameter_names(self) -> tuple[str, ...]:
        """Names of the parameters, in declaration order."""
        return tuple(self._parameters)

    @property
    def constraint_names(self) -> tuple[str, ...]:
        """Names of the constraints, in declaration order."""
        return tuple(self._constraints)

    def __repr__(self) -> str:
        return (f"Problem({self._name!r}: {len(self._variables)} variables, {len(self._parameters)} parameters, "
                f"{len(self._constraints)} constraints)")

    # ------------------------------------------------------------------ declarations

    def variable(self, name: str, init: ArrayLike, *, lower: ArrayLike | None = None,
                 upper: ArrayLike | None = None, scale: ArrayLike = 1.0, unit: str = "",
                 n: int | None = None) -> ca.MX:
        """Declare a design variable and return its expression ``scale * x_s`` (in the variable's units).

        Args:
            name: unique name (shared namespace with parameters and constraints).
            init: initial guess, variable units; scalar or one value per element. May lie outside the bounds
                (flagged by the pre-solve check; Ipopt moves it inside).
            lower, upper: bounds in variable units (None: unbounded on that side); scalar or per element.
            scale: positive magnitude of the variable, variable units; Ipopt sees ``x / scale``.
            unit: unit label for reports.
            n: number of elements for a vector variable (None: scalar).

        Raises:
            GearoptInputError: duplicate name, ``upper < lower``, ``scale <= 0``, non-finite numbers, bad ``n``.
        """
        with self._building():
            self._check_new_name(name, "variable")
            size = _check_size(n, name)
            owner = f"variable '{name}'"
            lo = as_bound(lower, size, owner=owner, what="lower", unit=unit, missing=-np.inf)
            hi = as_bound(upper, size, owner=owner, what="upper", unit=unit, missing=np.inf)
            check_ordered(lo, hi, owner=owner, unit=unit)
            sc = as_elements(scale, size, owner=owner, what="scale", unit=unit)
            check_positive(sc, owner=owner, what="scale")
            x0 = as_elements(init, size, owner=owner, what="init", unit=unit)
            symbol = self._opti.variable(size)
            rows = None
            if np.isfinite(lo).any() or np.isfinite(hi).any():
                self._opti.subject_to(self._opti.bounded(ca.DM(lo / sc), symbol, ca.DM(hi / sc)))
                rows = self._take_rows(size)
            self._opti.set_initial(symbol, x0 / sc)
            entry = VariableEntry(name, symbol, size, n is not None, x0, lo, hi, sc, unit, caller_source(), rows)
            self._variables[name] = entry
            self._touch()
            return _scaled(entry)

    def parameter(self, name: str, value: ArrayLike, *, unit: str = "") -> ca.MX:
        """Declare a parameter (fixed in a solve, changeable between solves) and return its symbol.

        Args:
            name: unique name.
            value: initial value in ``unit``; a scalar gives a scalar parameter, an array a vector parameter.
            unit: unit label for reports.
        """
        with self._building():
            self._check_new_name(name, "parameter")
            if isinstance(value, (ca.MX, ca.SX)):
                raise GearoptInputError(f"parameter '{name}': value={value!r} must be a number or an array")
            shape = np.shape(value)
            size = max(int(np.prod(shape)), 1)
            values = as_elements(value, size, owner=f"parameter '{name}'", what="value", unit=unit)
            symbol = self._opti.parameter(size)
            self._opti.set_value(symbol, values)
            self._parameters[name] = ParameterEntry(name, symbol, size, len(shape) > 0, values, unit,
                                                    caller_source())
            self._touch()
            return symbol

    def set_parameter(self, name: str, value: ArrayLike) -> None:
        """Change a parameter's value (in its declared unit) for the next solve; the problem is not rebuilt."""
        entry = self._lookup(self._parameters, name, "parameter")
        entry.value = as_elements(value, entry.size, owner=f"parameter '{name}'", what="value", unit=entry.unit)
        self._opti.set_value(entry.symbol, entry.value)

    def set_initial(self, name: str, value: ArrayLike) -> None:
        """Change a variable's initial guess (variable units) for the next solve without ``warm_start``."""
        entry = self._lookup(self._variables, name, "variable")
        entry.init = as_elements(value, entry.size, owner=f"variable '{name}'", what="init", unit=entry.unit)

    def subject_to(self, name: str, expr: Any, *, lower: ArrayLike | None = None, upper: ArrayLike | None = None,
                   scale: ArrayLike = 1.0, unit: str = "", source: str | None = None) -> None:
        """Impose ``lower <= expr <= upper`` elementwise (an equality where ``lower == upper``).

        Args:
            name: unique name; a vector constraint's elements are reported as ``name[i]``.
            expr: CasADi MX expression of the problem's variables and parameters (any shape, taken column-major).
            lower, upper: bounds in ``unit`` (None: no bound on that side; at least one is required); scalar or
                one per element. Numbers only: put parameters into ``expr``.
            scale: positive magnitude of a meaningful change of ``expr`` in ``unit``; scalar or per element.
            unit: unit label for reports.
            source: ``file:line`` shown in reports and failures; default: the caller's line outside
                ``gearopt.design``.

        Raises:
            GearoptInputError: duplicate name, no bound, inverted bounds, ``scale <= 0``, a constant expression or
                one without decision variables.
        """
        with self._building():
            self._check_new_name(name, "constraint")
            source = caller_source() if source is None else source
            owner = f"constraint '{name}' [{source}]"
            if lower is None and upper is None:
                raise GearoptInputError(f"{owner}: lower=None and upper=None; limit: give at least one bound")
            mx = _as_mx(expr, owner)
            size = int(mx.numel())
            if size == 0:
                raise GearoptInputError(f"{owner}: the expression is empty (0 elements); limit: at least 1")
            lo = as_bound(lower, size, owner=owner, what="lower", unit=unit, missing=-np.inf)
            hi = as_bound(upper, size, owner=owner, what="upper", unit=unit, missing=np.inf)
            check_ordered(lo, hi, owner=owner, unit=unit)
            sc = as_elements(scale, size, owner=owner, what="scale", unit=unit)
            check_positive(sc, owner=owner, what="scale")
            flat = ca.vec(mx)
            if self._record_if_constant(name, flat, lo, hi, unit, source, owner):
                return
            ref = np.where(np.isfinite(lo), lo, hi)
            scaled = (flat - ca.DM(ref)) / ca.DM(sc)
            lb = np.where(np.isfinite(lo), 0.0, -np.inf)
            ub = np.where(np.isfinite(hi), (hi - ref) / sc, np.inf)
            try:
                self._opti.subject_to(self._opti.bounded(ca.DM(lb), scaled, ca.DM(ub)))
            except RuntimeError as exc:
                raise GearoptInputError(f"{owner}: CasADi rejected the expression: {_last_line(exc)}") from exc
            entry = ConstraintEntry(name, flat, size, mx.shape != (1, 1), lo, hi, sc, unit, source,
                                    self._take_rows(size))
            self._constraints[name] = entry
            self._touch()

    def minimize(self, expr: Any, *, scale: float = 1.0) -> None:
        """Minimise the scalar ``expr`` (Ipopt sees ``expr / scale``); replaces any previous objective."""
        self._set_objective(expr, scale, 1.0)

    def maximize(self, expr: Any, *, scale: float = 1.0) -> None:
        """Maximise the scalar ``expr`` (Ipopt minimises ``-expr / scale``); replaces any previous objective."""
        self._set_objective(expr, scale, -1.0)

    # ------------------------------------------------------------------ checking and solving

    def check_initial_guess(self) -> InitialGuessReport:
        """Evaluate constraints, objective and their derivatives at the declared initial guess.

        Returns the report (it also lists variables outside their bounds and constraints violated at the start).

        Raises:
            BadInitialGuessError: a constraint element or the objective, or a derivative, is NaN/Inf; the message
                names each one with its source line.
        """
        start = {name: v.init / v.scale for name, v in self._variables.items()}
        report = self._check(start, IPOPT_BOUND_PUSH, IPOPT_BOUND_FRAC)
        report.raise_if_bad()
        return report

    def solve(self, *, warm_start: bool = False, verbose: bool = False,
              casadi_options: dict[str, Any] | None = None, elastic_on_failure: bool = False,
              **ipopt_options: Any) -> ProblemResult:
        """Run the pre-solve check, then Ipopt; return the result or raise a typed error.

        Args:
            warm_start: start from the previous successful solution (primal and constraint multipliers) instead
                of the declared initial guesses. Ipopt uses the multipliers only with
                ``warm_start_init_point="yes"``.
            verbose: Ipopt iteration log (``print_level`` 5) and CasADi timings.
            casadi_options: extra or overriding CasADi ``nlpsol`` options (e.g. ``{"expand": True}``).
            elastic_on_failure: when Ipopt fails, also run :meth:`solve_elastic` (default mode, same options and
                start) and raise the typed error with the least relaxation in its message and as attributes
                ``relaxations`` (DataFrame: name, element, bound_side, bound, relaxation, unit, ...; None if the
                elastic solve failed too) and ``elastic`` (the :class:`~gearopt.nlp.elastic.ElasticResult`).
            **ipopt_options: Ipopt options by their Ipopt names (``max_iter=50``, ``tol=1e-6`` ...), overriding
                :data:`DEFAULT_IPOPT_OPTIONS`.

        Raises:
            BadInitialGuessError: the pre-solve check failed.
            InfeasibleProblemError, IterationLimitError, NumericalSolveError: Ipopt failed; the error carries
                ``status``, ``hint``, ``violated`` (worst 5, by name) and the partial ``result``.
        """
        self._check_solvable()
        ipopt, plugin = _solver_options(verbose, casadi_options, ipopt_options)
        t_check = time.perf_counter()
        start = self._start(warm_start)
        report = self._check(start, float(ipopt.get("bound_push", IPOPT_BOUND_PUSH)),
                             float(ipopt.get("bound_frac", IPOPT_BOUND_FRAC)))
        report.warn_if_outside_bounds()
        report.raise_if_bad()
        self._configure_solver(plugin)
        lam0 = self._start_multipliers(warm_start)
        for name, v in self._variables.items():
            self._opti.set_initial(v.symbol, start[name])
        if self._ng:
            self._opti.set_initial(self._opti.lam_g, lam0)
        build_s = self._pending_build_s + (time.perf_counter() - t_check)
        self._pending_build_s = 0.0

        t_solve = time.perf_counter()
        try:
            self._opti.solve()
            error: RuntimeError | None = None
        except RuntimeError as exc:
            error = exc
        wall_s = time.perf_counter() - t_solve
        stats = self._stats()
        if stats is None:
            raise NumericalSolveError(f"problem '{self._name}': the NLP solver could not be set up or run: "
                                      f"{_last_line(error)}", hint="check the solver options (names and values)"
                                      ) from error
        if self._solver_dirty:
            self._solver_builds += 1
            self._solver_dirty = False
        solve_s = float(stats.get("t_wall_total", wall_s))
        x_scaled, lam = self._last_iterate(stats, start, lam0)
        result = self._result(stats, x_scaled, lam, start, solve_s, build_s + max(wall_s - solve_s, 0.0))
        if not result.success:
            failure = failures.solve_error(result)
            if elastic_on_failure:
                failure = attach_elastic(self, failure, warm_start=warm_start, verbose=verbose,
                                         casadi_options=casadi_options, **ipopt_options)
            raise failure from error
        self._previous_x, self._previous_lam = x_scaled, lam
        return result

    def solve_elastic(self, **options: Any) -> ElasticResult:
        """Least weighted relaxation of the constraints that makes the problem feasible, by name and in units
        (variable bounds stay hard); see :func:`gearopt.nlp.elastic.solve_elastic` for the options
        (``weights``, ``mode``, ``penalty``, tolerances, solve options). The problem itself is not modified."""
        return solve_elastic(self, **options)

    def multistart(self, n: int, *, seed: int = 0, **options: Any) -> MultiStartResult:
        """Solve from ``n`` Latin-hypercube starting points inside the variable bounds; see
        :func:`gearopt.nlp.multistart.multistart` (``variables``, ``span``, ``include_initial``, solve
        options). The declared initial guesses are restored afterwards."""
        return multistart(self, n, seed=seed, **options)

    # ------------------------------------------------------------------ internals: declarations

    @contextmanager
    def _building(self) -> Iterator[None]:
        t0 = time.perf_counter()
        try:
            yield
        finally:
            self._pending_build_s += time.perf_counter() - t0

    @property
    def constant_constraints(self) -> dict[str, "ConstantConstraint"]:
        """Constraints that turned out not to depend on the design variables (affine with zero coefficients, e.g. a
        margin that a model keeps fixed); they hold, so they were not handed to Ipopt."""
        return dict(self._constant_constraints)

    def _record_if_constant(self, name: str, flat: ca.MX, lo: np.ndarray, hi: np.ndarray, unit: str, source: str,
                            owner: str) -> bool:
        """Keep constraints that do not depend on the variables away from Ipopt.

        CasADi's ``detect_simple_bounds`` reads a constraint that is affine in one variable with a zero coefficient
        as a bound at infinity and Ipopt then reports an invalid problem. A constant constraint that holds is
        recorded in :attr:`constant_constraints`; one that fails raises :class:`InfeasibleProblemError` now.
        """
        if not self._variables:
            return False
        x = ca.vertcat(*[v.symbol for v in self._variables.values()])
        params = [p.symbol for p in self._parameters.values()]
        if params and ca.depends_on(flat, ca.vertcat(*params)):
            return False
        jac = ca.jacobian(flat, x)
        if ca.depends_on(jac, x):
            return False
        jac_value, value = (np.array(v, dtype=float).reshape(-1)
                            for v in ca.Function("constant_probe", [x], [jac, flat])(ca.DM.zeros(x.numel())))
        if np.any(jac_value != 0.0):
            return False
        below, above = np.maximum(lo - value, 0.0), np.maximum(value - hi, 0.0)
        if np.any(below + above > 0.0):
            i = int(np.argmax(below + above))
            violated = ViolatedConstraint(name, float((below + above)[i]), float(value[i]), float(lo[i]),
                                          float(hi[i]), source)
            raise InfeasibleProblemError(f"{owner}: does not depend on the design variables and is violated",
                                         status="constant constraint violated",
                                         hint="the model fixes this quantity; change its data, not the variables",
                                         violated=[violated])
        self._constant_constraints[name] = ConstantConstraint(name, value, lo, hi, unit, source)
        return True

    def _touch(self) -> None:
        """Record that the NLP changed (the solver must be rebuilt, the probe function re-made)."""
        self._version += 1
        self._solver_dirty = True

    def _take_rows(self, size: int) -> slice:
        rows = slice(self._ng, self._ng + size)
        self._ng += size
        return rows

    def _check_new_name(self, name: str, kind: str) -> None:
        check_name(name, kind)
        for other_kind, table in (("variable", self._variables), ("parameter", self._parameters),
                                  ("constraint", self._constraints), ("constraint", self._constant_constraints)):
            if name in table:
                raise GearoptInputError(f"{kind} name '{name}' is already used by the {other_kind} declared at "
                                        f"{table[name].source}; limit: names must be unique")

    @staticmethod
    def _lookup(table: dict, name: str, kind: str) -> Any:
        if name not in table:
            known = ", ".join(table) or "none"
            raise GearoptInputError(f"{kind} '{name}' is not declared; declared {kind}s: {known}")
        return table[name]

    def _set_objective(self, expr: Any, scale: float, sense: float) -> None:
        with self._building():
            owner = "objective"
            mx = _as_mx(expr, owner, allow_constant=True)
            if mx.shape != (1, 1):
                raise GearoptInputError(f"objective has shape {mx.shape}; limit: a scalar (1x1)")
            sc = as_elements(scale, 1, owner=owner, what="scale")
            check_positive(sc, owner=owner, what="scale")
            self._objective, self._sense, self._objective_scale = mx, sense, float(sc[0])
            self._opti.minimize(sense * mx / self._objective_scale)
            self._touch()

    # ------------------------------------------------------------------ internals: evaluation

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
                                    f"Problem.variable/parameter: {_last_line(exc)}") from exc
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
            mx = _as_mx(expr, "expression", allow_constant=True)
            try:
                fn = ca.Function("value", symbols, [mx])
            except RuntimeError as exc:
                raise GearoptInputError(f"expression is not a function of problem '{name}' variables and "
                                        f"parameters: {_last_line(exc)}") from exc
            return np.asarray(fn.call(args)[0].full(), dtype=float)

        return evaluate

    # ------------------------------------------------------------------ internals: solving

    def _check_solvable(self) -> None:
        nx = sum(v.size for v in self._variables.values())
        np_ = sum(p.size for p in self._parameters.values())
        # Opti counts only the parameters its objective and constraints use: a declared one may be unused
        if (self._opti.nx, self._opti.ng) != (nx, self._ng) or self._opti.np > np_:
            raise GearoptInputError(
                f"problem '{self._name}': the Opti stack was modified directly (opti has nx={self._opti.nx}, "
                f"np={self._opti.np}, ng={self._opti.ng}; declared {nx}, {np_}, {self._ng}); declare variables, "
                f"parameters and constraints through Problem so that they can be reported by name")

    def _start(self, warm_start: bool) -> dict[str, np.ndarray]:
        """Scaled start point: previous solution (warm start, where available) or the declared initial guess."""
        return {name: (self._previous_x[name] if warm_start and name in self._previous_x else v.init / v.scale)
                for name, v in self._variables.items()}

    def _start_multipliers(self, warm_start: bool) -> np.ndarray:
        lam = self._previous_lam
        if warm_start and lam is not None and lam.size == self._ng:
            return lam
        return np.zeros(self._ng)

    def _configure_solver(self, plugin_options: dict[str, Any]) -> None:
        key = repr(sorted(plugin_options.items()))
        if key != self._solver_key:
            self._opti.solver("ipopt", plugin_options)
            self._solver_key = key
            self._solver_dirty = True

    def _stats(self) -> dict[str, Any] | None:
        try:
            stats = self._opti.stats()
        except RuntimeError:
            return None
        return stats if "return_status" in stats else None

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
                for i, row in enumerate(range(v.bound_rows.start, v.bound_rows.stop)):
                    data[row] = (start[v.name][i], 1.0, v.lower[i] / v.scale[i], v.upper[i] / v.scale[i])
        offset = 0
        for c in self._constraints.values():
            for i, row in enumerate(range(c.rows.start, c.rows.stop)):
                data[row] = (g[offset + i], dg[offset + i], c.lower[i], c.upper[i])
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


def _check_size(n: int | None, name: str) -> int:
    if n is None:
        return 1
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise GearoptInputError(f"variable '{name}': n={n!r} is below its limit: must be an integer >= 1")
    return int(n)


def _scaled(entry: VariableEntry) -> ca.MX:
    """The user-facing expression ``scale * x_s`` of a variable."""
    if np.all(entry.scale == entry.scale[0]):
        return float(entry.scale[0]) * entry.symbol
    return ca.DM(entry.scale) * entry.symbol


def _as_mx(expr: Any, owner: str, *, allow_constant: bool = False) -> ca.MX:
    """``expr`` as an MX; numbers only if ``allow_constant``. SX is refused (Opti works on MX)."""
    if isinstance(expr, ca.MX):
        return expr
    if isinstance(expr, ca.SX):
        raise GearoptInputError(f"{owner}: got an SX expression; build it from the problem's MX symbols or call "
                                f"an SX kernel through a casadi.Function")
    try:
        dm = ca.DM(expr)
    except (NotImplementedError, TypeError, RuntimeError) as exc:
        raise GearoptInputError(f"{owner}: {expr!r} is not a CasADi expression or a number") from exc
    if not allow_constant:
        raise GearoptInputError(f"{owner}: the expression is the constant {expr!r}; limit: it must depend on "
                                f"the problem's variables")
    return ca.MX(dm)


def _solver_options(verbose: bool, casadi_options: dict[str, Any] | None,
                    ipopt_options: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """Merge defaults and overrides; return (Ipopt options by Ipopt name, full ``nlpsol`` option dict)."""
    ipopt = dict(DEFAULT_IPOPT_OPTIONS)
    if verbose:
        ipopt["print_level"] = 5
    ipopt.update({key.removeprefix("ipopt."): value for key, value in ipopt_options.items()})
    _check_budget_options(ipopt)
    plugin = dict(DEFAULT_CASADI_OPTIONS)
    if verbose:
        plugin["print_time"] = True
    plugin.update(casadi_options or {})
    plugin.update({f"ipopt.{key}": value for key, value in ipopt.items()})
    return ipopt, plugin


def _check_budget_options(ipopt: dict[str, Any]) -> None:
    """The budget and tolerance options must be numbers in range (Ipopt would reject them only after a build, or
    wrap a huge ``max_iter`` to a negative integer)."""
    it = ipopt.get("max_iter")
    if isinstance(it, bool) or not isinstance(it, (int, np.integer, float)) or not float(it).is_integer() \
            or not 0 <= it <= 10 ** 9:
        raise GearoptInputError(f"max_iter={it!r} must be an integer count in [0, 1e9]")
    ipopt["max_iter"] = int(it)
    for name in ("max_wall_time", "max_cpu_time", "tol"):
        if name in ipopt:
            v = ipopt[name]
            if isinstance(v, bool) or not isinstance(v, (int, float, np.floating)) or not v > 0 or v != v:
                raise GearoptInputError(f"{name}={v!r} must be a positive number")
            if name != "tol" and math.isinf(v):
                ipopt[name] = 1e20  # Ipopt's way of saying no limit


def _last_line(exc: BaseException | None) -> str:
    """The informative last line of a (multi-line) CasADi error message."""
    text = str(exc).strip() if exc is not None else ""
    return text.splitlines()[-1] if text else "unknown error"
