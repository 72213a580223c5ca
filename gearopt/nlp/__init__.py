"""A small NLP framework on CasADi's ``Opti`` that knows nothing of gears.

- :class:`Problem`: named, scaled variables, parameters and constraints; a pre-solve check of the initial guess;
  typed solve failures naming the worst violated constraints and the source line that declared them; a plain-data
  :class:`ProblemResult` with variable and constraint tables (margins, multipliers, activity); a
  :class:`WarmStartPoint` of a solution to start a later solve from (in this process or another).
- :func:`multistart`: Latin-hypercube starts with every start's outcome tabled.
- :func:`solve_elastic`: the least weighted relaxation that makes an infeasible problem feasible, by constraint name.

It imports only :mod:`gearopt.numerics`, :mod:`gearopt.errors` and :mod:`gearopt.units` of gearopt (a test holds it
to that), so it can be lifted out for another field. A client library registers its own package with
:func:`register_internal_package` so that declaration sites point at *its* callers.
"""

from gearopt.nlp.entries import register_internal_package
from gearopt.nlp.precheck import Finding, InitialGuessReport, InitialGuessWarning
from gearopt.nlp.result import ProblemResult
from gearopt.nlp.elastic import ElasticResult, solve_elastic
from gearopt.nlp.multistart import MultiStartResult, multistart
from gearopt.nlp.problem import DEFAULT_CASADI_OPTIONS, DEFAULT_IPOPT_OPTIONS, Problem, WarmStartPoint
from gearopt.nlp.solver_options import WARM_START_IPOPT

__all__ = ["Problem", "WarmStartPoint", "ProblemResult", "InitialGuessReport", "InitialGuessWarning", "Finding",
           "DEFAULT_IPOPT_OPTIONS", "DEFAULT_CASADI_OPTIONS", "WARM_START_IPOPT", "ElasticResult", "solve_elastic", "MultiStartResult",
           "multistart", "register_internal_package"]
