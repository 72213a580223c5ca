"""Plain-data result of a :class:`~gearopt.nlp.problem.Problem` solve: values, tables, report.

Sign convention of every multiplier reported here: it is the sensitivity of the optimal objective (``res.objective``,
in the objective's units) to the bound that is active, per unit of the constrained quantity,
``multiplier = d objective* / d bound``. For a minimisation an active lower bound has a positive multiplier and an
active upper bound a negative one (for a maximisation the signs flip). An inactive constraint has multiplier ~0.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np
import pandas as pd

from gearopt.nlp.entries import ConstraintEntry, VariableEntry, element_names
from gearopt.errors import ViolatedConstraint

Number = float | np.ndarray

CONSTRAINT_COLUMNS = ["name", "base", "value", "lower", "upper", "margin", "multiplier", "active", "scale", "unit",
                      "source"]
VARIABLE_COLUMNS = ["name", "base", "value", "init", "lower", "upper", "at_bound", "multiplier", "scale", "unit",
                    "source"]


@dataclass
class ProblemResult:
    """Outcome of one solve (successful or not), as plain data.

    Attributes:
        problem: name of the problem.
        status: Ipopt's return status string (``"Solve_Succeeded"``, ``"Infeasible_Problem_Detected"`` ...).
        success: True when Ipopt reports success (including ``Solved_To_Acceptable_Level``).
        objective: objective value at the returned point, in the objective's own (unscaled) units.
        iterations: Ipopt iteration count.
        solve_time_s: wall-clock time of the Ipopt run, s.
        build_time_s: wall-clock time spent building since the previous solve (declarations, pre-solve check,
            CasADi's solver construction), s. Close to zero for a re-solve of an unchanged problem.
        values: variable name -> value in the variable's units (float for scalars, 1-D array for vectors).
        parameters: parameter name -> value used in this solve.
        multipliers: constraint name -> multiplier (see the module docstring for units and sign).
        constraints: one row per constraint element: name (``c`` or ``c[i]``), base (declared name), value,
            lower, upper (±inf if absent), margin (distance to the nearest bound in the constraint's units,
            negative if violated), multiplier, active, scale, unit, source (``file:line`` of the declaration).
        variables: one row per variable element: name, base, value, init (start guess of this solve), lower,
            upper, at_bound, multiplier (of the variable bounds), scale, unit, source.
        active_tol: tolerance in scaled units used for ``active`` and ``at_bound``.
        exchanges: re-solves of the exchange of screened constraints (:meth:`~gearopt.nlp.problem.Problem.subject_to`
            ``screen``); ``iterations`` and ``solve_time_s`` count every run.
    """

    problem: str
    status: str
    success: bool
    objective: float
    iterations: int
    solve_time_s: float
    build_time_s: float
    values: dict[str, Number]
    parameters: dict[str, Number]
    multipliers: dict[str, Number]
    constraints: pd.DataFrame = field(repr=False)
    variables: pd.DataFrame = field(repr=False)
    active_tol: float = 1e-6
    exchanges: int = 0
    _evaluate: Callable[[Any], np.ndarray] | None = field(default=None, repr=False, compare=False)

    def value(self, expr: Any) -> Number:
        """Value of ``expr`` at this result's point: a variable or parameter name, or any CasADi expression built
        from the problem's variables and parameters. Returns a float for a scalar, an array otherwise."""
        if isinstance(expr, str):
            if expr in self.values:
                return self.values[expr]
            if expr in self.parameters:
                return self.parameters[expr]
            raise KeyError(f"no variable or parameter named {expr!r} in problem '{self.problem}'")
        if self._evaluate is None:
            raise RuntimeError("this result carries no evaluator (it was built without its problem)")
        out = np.asarray(self._evaluate(expr), dtype=float)
        if out.size == 1:
            return float(out.ravel()[0])
        return out.ravel() if 1 in out.shape else out

    def violations(self, n: int | None = None) -> list[ViolatedConstraint]:
        """Violated constraint and variable-bound elements, worst first, at most ``n`` (see
        :func:`violations_from_tables`)."""
        return violations_from_tables(self.constraints, self.variables, self.active_tol, n)

    def report(self) -> str:
        """Readable text report: status line, objective, timings, variable table and constraint table."""
        state = "converged" if self.success else "FAILED"
        exchanged = (f" ({self.exchanges} re-solve{'s' if self.exchanges > 1 else ''} exchanging screened rows)"
                     if self.exchanges else "")
        lines = [f"Problem '{self.problem}': {self.status} ({state}) after {self.iterations} iterations{exchanged}",
                 f"  objective      {self.objective:.8g}",
                 f"  build / solve  {self.build_time_s:.3g} s / {self.solve_time_s:.3g} s", ""]
        if self.parameters:
            lines.append("Parameters")
            lines.extend(f"  {k} = {_fmt_value(v)}" for k, v in self.parameters.items())
            lines.append("")
        lines.append("Variables")
        lines.append(_table_text(self.variables, ["name", "value", "lower", "upper", "at_bound", "multiplier",
                                                  "unit"]))
        lines.append("")
        lines.append("Constraints (active: at a bound with a nonzero multiplier; multiplier = d objective/d bound)")
        lines.append(_table_text(self.constraints, ["name", "value", "lower", "upper", "margin", "multiplier",
                                                    "active", "unit", "source"]))
        worst = self.violations(5)
        if worst:
            lines.append("")
            lines.append("Violated")
            lines.extend(f"  - {v}" for v in worst)
        return "\n".join(lines)


def constraint_table(constraints: list[ConstraintEntry], g: np.ndarray, lam_g: np.ndarray, *,
                     objective_factor: float, tol: float) -> pd.DataFrame:
    """Build the constraint table.

    Args:
        constraints: constraint records in declaration order.
        g: unscaled constraint values, all elements stacked in declaration order.
        lam_g: Opti's multiplier vector (CasADi sign convention, scaled problem).
        objective_factor: ``-sense * objective_scale`` turning a scaled CasADi multiplier into
            ``d objective / d bound`` once divided by the constraint scale.
        tol: activity tolerance in scaled units (margin and multiplier).
    """
    names, bases, units, sources = [], [], [], []
    columns: dict[str, list[np.ndarray]] = {k: [] for k in ("value", "lower", "upper", "lam", "scale")}
    offset = 0
    for c in constraints:
        lam = np.zeros(c.size)
        lam[c.passed] = lam_g[c.rows]
        columns["value"].append(np.asarray(g[offset:offset + c.size], dtype=float))
        offset += c.size
        for key, v in (("lower", c.lower), ("upper", c.upper), ("scale", c.scale), ("lam", lam)):
            columns[key].append(np.asarray(v, dtype=float).reshape(-1)[:c.size])
        names += c.element_names()
        bases += [c.name] * c.size
        units += [c.unit] * c.size
        sources += [c.source] * c.size
    if not names:
        return pd.DataFrame([], columns=CONSTRAINT_COLUMNS)
    value, lower, upper, lam, scale = (np.concatenate(columns[k]) for k in ("value", "lower", "upper", "lam",
                                                                              "scale"))
    margin = np.minimum(value - lower, upper - value)
    return pd.DataFrame({"name": names, "base": bases, "value": value, "lower": lower, "upper": upper,
                         "margin": margin, "multiplier": objective_factor * lam / scale,
                         "active": (np.abs(margin) <= tol * scale) & (np.abs(lam) > tol), "scale": scale,
                         "unit": units, "source": sources}, columns=CONSTRAINT_COLUMNS)


def variable_table(variables: list[VariableEntry], values: dict[str, np.ndarray], inits: dict[str, np.ndarray],
                   lam_g: np.ndarray, *, objective_factor: float, tol: float) -> pd.DataFrame:
    """Build the variable table (values and ``inits`` in variable units, keyed by name; other arguments as in
    :func:`constraint_table`). The multiplier is that of the variable's bounds, 0 for a free variable."""
    if not variables:
        return pd.DataFrame([], columns=VARIABLE_COLUMNS)
    columns: dict[str, list] = {k: [] for k in VARIABLE_COLUMNS}
    for v in variables:
        x = np.asarray(values[v.name], dtype=float).reshape(-1)[:v.size]
        lower, upper, scale = (np.asarray(a, dtype=float).reshape(-1)[:v.size] for a in (v.lower, v.upper, v.scale))
        lam = np.asarray(lam_g[v.bound_rows], dtype=float) if v.bound_rows is not None else np.zeros(v.size)
        columns["name"] += element_names(v.name, v.size, v.vector)
        columns["base"] += [v.name] * v.size
        columns["value"].append(x)
        columns["init"].append(np.asarray(inits[v.name], dtype=float).reshape(-1)[:v.size])
        columns["lower"].append(lower)
        columns["upper"].append(upper)
        columns["at_bound"].append(np.minimum(np.abs(x - lower), np.abs(upper - x)) <= tol * scale)
        columns["multiplier"].append(objective_factor * lam / scale)
        columns["scale"].append(scale)
        columns["unit"] += [v.unit] * v.size
        columns["source"] += [v.source] * v.size
    return pd.DataFrame({k: (np.concatenate(c) if c and isinstance(c[0], np.ndarray) else c)
                         for k, c in columns.items()}, columns=VARIABLE_COLUMNS)


def multipliers_by_name(constraints: list[ConstraintEntry], table: pd.DataFrame) -> dict[str, Number]:
    """Constraint name -> multiplier (float for a scalar constraint, array for a vector one)."""
    out: dict[str, Number] = {}
    offset = 0
    column = table["multiplier"].to_numpy()
    for c in constraints:
        block = column[offset:offset + c.size].copy()
        offset += c.size
        out[c.name] = block if c.vector else float(block[0])
    return out


def violations_from_tables(constraints: pd.DataFrame, variables: pd.DataFrame | None, tol: float,
                           n: int | None = None) -> list[ViolatedConstraint]:
    """Violated elements of a constraint table and (optionally) of a variable table's bounds, worst first.

    An element counts when its violation exceeds ``tol * scale``; elements are ranked by violation / scale (the
    quantity Ipopt sees) and reported with their violation in their own units. Variable rows are named
    ``"<name> (bounds)"``. Non-finite values are not counted (the pre-solve check reports those).
    """
    tables = [(constraints, "")] + ([(variables, " (bounds)")] if variables is not None else [])
    ratios, rows = [], []
    for t, (table, suffix) in enumerate(tables):
        value, lower, upper, scale = (table[k].to_numpy(dtype=float) for k in ("value", "lower", "upper", "scale"))
        with np.errstate(invalid="ignore"):                       # inf - inf: NaN, not counted
            below, above = lower - value, value - upper
        violation = np.where(above > below, above, below)          # max(below, above, 0) as Python's max orders
        violation = np.where(0.0 > violation, 0.0, violation)      # it: a NaN value is never counted
        hit = np.flatnonzero(violation > tol * scale)
        ratios.append(violation[hit] / scale[hit])
        rows += [(t, int(i), float(violation[i])) for i in hit]
    if not rows:
        return []
    ranked = np.argsort(-np.concatenate(ratios), kind="stable")[:n]      # worst first, ties in table order
    columns = [{k: table[k].to_numpy() for k in ("name", "value", "lower", "upper", "source")} for table, _ in tables]
    out = []
    for j in ranked:
        t, i, violation = rows[j]
        c = columns[t]
        out.append(ViolatedConstraint(f"{c['name'][i]}{tables[t][1]}", violation, float(c["value"][i]),
                                      float(c["lower"][i]), float(c["upper"][i]), c["source"][i]))
    return out


def _fmt_number(v: float) -> str:
    if np.isinf(v):
        return "-"
    return f"{v + 0.0:.6g}"


def _fmt_value(v: Number) -> str:
    arr = np.atleast_1d(np.asarray(v, dtype=float))
    text = ", ".join(_fmt_number(x) for x in arr)
    return f"[{text}]" if np.ndim(v) else text


def _table_text(table: pd.DataFrame, columns: list[str]) -> str:
    if table.empty:
        return "  (none)"
    shown = table[columns].copy()
    for col in columns:
        if pd.api.types.is_bool_dtype(shown[col]):
            shown[col] = shown[col].map({True: "yes", False: ""})
        elif pd.api.types.is_float_dtype(shown[col]):
            shown[col] = shown[col].map(_fmt_number)
    text = shown.to_string(index=False)
    return "\n".join("  " + line for line in text.splitlines())
