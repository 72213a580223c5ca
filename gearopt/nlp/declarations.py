"""Declarations of a :class:`~gearopt.nlp.problem.Problem`: variables, parameters, constraints and the objective,
each checked on input and recorded by name with the source line that declared it (:mod:`gearopt.nlp.entries`).

:class:`Declarations` is a mixin of :class:`~gearopt.nlp.problem.Problem`, which owns the state it works on (the
``Opti`` instance and the tables of entries, set up in ``Problem.__init__``). A constraint that does not depend on
the design variables is kept away from Ipopt (:class:`ConstantConstraint`).
"""

from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Iterator

import casadi as ca
import numpy as np

from gearopt.nlp.entries import (ArrayLike, ConstraintEntry, ParameterEntry, VariableEntry, as_bound, as_elements,
                                    as_mx, caller_source, check_name, check_ordered, check_positive, check_size,
                                    element_rows, last_line)
from gearopt.errors import GearoptInputError, InfeasibleProblemError, ViolatedConstraint


@dataclass(frozen=True)
class ConstantConstraint:
    """A declared constraint that does not depend on the design variables (it holds; not passed to Ipopt)."""

    name: str
    value: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    unit: str
    source: str


class Declarations:
    """The declaring methods of :class:`~gearopt.nlp.problem.Problem` (mixin; the state is the problem's)."""

    _opti: ca.Opti
    _variables: dict[str, VariableEntry]
    _parameters: dict[str, ParameterEntry]
    _constraints: dict[str, ConstraintEntry]
    _constant_constraints: dict[str, ConstantConstraint]
    _objective: ca.MX
    _sense: float
    _objective_scale: float
    _ng: int
    _version: int
    _solver_dirty: bool
    _pending_build_s: float

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
            size = check_size(n, name)
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
            return scaled_expression(entry)

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
                   scale: ArrayLike = 1.0, unit: str = "", source: str | None = None,
                   screen: ArrayLike | None = None) -> None:
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
            screen: rows by exchange for a long vector of inequalities of which few can bind (the contact
                stress at every spring of an LTCA): an element whose margin to its bound exceeds ``screen``
                (constraint units; scalar or per element, >= 0) at the start of a solve is held back from Ipopt.
                After each solve the held-back elements are evaluated; any the optimum breaks joins Ipopt's rows,
                with every element then within ``screen`` of its bound, and the problem is re-solved warm
                (:data:`~gearopt.nlp.problem.MAX_EXCHANGES` rounds, then every element). The optimum meets the
                whole constraint; Ipopt's linear algebra and the Jacobian see only the passed rows. Results
                report every element (a held-back one with a zero multiplier). An ``expr`` stacked with
                ``vertcat`` from blocks of independent models (one relief variant's LTCA per element) hands Ipopt
                the blocks of its passed rows only: the held-back models are not evaluated in a solve.

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
            mx = as_mx(expr, owner)
            size = int(mx.numel())
            if size == 0:
                raise GearoptInputError(f"{owner}: the expression is empty (0 elements); limit: at least 1")
            lo = as_bound(lower, size, owner=owner, what="lower", unit=unit, missing=-np.inf)
            hi = as_bound(upper, size, owner=owner, what="upper", unit=unit, missing=np.inf)
            check_ordered(lo, hi, owner=owner, unit=unit)
            sc = as_elements(scale, size, owner=owner, what="scale", unit=unit)
            check_positive(sc, owner=owner, what="scale")
            held = None
            if screen is not None:
                held = as_elements(screen, size, owner=owner, what="screen", unit=unit)
                if np.any(held < 0.0):
                    raise GearoptInputError(f"{owner}: screen={float(held.min())!r} {unit} is below its limit 0")
            flat = ca.vec(mx)
            if self._record_if_constant(name, flat, lo, hi, unit, source, owner):
                return
            entry = ConstraintEntry(name, flat, size, mx.shape != (1, 1), lo, hi, sc, unit, source,
                                    np.zeros(0, dtype=int), np.zeros(0, dtype=int), held)
            if held is None:
                try:
                    self._pass_elements(entry, np.arange(size))
                except RuntimeError as exc:
                    raise GearoptInputError(f"{owner}: CasADi rejected the expression: {last_line(exc)}") from exc
            self._constraints[name] = entry
            self._touch()

    def minimize(self, expr: Any, *, scale: float = 1.0) -> None:
        """Minimise the scalar ``expr`` (Ipopt sees ``expr / scale``); replaces any previous objective."""
        self._set_objective(expr, scale, 1.0)

    def maximize(self, expr: Any, *, scale: float = 1.0) -> None:
        """Maximise the scalar ``expr`` (Ipopt minimises ``-expr / scale``); replaces any previous objective."""
        self._set_objective(expr, scale, -1.0)

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
        recorded in :attr:`constant_constraints`; one that fails raises :class:`InfeasibleProblemError` at declaration.
        """
        if not self._variables:
            return False
        x = ca.vertcat(*[v.symbol for v in self._variables.values()])
        params = [p.symbol for p in self._parameters.values()]
        if params and ca.depends_on(flat, ca.vertcat(*params)):
            return False
        # structure first: a symbolic Jacobian (or a Hessian sparsity) of a large model -- every spring of an LTCA
        # -- cost seconds per constraint. A row on two or more variables is no simple bound whatever its
        # coefficients; only rows on none or one need the numbers.
        per_row = np.bincount(np.asarray(ca.jacobian_sparsity(flat, x).get_triplet()[0], dtype=int),
                              minlength=int(flat.numel()))
        if per_row.size and per_row.min() >= 2:
            return False
        if per_row.any() and any(ca.which_depends(flat, x, 2, True)):
            return False
        jac = ca.jacobian(flat, x)
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

    def _take_rows(self, size: int) -> np.ndarray:
        rows = np.arange(self._ng, self._ng + size)
        self._ng += size
        return rows

    def _pass_elements(self, entry: ConstraintEntry, elements: np.ndarray) -> None:
        """Hand more elements of a screened constraint to Ipopt (rows appended to Opti's constraint vector)."""
        new = np.setdiff1d(np.asarray(elements, dtype=int), entry.passed)
        if not new.size:
            return
        idx = new.tolist()
        scaled = (element_rows(entry.expr, idx) - ca.DM(entry.ref[new])) / ca.DM(entry.scale[new])
        lb = np.where(np.isfinite(entry.lower[new]), 0.0, -np.inf)
        ub = np.where(np.isfinite(entry.upper[new]), (entry.upper[new] - entry.ref[new]) / entry.scale[new], np.inf)
        self._opti.subject_to(self._opti.bounded(ca.DM(lb), scaled, ca.DM(ub)))
        entry.rows = np.concatenate([entry.rows, self._take_rows(new.size)])
        entry.passed = np.concatenate([entry.passed, new])
        self._solver_dirty = True     # the probe (every element of every constraint) stays valid

    def _screened_elements(self, g: np.ndarray, *, broken_only: bool) -> dict[str, np.ndarray]:
        """Held-back elements of the screened constraints at constraint values ``g`` (every element stacked):
        those within their ``screen`` of a bound (or beyond it), or with ``broken_only`` those that break a bound
        by more than the activity tolerance (in scaled units). Constraint name -> element indices."""
        out, offset = {}, 0
        for c in self._constraints.values():
            values = g[offset:offset + c.size]
            offset += c.size
            if c.screen is None:
                continue
            margin = np.minimum(values - c.lower, c.upper - values)
            held = np.ones(c.size, dtype=bool)
            held[c.passed] = False
            hit = margin < -self._active_tol * c.scale if broken_only else margin <= c.screen
            if np.any(hit & held):
                out[c.name] = np.flatnonzero(hit & held)
        return out

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
            mx = as_mx(expr, owner, allow_constant=True)
            if mx.shape != (1, 1):
                raise GearoptInputError(f"objective has shape {mx.shape}; limit: a scalar (1x1)")
            sc = as_elements(scale, 1, owner=owner, what="scale")
            check_positive(sc, owner=owner, what="scale")
            if (ca.is_equal(mx, self._objective, 0) and sense == self._sense
                    and float(sc[0]) == self._objective_scale):
                return       # the objective it has: no new NLP solver (building one costs as much as a solve)
            self._objective, self._sense, self._objective_scale = mx, sense, float(sc[0])
            self._opti.minimize(sense * mx / self._objective_scale)
            self._touch()


def scaled_expression(entry: VariableEntry) -> ca.MX:
    """The user-facing expression ``scale * x_s`` of a variable."""
    if np.all(entry.scale == entry.scale[0]):
        return float(entry.scale[0]) * entry.symbol
    return ca.DM(entry.scale) * entry.symbol
