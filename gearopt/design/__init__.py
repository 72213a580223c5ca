"""Design layer: the gear design problems built on the NLP framework :mod:`gearopt.nlp` -- scenes that build only
what they need, and the NLPs of the toolbox: profile-shift split, tooth counts, microgeometry, joint and blank sizing.

:class:`Scene` and its spec records (:class:`LoadCase`, :class:`DesignVariable`, :class:`Objective`,
:class:`Limit`), :func:`optimise_microgeometry`, :class:`TrainDesign`, :func:`evaluate_requirements` and
:func:`recommend` are imported from gearopt itself (``gearopt.__all__``); the
framework's names (:class:`~gearopt.nlp.Problem`, :func:`~gearopt.nlp.multistart`, ...) from :mod:`gearopt.nlp`."""

from gearopt.nlp import register_internal_package

register_internal_package(__file__)  # constraints a design NLP declares point at the caller of the design layer
from gearopt.design.microgeometry_nlp import MicrogeometryDesign, min_tip_relief_design, optimise_microgeometry
from gearopt.design.shift_distribution import optimise_shift_split
from gearopt.design.tooth_counts import (ToothCountEnumeration, ToothCountStudy, bonmin_cross_check,
                                         enumerate_tooth_counts, tooth_count_study)
from gearopt.design.joint_sizing import (JointDemand, JointSizing, PressFitSpec, TaperFitSpec, size_joint,
                                         size_press_fit, size_taper_fit, suggest_fit)
from gearopt.design.blank_sizing import BlankSizing, BlankSpec, WebDemand, size_blank, web_demand_from_loads
from gearopt.design.scene import BuiltScene, DesignVariable, Limit, LoadCase, Objective, Scene, SceneResult
from gearopt.design.scene_options import (ContactModelOptions, ContactTemperatureOptions, ExactCheckOptions,
                                          LTCAOptions, RefinementOptions, SearchOptions)
from gearopt.design.train_design import loaded_flanks, rank_tooth_counts
from gearopt.design.requirements import (DynamicPeaks, RequirementRow, RequirementsCheck, TrainDesign,
                                         evaluate_requirements, rating_headroom)
from gearopt.design.recommendation import Recommendation, design_sheet, recommend

__all__ = ["MicrogeometryDesign", "min_tip_relief_design",
           "optimise_shift_split", "ToothCountEnumeration", "ToothCountStudy", "bonmin_cross_check",
           "enumerate_tooth_counts", "tooth_count_study", "JointDemand", "JointSizing", "PressFitSpec",
           "TaperFitSpec", "size_joint", "size_press_fit", "size_taper_fit", "suggest_fit", "BlankSizing",
           "BlankSpec", "WebDemand", "size_blank", "web_demand_from_loads", "BuiltScene", "SceneResult",
           "LTCAOptions", "ContactModelOptions", "ContactTemperatureOptions", "ExactCheckOptions", "RefinementOptions",
           "SearchOptions", "loaded_flanks", "rank_tooth_counts", "DynamicPeaks", "RequirementRow", "RequirementsCheck",
           "rating_headroom", "Recommendation", "design_sheet"]
