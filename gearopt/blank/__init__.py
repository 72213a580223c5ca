"""Gear blank and web (thesis sec. 3.10): closed-form mass and inertia of solid, webbed and pocketed blanks, the
rim backup ratio, a simple web stress and Goodman / equivalent-fully-reversed fatigue margins for forward, reverse
and forward-reverse loading. Dual-typed (inertia reduction can be an NLP objective)."""

from .blank import GearBlank, annulus_inertia_kgm2, annulus_mass_kg, rim_backup_ratio, rim_thickness_factor
from .catalogue import blank_from_data
from .web import (
           clamped_annular_plate_moment_Nmm_per_mm,
           forward_reverse_from_history,
           goodman_equivalent_fully_reversed_MPa,
           web_fatigue,
           web_stress,
           web_torsion_shear_MPa,
           web_transverse_shear_MPa,
)

__all__ = ["GearBlank", "annulus_mass_kg", "annulus_inertia_kgm2", "rim_backup_ratio", "rim_thickness_factor",
           "blank_from_data", "web_stress", "web_fatigue", "web_torsion_shear_MPa", "web_transverse_shear_MPa",
           "clamped_annular_plate_moment_Nmm_per_mm", "goodman_equivalent_fully_reversed_MPa",
           "forward_reverse_from_history"]
