"""Typed errors of gearopt.

Bad input and impossible geometry raise subclasses of :class:`GearoptInputError` (itself a ``ValueError``) whose
message names the parameter, the value and the limit. Failed solves raise subclasses of :class:`SolveError` carrying
Ipopt's return status, a hint, and the worst violated constraints by name.
"""

from __future__ import annotations

from dataclasses import dataclass


class GearoptError(Exception):
    """Base class of every error gearopt raises on purpose."""


class GearoptInputError(GearoptError, ValueError):
    """An argument is outside its admissible range (message: parameter, value, limit)."""


class GeometryError(GearoptInputError):
    """Gear geometry that cannot exist: undercut, pointed tip, interference, contact ratio < 1, unreachable centre
    distance, a profile shift outside its limits."""


@dataclass
class ViolatedConstraint:
    """One constraint of a failed solve with its violation in the constraint's own units."""

    name: str
    violation: float
    value: float
    lower: float
    upper: float
    source: str = ""

    def __str__(self) -> str:
        where = f"  [{self.source}]" if self.source else ""
        return (f"{self.name}: value {self.value:.6g} outside [{self.lower:.6g}, {self.upper:.6g}] "
                f"by {self.violation:.3g}{where}")


class SolveError(GearoptError, RuntimeError):
    """An NLP solve did not converge. ``status`` is Ipopt's return status; ``violated`` lists the worst violated
    constraints (largest first) at the last iterate; ``hint`` suggests what to try."""

    def __init__(self, message: str, *, status: str = "", hint: str = "",
                 violated: list[ViolatedConstraint] | None = None, result=None):
        self.status = status
        self.hint = hint
        self.violated = list(violated or [])
        self.result = result
        lines = [message]
        if status:
            lines.append(f"Ipopt status: {status}")
        if self.violated:
            lines.append("Worst violated constraints:")
            lines.extend(f"  - {v}" for v in self.violated)
        if hint:
            lines.append(f"Hint: {hint}")
        super().__init__("\n".join(lines))


class InfeasibleProblemError(SolveError):
    """Ipopt converged to a point of local infeasibility: the constraints cannot all be met."""


class IterationLimitError(SolveError):
    """Ipopt stopped at its iteration or time limit before converging."""


class NumericalSolveError(SolveError):
    """Ipopt failed for numerical reasons (restoration failure, NaN/Inf in evaluation, too-small step)."""


class NonFiniteResultError(GearoptInputError):
    """A public result would hold NaN (or an infinity where none is meaningful): the message names the quantity and
    the inputs that led there. Raised instead of returning the NaN (:func:`gearopt.validation.check_result`)."""


class BudgetExceededError(SolveError):
    """A computation hit its budget (wall time, integrator steps, problem size) before finishing. ``limit`` names the
    budget (e.g. ``"max_wall_time_s"``), ``value`` its setting; the message says how to raise it."""

    def __init__(self, message: str, *, limit: str = "", value=None, hint: str = "", **kw):
        self.limit = limit
        self.value = value
        super().__init__(message, hint=hint, **kw)


class DataFileError(GearoptInputError):
    """A data file cannot be read or does not follow the data schema: the message names the file and, for schema
    problems, every offending key path (``docs/data-schema.md``)."""


class MissingSectionError(DataFileError):
    """A study needs a section (or key) the data file does not have: the message names the file, the section and
    what needs it."""


class BadInitialGuessError(GearoptInputError):
    """The pre-solve check found NaN/Inf or inverted bounds at the initial guess (names listed in the message)."""


__all__ = [
    # GearoptError, GearoptInputError and SolveError are imported from gearopt itself (gearopt.__all__)
    "GeometryError", "ViolatedConstraint", "InfeasibleProblemError", "IterationLimitError", "NumericalSolveError",
    "BadInitialGuessError",
    "NonFiniteResultError", "BudgetExceededError", "DataFileError",
]
