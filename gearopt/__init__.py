"""gearopt: exact, differentiable gear-train design models on CasADi, optimised with Ipopt."""

from . import numerics
from .errors import (GearoptError, GearoptInputError, GeometryError, SolveError, InfeasibleProblemError,
                     IterationLimitError, NumericalSolveError, BadInitialGuessError, NonFiniteResultError,
                     BudgetExceededError, DataFileError, MissingSectionError)
from .geometry import (GearPair, GearSpec, GearTrain, MeshSpec, PairTolerances, RackSpec, iso_tr_4467_shift_limits,
                       shift_split_iso_tr_4467)
from .data import load_default_train, load_default_data, load_system, System

__version__ = "0.1.0"
from .contact import LTCAModel, Microgeometry, harris_map, iso6336_stiffness, ltca, min_tip_relief_um
from .rating import (contact_stress_iso6336, flash_temperature_blok_K, lewis_bending_stress_MPa, lewis_form_factor,
                     material, root_stress_at_load_point, root_stress_iso6336)
from .engine import AccessoryTorque, CylinderPressure, EngineExcitation, crank_torque, peak_pressure_bar, slider_crank
from .joints import (bolt_preload_N, fit_interference_um, joint_margins, press_fit, quasi_static_mesh_torques_Nm,
                     taper_fit, walk_off)
from .blank import GearBlank, web_fatigue, web_stress
from .dynamics import (MeshStiffnessShape, PeriodicStateError, TorsionalNetwork,
                       node_accelerations, walk_off_history)
from .dynamics.ltca_stiffness import ltca_mesh_stiffness
from .report.dynamics_figures import campbell_table, plot_campbell
from .design import (DesignVariable, Limit, LoadCase, Objective, Problem, Scene, enumerate_tooth_counts,
                     optimise_microgeometry, optimise_shift_split, size_blank, size_joint, tooth_count_study)
