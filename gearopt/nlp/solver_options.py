"""Solver options of a :class:`~gearopt.nlp.problem.Problem` solve: the defaults, and the merge of the caller's
overrides with range checks on the budget and tolerance options."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from gearopt.errors import GearoptInputError

DEFAULT_IPOPT_OPTIONS: dict[str, Any] = {
    "print_level": 0, "sb": "yes", "max_iter": 1000, "tol": 1e-8, "mu_strategy": "adaptive", "max_wall_time": 600.0}
"""Ipopt options used unless overridden by keyword arguments of :meth:`~gearopt.nlp.problem.Problem.solve`. The
budgets ``max_iter`` and ``max_wall_time`` [s] stop a solve that does not converge with
:class:`~gearopt.errors.IterationLimitError` (status ``Maximum_Iterations_Exceeded`` / ``Maximum_WallTime_Exceeded``,
naming the option to raise)."""

WARM_START_IPOPT: dict[str, Any] = {
    "warm_start_init_point": "yes", "warm_start_bound_push": 1e-6, "warm_start_mult_bound_push": 1e-6,
    "mu_init": 1e-4}
"""Ipopt options of a solve warm-started from a solution's multipliers (``Problem.solve(warm_start=point)`` with a
:class:`~gearopt.nlp.problem.WarmStartPoint`): Ipopt takes the given multipliers (``warm_start_init_point``), moves
the start and the multipliers off their bounds by little, and begins with a small barrier parameter instead of
re-centring far from a start that is already near an optimum."""

DEFAULT_CASADI_OPTIONS: dict[str, Any] = {
    "print_time": False, "record_time": True, "detect_simple_bounds": True}
"""CasADi ``nlpsol`` options. ``detect_simple_bounds`` hands variable bounds (and constraints affine in a single
variable) to Ipopt as true bounds, which its iterates never leave; ``record_time`` gives the solve wall time."""


def solver_options(verbose: bool, casadi_options: dict[str, Any] | None,
                   ipopt_options: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """Merge defaults and overrides; return (Ipopt options by Ipopt name, full ``nlpsol`` option dict)."""
    ipopt = dict(DEFAULT_IPOPT_OPTIONS)
    if verbose:
        ipopt["print_level"] = 5
    ipopt.update({key.removeprefix("ipopt."): value for key, value in ipopt_options.items()})
    check_budget_options(ipopt)
    plugin = dict(DEFAULT_CASADI_OPTIONS)
    if verbose:
        plugin["print_time"] = True
    plugin.update(casadi_options or {})
    plugin.update({f"ipopt.{key}": value for key, value in ipopt.items()})
    return ipopt, plugin


def check_budget_options(ipopt: dict[str, Any]) -> None:
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
