"""Shaft-hub joints (thesis sec. 3.11): press fits (Lame/DIN 7190 elastic), nut-clamped taper fits (cone-clutch
analogy), bolt preload from nut torque, ISO 286 fit interference, and the walk-off thrust of helical meshes with the
joints' slip margins. Every model is dual-typed (floats, numpy arrays, CasADi symbols)."""

from .bolt import (
    NUT_FACTORS,
    bolt_preload,
    bolt_preload_N,
    nut_factor_from_friction,
    nut_factor_range,
    nut_torque_Nm,
    thread_stress_area_mm2,
)
from .catalogue import JointCapacity, joint_capacities, joint_capacity
from .iso286 import fit_interference_um, hole_deviations_um, shaft_deviations_um, tolerance_grade_um
from .press_fit import (
    PressFitResult,
    centrifugal_interference_loss_um,
    lame_compliance_mm_per_MPa,
    press_fit,
    press_fit_pressure_MPa,
    roughness_smoothing_loss_um,
    shrink_fit_assembly_temperature_C,
    thermal_interference_change_um,
)
from .taper_fit import TaperFitResult, cone_friction_radius_mm, taper_fit, taper_slip_utilisation
from .walk_off import (
    WalkOffResult,
    gear_rotation_signs,
    joint_margins,
    margin_history,
    mesh_axial_force_N,
    press_fit_slip_utilisation,
    quasi_static_mesh_torques_Nm,
    walk_off,
    working_helix_angle_deg,
)

__all__ = [
    # press_fit, taper_fit and walk_off are imported from gearopt itself (gearopt.__all__)
    "PressFitResult", "press_fit_pressure_MPa", "lame_compliance_mm_per_MPa", "roughness_smoothing_loss_um",
    "thermal_interference_change_um", "centrifugal_interference_loss_um", "shrink_fit_assembly_temperature_C",
    "TaperFitResult", "cone_friction_radius_mm", "taper_slip_utilisation",
    "NUT_FACTORS", "nut_factor_range", "bolt_preload_N", "nut_torque_Nm", "nut_factor_from_friction",
    "thread_stress_area_mm2", "bolt_preload",
    "fit_interference_um", "hole_deviations_um", "shaft_deviations_um", "tolerance_grade_um",
    "WalkOffResult", "gear_rotation_signs", "mesh_axial_force_N", "working_helix_angle_deg",
    "quasi_static_mesh_torques_Nm", "press_fit_slip_utilisation", "joint_margins", "margin_history",
    "joint_capacity", "joint_capacities", "JointCapacity",
]
