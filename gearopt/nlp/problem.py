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

import dataclasses
import time
from typing import Any

import casadi as ca
import numpy as np

import gearopt.numerics as nm
from gearopt.nlp import failures
from gearopt.nlp.declarations import ConstantConstraint, Declarations
from gearopt.nlp.entries import ConstraintEntry, ParameterEntry, VariableEntry, check_name, last_line
from gearopt.nlp.evaluation import Evaluation
from gearopt.nlp.precheck import IPOPT_BOUND_FRAC, IPOPT_BOUND_PUSH, InitialGuessReport
from gearopt.nlp.elastic import ElasticResult, attach_elastic, solve_elastic
from gearopt.nlp.multistart import MultiStartResult, multistart
from gearopt.nlp.result import ProblemResult
from gearopt.nlp.solver_options import DEFAULT_CASADI_OPTIONS, DEFAULT_IPOPT_OPTIONS, solver_options
from gearopt.errors import GearoptInputError, NumericalSolveError


MAX_EXCHANGES = 4
"""Exchange rounds of a screened constraint (:meth:`Problem.subject_to` ``screen``) before a solve hands every
element of the constraints still broken to Ipopt: the exchange then ends in at most one more solve."""


@dataclasses.dataclass(frozen=True)
class WarmStartPoint:
    """A solution of a :class:`Problem` to warm-start a later solve from: the scaled variables by name, the
    constraint multipliers (Ipopt's order) and the same multipliers by constraint name. It is plain data: it
    pickles, so a solve in another process of a problem built the same way can start from it
    (``Problem.solve(warm_start=point)``).

    ``multipliers_by_name``: constraint name -> multipliers in the units of :attr:`ProblemResult.multipliers`
    (``d objective / d bound``, one per element, 0 where an element was not passed to Ipopt), and variable name ->
    the multipliers of its bounds (``ProblemResult.variables["multiplier"]``'s units). Where it is given, a solve
    takes, for every constraint and bounded variable of the same name and size, the multipliers from it (rescaled
    to its own scales; every row of the problem that was solved): a start for another problem that shares
    constraints with the solved one (a re-solve with more limits, a rebuilt scene). The multipliers are those of
    the solved problem's objective: a problem that optimises another quantity, or the same one in the other sense,
    gets multipliers of the wrong size or sign. :meth:`from_result` makes a point of a result's multipliers alone
    (the primal start then stays the problem's own initial values)."""

    x_scaled: dict
    multipliers: np.ndarray
    multipliers_by_name: dict = dataclasses.field(default_factory=dict)

    def __post_init__(self):
        for field_name in ("x_scaled", "multipliers_by_name"):
            given = getattr(self, field_name)
            if not isinstance(given, dict) or not all(isinstance(k, str) for k in given):
                raise GearoptInputError(f"WarmStartPoint {field_name}={given!r} must be a dict of name -> values")
        x = {k: _finite_values("x_scaled", k, v) for k, v in self.x_scaled.items()}
        by_name = {k: _finite_values("multipliers_by_name", k, v).ravel() for k, v in self.multipliers_by_name.items()}
        lam = _finite_values("multipliers", None, self.multipliers).ravel()
        object.__setattr__(self, "x_scaled", x)
        object.__setattr__(self, "multipliers", lam)
        object.__setattr__(self, "multipliers_by_name", by_name)

    @classmethod
    def from_result(cls, result: ProblemResult) -> "WarmStartPoint":
        """The multipliers of a solve's result by constraint and variable name (its finite ones), no primal values:
        a problem that shares constraints with the solved one starts from them (with its own initial values)."""
        if not isinstance(result, ProblemResult):
            raise GearoptInputError(f"WarmStartPoint.from_result: result={result!r} must be a ProblemResult")
        by_name = {k: np.atleast_1d(np.asarray(v, dtype=float)) for k, v in result.multipliers.items()}
        if len(result.variables):
            for base, rows in result.variables.groupby("base", sort=False):
                by_name[str(base)] = rows["multiplier"].to_numpy(dtype=float)
        return cls({}, np.zeros(0), {k: v for k, v in by_name.items() if np.all(np.isfinite(v))})


def _finite_values(field_name: str, key: str | None, values) -> np.ndarray:
    """``values`` as a float array, every value finite (a :class:`WarmStartPoint` field), else a named error."""
    where = f"{field_name}[{key!r}]" if key is not None else field_name
    try:
        arr = np.atleast_1d(np.asarray(values, dtype=float))
    except (TypeError, ValueError) as exc:
        raise GearoptInputError(f"WarmStartPoint {where}={values!r}: must be real numbers ({exc})") from None
    if not np.all(np.isfinite(arr)):
        raise GearoptInputError(f"WarmStartPoint {where}={values!r}: every value must be finite")
    return arr


class Problem(Declarations, Evaluation):
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
        self.start_completion = None
        """Optional callable ``{name: value in variable units} -> {name: value}`` run on every start that is not a
        warm start: it may set dependent variables consistently with the others (e.g. the approaches of a lifted
        contact model from the design variables of that start)."""

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

    def depends_on_variables(self, expr: Any) -> bool:
        """Whether ``expr`` (a CasADi expression or a number) depends on any variable declared so far (through
        :meth:`variable`; parameters and undeclared symbols do not count). Unlike ``opti.x``, which holds only the
        variables a constraint or the objective already uses, this counts a variable from its declaration -- and it
        is cheaper: reading ``opti.x`` makes CasADi assemble the whole problem again, about 5 ms per read once it
        carries LTCA limits."""
        if not nm.is_symbolic(expr) or not self._variables:
            return False
        return nm.depends_on(expr, ca.vertcat(*[v.symbol for v in self._variables.values()]))

    def __repr__(self) -> str:
        return (f"Problem({self._name!r}: {len(self._variables)} variables, {len(self._parameters)} parameters, "
                f"{len(self._constraints)} constraints)")

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

    def warm_start_point(self) -> WarmStartPoint | None:
        """The last successful solution (scaled variables and constraint multipliers) as a :class:`WarmStartPoint`,
        None before the first one: ``solve(warm_start=point)`` starts there later, after other solves of this
        problem or in another process."""
        if not self._previous_x or self._previous_lam is None:
            return None
        factor = -self._sense * self._objective_scale        # as ProblemResult.multipliers (constraint_table)
        lam, by_name = self._previous_lam, {}
        for name, c in self._constraints.items():           # rows passed since that solve: no multiplier yet
            natural, known = np.zeros(c.size), c.rows < lam.size
            natural[c.passed[known]] = lam[c.rows[known]] * factor / c.scale[c.passed[known]]
            by_name[name] = natural
        for name, v in self._variables.items():              # bounds: as ProblemResult.variables (variable_table)
            if v.bound_rows is not None and np.all(v.bound_rows < lam.size):
                by_name[name] = lam[v.bound_rows] * factor / v.scale
        return WarmStartPoint({k: np.array(v, dtype=float) for k, v in self._previous_x.items()},
                              np.array(self._previous_lam, dtype=float), by_name)

    def solve(self, *, warm_start: bool | WarmStartPoint = False, verbose: bool = False,
              casadi_options: dict[str, Any] | None = None, elastic_on_failure: bool = False,
              **ipopt_options: Any) -> ProblemResult:
        """Run the pre-solve check, then Ipopt; return the result or raise a typed error.

        Args:
            warm_start: start from the previous successful solution (primal and constraint multipliers) instead
                of the declared initial guesses, or from a :class:`WarmStartPoint` (:meth:`warm_start_point`,
                :meth:`WarmStartPoint.from_result`): its multipliers matched by constraint and variable name and
                size (a point without them: as they are where their count matches this problem's rows); variables
                it lacks start at their declared initial values. Ipopt uses the multipliers only with ``warm_start_init_point="yes"``
                (:data:`~gearopt.nlp.WARM_START_IPOPT`).
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
        ipopt, plugin = solver_options(verbose, casadi_options, ipopt_options)
        t_check = time.perf_counter()
        start = self._start(warm_start)
        report = self._check(start, float(ipopt.get("bound_push", IPOPT_BOUND_PUSH)),
                             float(ipopt.get("bound_frac", IPOPT_BOUND_FRAC)))
        report.warn_if_outside_bounds()
        report.raise_if_bad()
        if self._screened():                         # rows by exchange: the held-back elements near a bound here
            self._pass_screened(self._evaluate(start)[0], broken_only=False)
        lam0 = self._start_multipliers(warm_start)
        build_s = self._pending_build_s + (time.perf_counter() - t_check)
        self._pending_build_s = 0.0
        iterations, solve_s, exchanges, first_start = 0, 0.0, 0, start
        while True:
            stats, x_scaled, lam, error, wall_s = self._run_ipopt(plugin, start, lam0)
            iterations += self._iterations(stats)
            solve_s += float(stats.get("t_wall_total", wall_s))
            build_s += max(wall_s - float(stats.get("t_wall_total", wall_s)), 0.0)
            result = self._result(stats, x_scaled, lam, first_start, solve_s, build_s)
            if not result.success or not self._screened():
                break
            g = self._evaluate(x_scaled)[0]
            if not self._screened_elements(g, broken_only=True):
                break
            # rows by exchange: the optimum broke held-back elements; pass them (and all now near a bound), re-solve
            exchanges += 1
            every = exchanges > MAX_EXCHANGES
            self._pass_screened(g, broken_only=False, every=every)
            start, lam0 = x_scaled, np.concatenate([lam, np.zeros(self._ng - lam.size)])
        result = dataclasses.replace(result, iterations=iterations, exchanges=exchanges)
        if not result.success:
            failure = failures.solve_error(result)
            if elastic_on_failure:
                failure = attach_elastic(self, failure, warm_start=warm_start, verbose=verbose,
                                         casadi_options=casadi_options, **ipopt_options)
            raise failure from error
        self._previous_x, self._previous_lam = x_scaled, lam
        return result

    def _run_ipopt(self, plugin: dict[str, Any], start: dict[str, np.ndarray], lam0: np.ndarray):
        """One Ipopt run from ``start`` (scaled) with constraint multipliers ``lam0``: ``(stats, x_scaled, lam,
        error, wall_s)``."""
        self._configure_solver(plugin)
        for name, v in self._variables.items():
            self._opti.set_initial(v.symbol, start[name])
        if self._ng:
            self._opti.set_initial(self._opti.lam_g, lam0)
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
                                      f"{last_line(error)}", hint="check the solver options (names and values)"
                                      ) from error
        if self._solver_dirty:
            self._solver_builds += 1
            self._solver_dirty = False
        x_scaled, lam = self._last_iterate(stats, start, lam0)
        return stats, x_scaled, lam, error, wall_s

    def _screened(self) -> bool:
        return any(c.screen is not None and c.passed.size < c.size for c in self._constraints.values())

    def _pass_screened(self, g: np.ndarray, *, broken_only: bool, every: bool = False) -> None:
        """Pass the held-back elements of screened constraints that are near a bound at ``g`` (or all of those
        constraints' elements with ``every``) to Ipopt."""
        chosen = self._screened_elements(g, broken_only=broken_only)
        for name, elements in chosen.items():
            entry = self._constraints[name]
            self._pass_elements(entry, np.arange(entry.size) if every else elements)

    def solve_elastic(self, **options: Any) -> ElasticResult:
        """Least weighted relaxation of the constraints that makes the problem feasible, by name and in units
        (variable bounds stay hard); see :func:`gearopt.nlp.elastic.solve_elastic` for the options
        (``weights``, ``mode``, ``penalty``, tolerances, solve options). The problem itself is not modified."""
        return solve_elastic(self, **options)

    def multistart(self, n: int, *, seed: int = 0, **options: Any) -> MultiStartResult:
        """Solve from ``n`` Latin-hypercube starting points inside the variable bounds; see
        :func:`gearopt.nlp.multistart.multistart` (``variables``, ``span``, ``include_initial``, solve
        options; ``points`` for given starts). The declared initial guesses are restored afterwards."""
        return multistart(self, n, seed=seed, **options)

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

    def _start(self, warm_start: bool | WarmStartPoint) -> dict[str, np.ndarray]:
        """Scaled start point: a given warm-start point, the previous solution (warm start, where available) or the
        declared initial guess (completed by :attr:`start_completion`)."""
        if isinstance(warm_start, WarmStartPoint) and not warm_start.x_scaled:    # multipliers only
            return self._start(False)
        if isinstance(warm_start, WarmStartPoint):      # a variable it lacks (or of another size): its init
            given = warm_start.x_scaled
            return {name: (given[name].reshape(v.init.shape)
                           if name in given and given[name].size == v.init.size else v.init / v.scale)
                    for name, v in self._variables.items()}
        if warm_start and self._previous_x:
            return {name: (self._previous_x[name] if name in self._previous_x else v.init / v.scale)
                    for name, v in self._variables.items()}
        if self.start_completion is not None:
            done = self.start_completion({name: v.init for name, v in self._variables.items()})
            for name, value in done.items():
                self._variables[name].init = np.asarray(value, dtype=float).reshape(self._variables[name].init.shape)
        return {name: v.init / v.scale for name, v in self._variables.items()}

    def _start_multipliers(self, warm_start: bool | WarmStartPoint) -> np.ndarray:
        if isinstance(warm_start, WarmStartPoint):
            if warm_start.multipliers_by_name:           # by name (constraints and variable bounds: every row)
                return self._multipliers_by_name(warm_start.multipliers_by_name)
            lam = warm_start.multipliers                  # another problem's order may differ: only an equal count
            return lam.copy() if lam.size == self._ng else np.zeros(self._ng)
        lam = self._previous_lam
        if warm_start and lam is not None and lam.size <= self._ng:   # rows passed since: zero multipliers
            return np.concatenate([lam, np.zeros(self._ng - lam.size)])
        return np.zeros(self._ng)

    def _multipliers_by_name(self, by_name: dict[str, np.ndarray]) -> np.ndarray:
        """Ipopt's start multipliers from multipliers by constraint name (:class:`WarmStartPoint`): each passed row
        of a constraint of the same name and size, rescaled to this problem's scales; 0 elsewhere."""
        factor = -self._sense * self._objective_scale
        lam = np.zeros(self._ng)
        for name, c in self._constraints.items():
            given = by_name.get(name)
            if given is not None and given.size == c.size and c.rows.size:
                lam[c.rows] = given[c.passed] * c.scale[c.passed] / factor
        for name, v in self._variables.items():
            given = by_name.get(name)
            if given is not None and given.size == v.size and v.bound_rows is not None:
                lam[v.bound_rows] = given * v.scale / factor
        return lam

    @staticmethod
    def _iterations(stats: dict[str, Any]) -> int:
        if str(stats["return_status"]) in failures.NOT_STARTED_STATUSES:
            return 0
        return max(int(stats.get("iter_count", 0)), 0)

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


__all__ = ["Problem", "WarmStartPoint", "ConstantConstraint", "DEFAULT_IPOPT_OPTIONS", "DEFAULT_CASADI_OPTIONS"]
