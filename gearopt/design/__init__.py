"""Design layer: :class:`Problem` (a named, scaled wrapper of ``casadi.Opti`` with a pre-solve check, typed solve
failures, multi-start and an elastic mode), scenes that build only what they need, and the NLPs of the toolbox:
profile-shift split, tooth counts, microgeometry, joint and blank sizing."""

from gearopt.design.precheck import Finding, InitialGuessReport, InitialGuessWarning
from gearopt.design.problem import DEFAULT_CASADI_OPTIONS, DEFAULT_IPOPT_OPTIONS, Problem
from gearopt.design.result import ProblemResult
from gearopt.design.elastic import ElasticResult, solve_elastic
from gearopt.design.multistart import MultiStartResult, multistart
from gearopt.design.microgeometry_nlp import MicrogeometryDesign, min_tip_relief_design, optimise_microgeometry
from gearopt.design.shift_distribution import optimise_shift_split
from gearopt.design.tooth_counts import (ToothCountEnumeration, ToothCountStudy, bonmin_cross_check,
                                         enumerate_tooth_counts, tooth_count_study)
from gearopt.design.joint_sizing import (JointDemand, JointSizing, PressFitSpec, TaperFitSpec, size_joint,
                                         size_press_fit, size_taper_fit, suggest_fit)
from gearopt.design.blank_sizing import BlankSizing, BlankSpec, WebDemand, size_blank, web_demand_from_loads
from gearopt.design.scene import BuiltScene, DesignVariable, Limit, LoadCase, Objective, Scene, SceneResult

__all__ = ["Problem", "ProblemResult", "InitialGuessReport", "InitialGuessWarning", "Finding",
           "DEFAULT_IPOPT_OPTIONS", "DEFAULT_CASADI_OPTIONS", "ElasticResult", "solve_elastic", "MultiStartResult",
           "multistart", "optimise_microgeometry", "MicrogeometryDesign", "min_tip_relief_design",
           "optimise_shift_split", "ToothCountEnumeration", "ToothCountStudy", "bonmin_cross_check",
           "enumerate_tooth_counts", "tooth_count_study", "JointDemand", "JointSizing", "PressFitSpec",
           "TaperFitSpec", "size_joint", "size_press_fit", "size_taper_fit", "suggest_fit", "BlankSizing",
           "BlankSpec", "WebDemand", "size_blank", "web_demand_from_loads", "Scene", "BuiltScene", "SceneResult",
           "LoadCase", "DesignVariable", "Objective", "Limit"]
