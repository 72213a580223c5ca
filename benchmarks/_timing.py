"""Timing and command-line helpers shared by the benchmark scripts (run as ``python benchmarks/bench_*.py``)."""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

REPEATS = 7
QUICK = False
"""Set by :func:`bench_args` for ``--quick``: every :func:`median_time` then times one call."""


def median_time(fun, repeats: int = REPEATS, budget_s: float | None = None) -> float:
    """Median wall time [s] of ``fun()`` over ``repeats`` calls (one call in quick mode); with ``budget_s``, stop
    early (after at least 3 calls) once the calls have used that much time."""
    if QUICK:
        repeats = 1
    times = []
    for i in range(repeats):
        t0 = time.perf_counter()
        fun()
        times.append(time.perf_counter() - t0)
        if budget_s is not None and i >= 2 and sum(times) > budget_s:
            break
    return statistics.median(times)


def bench_args(doc: str, argv, module_globals: dict, quick: dict) -> argparse.Namespace:
    """Parse ``--quick`` and ``--out DIR`` of a benchmark script. ``--quick`` (the test suite's mode: it runs
    and its headline ratios keep their sign, in seconds) replaces the script's module-level settings by ``quick``
    (fewer cases, repeats, points); ``--out`` replaces its ``OUT`` results directory (default
    ``benchmarks/results``; quick runs should write elsewhere, their numbers are not the published ones)."""
    global QUICK
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small settings (seconds; used by the tests)")
    parser.add_argument("--out", type=Path, default=None, help="results directory (default benchmarks/results)")
    args = parser.parse_args(argv)
    QUICK = bool(args.quick)
    if args.quick:
        module_globals.update(quick)
    if args.out is not None:
        module_globals["OUT"] = args.out
    Path(module_globals["OUT"]).mkdir(parents=True, exist_ok=True)
    return args
