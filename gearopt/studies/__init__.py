"""Studies: multi-model comparisons and sweeps built on the model and design layers (plain-data results)."""

from .contact_study import DESIGNS, MeshContactStudy, mesh_contact_study

__all__ = ["mesh_contact_study", "MeshContactStudy", "DESIGNS"]
