"""Strength rating and surface temperature of gear pairs: contact stress (Hertz per the thesis, ISO 6336-2 method
B), root stress (Lewis per the thesis, ISO 6336-3 method B and its generalisation to any load point), Blok flash
temperature, a gear-material catalogue with provenance, and the complete ISO 6336 rating with computed load,
life, lubrication, size and scuffing factors (:func:`rate_iso6336`)."""

from .contact_stress import (contact_stress_iso6336, hertz_contact_stress_pair_MPa, hertz_line_contact_stress_MPa,
                             thesis_contact_stress_MPa)
from .flash_temperature import (DEFAULT_FRICTION_COEFFICIENT, contact_temperature_C, flash_temperature_blok_K,
                                flash_temperature_pair_K, rolling_velocities_m_s, sliding_velocity_m_s)
from .lewis import lewis_bending_stress_MPa, lewis_form_factor, lewis_form_factor_from_geometry
from .materials import Material, material, material_names
from .root_stress import critical_section_iso6336, root_stress_at_load_point, root_stress_iso6336
from .lubrication import DEFAULT_OIL_TEMPERATURE_C, Lubricant, default_lubricant
from .validity import RatingValidityWarning
from .deflection import ShaftSupport, beam_shaft_misalignment_um, iso6336_shaft_misalignment_um
from .scuffing import scuffing_safety_factors
from .iso6336 import ISO6336Rating, rate_iso6336
from .stiffness import (StiffnessValidityWarning, contact_line_length_mm, iso6336_stiffness, line_of_contact_stiffness,
                        mesh_damping, mesh_stiffness_table)
from .train_rating import iso6336_train_table

__all__ = [
    "contact_stress_iso6336", "hertz_contact_stress_pair_MPa", "hertz_line_contact_stress_MPa",
    "thesis_contact_stress_MPa", "contact_temperature_C", "flash_temperature_blok_K", "flash_temperature_pair_K",
    "rolling_velocities_m_s", "sliding_velocity_m_s", "lewis_bending_stress_MPa", "lewis_form_factor",
    "lewis_form_factor_from_geometry", "Material", "material", "material_names", "critical_section_iso6336",
    "root_stress_at_load_point", "root_stress_iso6336", "Lubricant", "default_lubricant", "RatingValidityWarning",
    "ShaftSupport", "beam_shaft_misalignment_um", "iso6336_shaft_misalignment_um", "scuffing_safety_factors",
    "ISO6336Rating", "iso6336_train_table", "StiffnessValidityWarning", "contact_line_length_mm", "iso6336_stiffness",
    "line_of_contact_stiffness", "mesh_damping", "mesh_stiffness_table", "DEFAULT_FRICTION_COEFFICIENT",
    "DEFAULT_OIL_TEMPERATURE_C",
]   # rate_iso6336 is imported from gearopt itself (gearopt.__all__)
