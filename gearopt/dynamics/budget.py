"""Budgets of the torsional integrations: a step/size sanity check before integrating and a wall-time limit
between cycles, each raising :class:`~gearopt.errors.BudgetExceededError` that names the limit hit.

Why: a network with a 1e-12 kg m^2 inertia or a 1e15 N/m mesh has natural frequencies of 1e8 Hz and more; an
explicit-accuracy integrator then needs ~10 steps per period (CVODES' BDF on a stiff, non-smooth lash model) and a
single engine cycle costs billions of steps -- an apparent hang. The estimate below catches that before the first
step: steps per cycle ~ ``STEPS_PER_PERIOD`` x (highest undamped natural frequency) x (cycle duration), or the cycle
divided by the step limit ``max_step_deg`` if that is smaller. Both limits are overridable per simulator
(``simulate(..., max_steps_per_cycle=..., max_wall_time_s=...)``).
"""

from __future__ import annotations

import contextlib
import math
import time

import numpy as np

from ..errors import BudgetExceededError, GearoptInputError
from ..validation import check_int, check_range

#: Default limit of the estimated integrator steps per engine cycle (the default train: estimate ~1e4, actual ~3e4;
#: 2e5 steps take a few seconds per cycle).
DEFAULT_MAX_STEPS_PER_CYCLE = 200_000
#: Default wall-time limit of one simulation run [s] (a 10-cycle default-train run takes a few seconds).
DEFAULT_MAX_WALL_TIME_S = 900.0
#: Largest number of cycles of one run (recorded or run-in): about a day of integration for the default train.
MAX_CYCLES = 100_000
#: Steps per period of the highest mode assumed by the estimate (stiff BDF on a smooth-lash model).
STEPS_PER_PERIOD = 10.0


def check_budget_settings(max_steps_per_cycle, max_wall_time_s) -> tuple[int, float]:
    """Validated budget settings (``max_wall_time_s`` may be ``inf``: no limit)."""
    steps = check_int("max_steps_per_cycle", max_steps_per_cycle, 1, None)
    check_range("max_wall_time_s", max_wall_time_s, 0.0, None, low_inclusive=False, unit="s", allow_inf=True)
    return steps, float(max_wall_time_s)


def estimated_steps_per_cycle(network, speed_rpm: float, max_step_deg: float | None) -> tuple[float, float]:
    """(estimated integrator steps per cycle, highest undamped natural frequency [Hz]) at ``speed_rpm``."""
    try:
        f = np.asarray(network.natural_frequencies_Hz(boundary="network"), dtype=float)
    except GearoptInputError:
        raise
    except Exception:  # noqa: BLE001 - a singular network: the step limit alone is the estimate
        f = np.zeros(0)
    f_max = float(np.max(f[np.isfinite(f)])) if f.size and np.isfinite(f).any() else 0.0
    cycle_s = network.cycle_deg / (6.0 * speed_rpm)  # deg / (deg/s)
    steps = STEPS_PER_PERIOD * f_max * cycle_s
    if max_step_deg:
        steps = max(steps, network.cycle_deg / max_step_deg)
    return steps, f_max


def check_step_budget(network, speed_rpm: float, max_step_deg: float | None, max_steps_per_cycle: int) -> None:
    """Raise :class:`BudgetExceededError` (limit ``max_steps_per_cycle``) when the network's time scales would need
    more integrator steps per cycle than allowed (e.g. a tiny inertia against a stiff mesh)."""
    steps, f_max = estimated_steps_per_cycle(network, speed_rpm, max_step_deg)
    if not math.isfinite(steps) or steps > max_steps_per_cycle:
        raise BudgetExceededError(
            f"network '{network.name}' at {speed_rpm:g} rpm would need ~{steps:.3g} integrator steps per cycle "
            f"(highest natural frequency {f_max:.4g} Hz, step limit {max_step_deg} deg), beyond the budget "
            f"max_steps_per_cycle={max_steps_per_cycle}", limit="max_steps_per_cycle", value=max_steps_per_cycle,
            hint="check inertias (kg m^2) and stiffnesses (N/m, N m/rad) for unit errors, or raise "
                 "max_steps_per_cycle")


def check_wall_time(t_start: float, max_wall_time_s: float, cycle: int) -> None:
    """Raise :class:`BudgetExceededError` (limit ``max_wall_time_s``) once a run has taken longer than allowed."""
    elapsed = time.perf_counter() - t_start
    if elapsed > max_wall_time_s:
        raise BudgetExceededError(f"simulation stopped after {cycle} cycles and {elapsed:.1f} s: beyond the budget "
                                  f"max_wall_time_s={max_wall_time_s:g}", limit="max_wall_time_s",
                                  value=max_wall_time_s, hint="raise max_wall_time_s or simulate fewer cycles")


@contextlib.contextmanager
def step_limit_errors(max_num_steps: int):
    """Turn the step-limit failure (CVODES/IDAS ``max_num_steps``) of an integrator call inside the block into a
    :class:`BudgetExceededError` naming the limit; other errors pass unchanged."""
    try:
        yield
    except RuntimeError as exc:
        text = str(exc)
        if "TOO_MUCH_WORK" in text or "max_num_steps" in text or "mxstep" in text.lower():
            raise BudgetExceededError(f"the integrator hit its step limit max_num_steps={max_num_steps} within one "
                                      f"output interval", limit="max_num_steps", value=max_num_steps,
                                      hint="check the network parameters for unit errors") from exc
        raise


def integrate(integrator, x0, p, max_num_steps: int):
    """Call a CasADi integrator; its step-limit failure (CVODES/IDAS ``max_num_steps``) becomes a
    :class:`BudgetExceededError` naming the limit (:func:`step_limit_errors`)."""
    with step_limit_errors(max_num_steps):
        return integrator(x0=x0, p=p)


__all__ = ["MAX_CYCLES", "DEFAULT_MAX_STEPS_PER_CYCLE", "DEFAULT_MAX_WALL_TIME_S", "STEPS_PER_PERIOD",
           "check_budget_settings",
           "estimated_steps_per_cycle", "check_step_budget", "check_wall_time", "integrate", "step_limit_errors"]
