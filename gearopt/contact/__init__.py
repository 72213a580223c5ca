"""Tooth contact: microgeometry, mesh stiffness, tip-relief physics and loaded tooth contact analysis (LTCA)."""

from .harris import harris_map
from .layout import MeshLayout, mesh_layout
from .ltca import LTCAResult, ltca
from .ltca_smooth import LTCAModel, SmoothLTCAResult
from .ltca_macro import MacroLTCAModel, MacroLTCAResult
from .microgeometry import Microgeometry
from .potential_energy import (ANCHOR_CONVENTIONS, PotentialEnergyOptions, potential_energy_mesh_stiffness,
                               potential_energy_single_stiffness, potential_energy_stiffness_profile)
from ..rating.stiffness import (StiffnessValidityWarning, contact_line_length_mm, iso6336_stiffness, line_of_contact_stiffness,
                        mesh_damping, mesh_stiffness_table)
from .tip_relief import governing_tip_relief_um, min_tip_relief_table, min_tip_relief_um
