"""Tooth contact: microgeometry, mesh stiffness, tip-relief physics and loaded tooth contact analysis (LTCA).

:class:`Microgeometry`, :func:`ltca`, :class:`LTCAModel` and :func:`harris_map` are imported from gearopt itself
(``gearopt.__all__``); :func:`ltca_torques` (one design at several torques) from here; the ISO 6336-1 stiffness the
LTCA uses is in :mod:`gearopt.rating`."""

from .harris import harris_map
from .layout import MeshLayout, mesh_layout
from .ltca import LTCAResult, ltca, ltca_torques
from .ltca_smooth import LTCAModel, SmoothLTCAResult
from .ltca_macro import MacroLTCAModel, MacroLTCAResult
from .microgeometry import Microgeometry
from .potential_energy import (ANCHOR_CONVENTIONS, PotentialEnergyOptions, potential_energy_mesh_stiffness,
                               potential_energy_single_stiffness, potential_energy_stiffness_profile)
from .tip_relief import governing_tip_relief_um, min_tip_relief_table, min_tip_relief_um

__all__ = ["MeshLayout", "mesh_layout", "LTCAResult", "ltca_torques", "SmoothLTCAResult", "MacroLTCAModel",
           "MacroLTCAResult",
           "ANCHOR_CONVENTIONS", "PotentialEnergyOptions", "potential_energy_mesh_stiffness",
           "potential_energy_single_stiffness", "potential_energy_stiffness_profile", "governing_tip_relief_um",
           "min_tip_relief_table", "min_tip_relief_um"]
