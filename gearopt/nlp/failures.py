"""Turn an unsuccessful Ipopt return status into a typed :class:`~gearopt.errors.SolveError`.

Status strings are Ipopt's ``ApplicationReturnStatus`` names as CasADi reports them in ``stats()["return_status"]``.
"""

from __future__ import annotations

from gearopt.nlp.result import ProblemResult
from gearopt.errors import InfeasibleProblemError, IterationLimitError, NumericalSolveError, SolveError

WORST_SHOWN = 5
"""How many violated constraints a solve error lists."""

INFEASIBLE_STATUSES = frozenset({"Infeasible_Problem_Detected", "Invalid_Problem_Definition"})
NOT_STARTED_STATUSES = frozenset({"Invalid_Problem_Definition", "Invalid_Option", "Not_Enough_Degrees_Of_Freedom"})
"""Statuses with which Ipopt returns before its first iteration (its iterate and iteration count are meaningless)."""
LIMIT_STATUSES = frozenset({"Maximum_Iterations_Exceeded", "Maximum_CpuTime_Exceeded", "Maximum_WallTime_Exceeded"})

_HINTS = {
    "Infeasible_Problem_Detected":
        "the named constraints below cannot all be met; relax the largest violation or widen bounds",
    "Invalid_Problem_Definition":
        "the bounds are inconsistent (constraints on a single variable become variable bounds and a lower bound "
        "exceeds an upper one); the named constraints below conflict, relax one of them",
    "Maximum_Iterations_Exceeded":
        "raise max_iter, improve the initial guess, or check the variable and constraint scales",
    "Maximum_CpuTime_Exceeded": "raise max_cpu_time, improve the initial guess, or simplify the models",
    "Maximum_WallTime_Exceeded": "raise max_wall_time, improve the initial guess, or simplify the models",
    "Restoration_Failed":
        "Ipopt could not regain feasibility from this point; try another initial guess or relax the constraints below",
    "Invalid_Number_Detected":
        "a model returned NaN/Inf during the iterations; guard sqrt/log/acos domains or tighten the variable bounds",
    "Search_Direction_Becomes_Too_Small":
        "progress stalled; check the scales of variables and constraints or loosen tol",
    "Error_In_Step_Computation":
        "the KKT system is singular or badly scaled; check for redundant constraints and the scales",
    "Not_Enough_Degrees_Of_Freedom": "more equality constraints than free variables; remove or relax equalities",
    "Diverging_Iterates": "the variables grow without bound; add bounds to the variables",
    "Invalid_Option": "an Ipopt option name or value is invalid; check the options passed to solve()",
}
_DEFAULT_HINT = "inspect the partial result (error.result) and the violated constraints; try another initial guess"


def error_class(status: str) -> type[SolveError]:
    """The :class:`SolveError` subclass for an Ipopt return status."""
    if status in INFEASIBLE_STATUSES:
        return InfeasibleProblemError
    if status in LIMIT_STATUSES:
        return IterationLimitError
    return NumericalSolveError


def hint_for(status: str) -> str:
    """A one-line hint for an Ipopt return status."""
    return _HINTS.get(status, _DEFAULT_HINT)


def solve_error(result: ProblemResult) -> SolveError:
    """Build the typed error for an unsuccessful ``result`` (status, hint, worst violated constraints, the partial
    result itself)."""
    cls = error_class(result.status)
    message = (f"problem '{result.problem}' did not solve: Ipopt stopped after {result.iterations} iterations "
               f"with objective {result.objective:.6g}")
    return cls(message, status=result.status, hint=hint_for(result.status),
               violated=result.violations(WORST_SHOWN), result=result)
