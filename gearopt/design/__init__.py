"""Design layer: :class:`Problem`, a named, scaled wrapper of ``casadi.Opti`` with a pre-solve check, typed solve
failures and a plain-data :class:`ProblemResult`."""

from gearopt.design.precheck import Finding, InitialGuessReport, InitialGuessWarning
from gearopt.design.problem import DEFAULT_CASADI_OPTIONS, DEFAULT_IPOPT_OPTIONS, Problem
from gearopt.design.result import ProblemResult
from gearopt.design.microgeometry_nlp import MicrogeometryDesign, min_tip_relief_design, optimise_microgeometry

__all__ = ["Problem", "ProblemResult", "InitialGuessReport", "InitialGuessWarning", "Finding",
           "DEFAULT_IPOPT_OPTIONS", "DEFAULT_CASADI_OPTIONS", "optimise_microgeometry", "MicrogeometryDesign",
           "min_tip_relief_design"]
