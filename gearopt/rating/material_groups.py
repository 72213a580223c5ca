"""ISO 6336 material groups of the catalogue materials (the abbreviations the standard's factor tables use).

ISO 6336-1/-2/-3/-5 pick running-in allowances, life-factor curves, notch sensitivity, surface and size factors by
material group: St (structural steel), V (through-hardened steel), GGG (spheroidal cast iron, perlitic/bainitic or
ferritic), GG (grey cast iron), Eh (case-hardened), IF (flame/induction hardened), NT/NV (nitrided / nitrocarburised).
The catalogue's ``treatment`` fixes the group; cast iron is split by the EN designation (GJS = spheroidal, perlitic
for the grades >= 500 MPa here; GJL = grey).
"""

from __future__ import annotations

from ..errors import GearoptInputError
from .materials import Material, material

#: The groups used here.
GROUPS = ("St", "V", "GGG", "GG", "Eh", "NT")

_BY_TREATMENT = {"case_carburised": "Eh", "through_hardened": "V", "nitrided": "NT"}


def iso6336_material_group(mat) -> str:
    """ISO 6336 group of a catalogue material (name or :class:`Material`): "Eh" (case-carburised), "V"
    (through-hardened), "NT" (nitrided), "GGG" (GJS spheroidal iron, perlitic) or "GG" (GJL grey iron)."""
    m = material(mat)
    if m.treatment in _BY_TREATMENT:
        return _BY_TREATMENT[m.treatment]
    if m.treatment == "cast_iron":
        name = m.name.upper()
        if "GJS" in name or "GGG" in name:
            return "GGG"
        if "GJL" in name or name.startswith("GG"):
            return "GG"
    raise GearoptInputError(f"material {m.name!r} (treatment {m.treatment!r}) has no ISO 6336 material group; "
                            f"one of {GROUPS} is needed")


__all__ = ["GROUPS", "iso6336_material_group", "Material"]
