"""Locate conflicting simple bounds.

CasADi's ``detect_simple_bounds`` turns every constraint that is affine in a single variable into a bound of that
variable. When two of them contradict each other (``x >= 2`` and ``x <= 1``) Ipopt refuses the problem with
``Invalid_Problem_Definition`` before iterating, so there is no iterate showing which constraints clash. This module
computes the bounds each such row implies on its variable and moves every variable with an empty interval to the
middle of the gap; at that point each conflicting constraint is violated and can be reported by name.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SimpleRow:
    """A constraint row ``lower <= e(x) <= upper`` affine in the single scaled variable ``x[target]``.

    ``value`` is ``e`` at the start point, ``slope`` is ``de/dx[target]`` (constraint units per scaled unit).
    """

    target: int
    value: float
    slope: float
    lower: float
    upper: float


def implied_interval(row: SimpleRow, x_start: float) -> tuple[float, float]:
    """The interval of the scaled variable allowed by ``row`` (``(-inf, inf)`` for a constant row)."""
    if row.slope == 0.0:
        return -np.inf, np.inf
    a = (row.lower - row.value) / row.slope + x_start
    b = (row.upper - row.value) / row.slope + x_start
    return (a, b) if row.slope > 0 else (b, a)


def separate_conflicts(x_start: np.ndarray, rows: list[SimpleRow]) -> np.ndarray:
    """Return ``x_start`` with each variable whose implied bounds are contradictory placed midway between the
    largest implied lower bound and the smallest implied upper bound (other variables unchanged)."""
    x = np.array(x_start, dtype=float)
    lo = np.full(x.size, -np.inf)
    hi = np.full(x.size, np.inf)
    for row in rows:
        a, b = implied_interval(row, x_start[row.target])
        lo[row.target] = max(lo[row.target], a)
        hi[row.target] = min(hi[row.target], b)
    clash = lo > hi
    x[clash] = 0.5 * (lo[clash] + hi[clash])
    return x
