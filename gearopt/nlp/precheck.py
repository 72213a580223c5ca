"""Pre-solve check of a problem at its initial guess.

Ipopt stops at iteration 0 with ``Invalid_Number_Detected`` and no hint of *which* model produced the NaN. This
module evaluates every named constraint, the objective and their first derivatives at the point Ipopt will start
from and reports the offenders by name and declaration line, before Ipopt is called.

The start point mimics Ipopt's own projection of the initial guess into the variable bounds (options ``bound_push``
and ``bound_frac``, Ipopt implementation paper, Waechter & Biegler 2006, section 3.6), so a guess sitting exactly on
a bound (e.g. ``x = 0`` for ``sqrt(x)``) is judged where Ipopt really evaluates it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from gearopt.nlp.entries import ConstraintEntry, VariableEntry, element_names
from gearopt.errors import BadInitialGuessError, ViolatedConstraint

IPOPT_BOUND_PUSH = 1e-2
"""Ipopt's default ``bound_push`` (relative distance of the start point from a bound)."""
IPOPT_BOUND_FRAC = 1e-2
"""Ipopt's default ``bound_frac`` (fraction of the bound interval)."""


class InitialGuessWarning(UserWarning):
    """The initial guess has a questionable but admissible feature (e.g. a variable outside its bounds)."""


@dataclass(frozen=True)
class Finding:
    """One element flagged by the pre-solve check."""

    name: str
    detail: str
    source: str = ""

    def __str__(self) -> str:
        where = f"  [{self.source}]" if self.source else ""
        return f"{self.name}: {self.detail}{where}"


@dataclass
class InitialGuessReport:
    """Outcome of :meth:`Problem.check_initial_guess`.

    ``nonfinite_values`` and ``nonfinite_derivatives`` are errors (the solve would fail at once);
    ``outside_bounds`` and ``violated`` are informative (Ipopt moves the start inside the bounds and is allowed to
    start infeasible).
    """

    problem: str
    nonfinite_values: list[Finding] = field(default_factory=list)
    nonfinite_derivatives: list[Finding] = field(default_factory=list)
    outside_bounds: list[Finding] = field(default_factory=list)
    violated: list[ViolatedConstraint] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """True when every constraint, the objective and their derivatives are finite at the start point."""
        return not (self.nonfinite_values or self.nonfinite_derivatives)

    @property
    def names(self) -> list[str]:
        """Names of the elements with a non-finite value or derivative."""
        return [f.name for f in self.nonfinite_values + self.nonfinite_derivatives]

    def __str__(self) -> str:
        lines = [f"Initial guess check of problem '{self.problem}': "
                 + ("passed" if self.ok else "non-finite values at the initial guess")]
        sections = [("NaN/Inf value", self.nonfinite_values), ("NaN/Inf derivative", self.nonfinite_derivatives),
                    ("Outside bounds (Ipopt moves them inside)", self.outside_bounds)]
        for title, items in sections:
            if items:
                lines.append(f"{title}:")
                lines.extend(f"  - {f}" for f in items)
        if self.violated:
            lines.append(f"Violated at the initial guess (allowed): {len(self.violated)} element(s), worst:")
            lines.extend(f"  - {v}" for v in self.violated[:5])
        return "\n".join(lines)

    def raise_if_bad(self) -> None:
        """Raise :class:`BadInitialGuessError` listing the offending names if the check failed."""
        if not self.ok:
            hint = ("Hint: move the initial guess into the models' domains (e.g. sqrt/log arguments > 0) "
                    "or tighten the variable bounds.")
            raise BadInitialGuessError(f"{self}\n{hint}")

    def warn_if_outside_bounds(self) -> None:
        """Emit an :class:`InitialGuessWarning` naming the variables whose initial guess is outside its bounds."""
        if self.outside_bounds:
            names = ", ".join(f.name for f in self.outside_bounds)
            warnings.warn(f"problem '{self.problem}': initial guess outside the bounds of {names}; "
                          f"Ipopt will move it inside", InitialGuessWarning, stacklevel=3)


def ipopt_start_point(x0: np.ndarray, lower: np.ndarray, upper: np.ndarray, *,
                      bound_push: float = IPOPT_BOUND_PUSH, bound_frac: float = IPOPT_BOUND_FRAC) -> np.ndarray:
    """Project ``x0`` into ``[lower + p_L, upper - p_U]`` as Ipopt does before its first iteration.

    ``p_L = min(bound_push * max(1, |lower|), bound_frac * (upper - lower))`` (the second term only with both bounds),
    likewise ``p_U``. Works in whatever units the arrays share; Ipopt applies it to the scaled variables.
    """
    x = np.array(x0, dtype=float)
    has_lo, has_hi = np.isfinite(lower), np.isfinite(upper)
    with np.errstate(invalid="ignore"):
        width = np.where(has_lo & has_hi, upper - lower, np.inf)
        push_lo = np.minimum(bound_push * np.maximum(1.0, np.abs(lower)), bound_frac * width)
        push_hi = np.minimum(bound_push * np.maximum(1.0, np.abs(upper)), bound_frac * width)
        x = np.where(has_lo, np.maximum(x, lower + push_lo), x)
        x = np.where(has_hi, np.minimum(x, upper - push_hi), x)
    return x


def outside_bounds(variables: list[VariableEntry], values: dict[str, np.ndarray]) -> list[Finding]:
    """Variable elements whose value lies outside ``[lower, upper]`` (variable units)."""
    found = []
    for v in variables:
        x = values[v.name]
        for label, xi, lo, hi in zip(element_names(v.name, v.size, v.vector), x, v.lower, v.upper):
            if xi < lo or xi > hi:
                found.append(Finding(label, f"init {xi:.6g} outside [{lo:.6g}, {hi:.6g}]", v.source))
    return found


def nonfinite(constraints: list[ConstraintEntry], g: np.ndarray, objective: float, kind: str) -> list[Finding]:
    """Constraint elements (rows of ``g`` in declaration order) and the objective that are NaN/Inf.

    ``kind`` is the word used in the message ("value" or "derivative").
    """
    found = []
    offset = 0
    for c in constraints:
        block = np.asarray(g[offset:offset + c.size], dtype=float)
        offset += c.size
        bad = np.flatnonzero(~np.isfinite(block))
        if bad.size:
            names = c.element_names()
            found += [Finding(names[i], f"{kind} is {block[i]} at the initial guess", c.source) for i in bad]
    if not np.isfinite(objective):
        found.append(Finding("objective", f"{kind} is {objective} at the initial guess"))
    return found
