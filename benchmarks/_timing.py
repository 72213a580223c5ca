"""Timing helper shared by the benchmark scripts (run as ``python benchmarks/bench_*.py``)."""

from __future__ import annotations

import statistics
import time

REPEATS = 7


def median_time(fun, repeats: int = REPEATS, budget_s: float | None = None) -> float:
    """Median wall time [s] of ``fun()`` over ``repeats`` calls; with ``budget_s``, stop early (after at least 3
    calls) once the calls have used that much time."""
    times = []
    for i in range(repeats):
        t0 = time.perf_counter()
        fun()
        times.append(time.perf_counter() - t0)
        if budget_s is not None and i >= 2 and sum(times) > budget_s:
            break
    return statistics.median(times)
