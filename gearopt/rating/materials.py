"""Gear materials for strength and temperature ratings: a small catalogue with every number's provenance.

The catalogue merges the ``[materials.*]`` tables of the packaged default data (``default_train.toml``: 20MnCr5
case-carburised, 42CrMo4 through-hardened, GJL-250 grey cast iron) with ``materials.toml`` (31CrMoV9 nitrided,
GJS-600-3 ductile iron, and the gear-rating keys GJL-250 lacks there). A key given in both files is an error, so
each number has exactly one source. Provenance tags: [V] public source, [C] computed, [E] estimate, [M] literature,
not verified here -- ISO 6336-5 allowables are [M]/[E]: check them against the standard before relying on them.

Units: moduli and stresses MPa, density kg/m^3, thermal conductivity W/(m K), specific heat J/(kg K), the thermal
contact coefficient B_M N/(mm s^0.5 K).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
from typing import Any

from ..errors import GearoptInputError

#: Surface treatments of the catalogue (ISO 6336-5 material groups, coarsely).
TREATMENTS = ("case_carburised", "through_hardened", "nitrided", "cast_iron")

_NUMERIC_FIELDS = ("E_MPa", "poisson_ratio", "density_kg_m3", "thermal_conductivity_W_mK", "specific_heat_J_kgK",
                   "sigma_Hlim_MPa", "sigma_Flim_MPa", "yield_strength_MPa", "tensile_strength_MPa",
                   "endurance_limit_MPa", "surface_hardness_HV")
_REQUIRED = ("E_MPa", "poisson_ratio", "density_kg_m3", "thermal_conductivity_W_mK", "specific_heat_J_kgK")


def thermal_contact_coefficient(thermal_conductivity_W_mK, density_kg_m3, specific_heat_J_kgK):
    """Blok's thermal contact coefficient (thermal effusivity) B_M = sqrt(lambda rho c) [N/(mm s^0.5 K)].

    lambda [W/(m K)] = [N/(s K)] and rho c [J/(m^3 K)] = 1e-6 [N/(mm^2 K)], so B_M = sqrt(lambda rho c 1e-6).
    Source: ISO/TR 13989-1 / gearcalc manual sec. 14.11 (B_M = sqrt(lambda_M rho_M c_M); about 13.6 for martensitic
    steel). Dual-typed.
    """
    return (thermal_conductivity_W_mK * density_kg_m3 * specific_heat_J_kgK * 1e-6) ** 0.5


@dataclass(frozen=True)
class Material:
    """One gear material (frozen). Fields carry units in their names; ``None`` = not applicable/unknown (e.g. no
    yield point for grey iron). ``sources`` maps each numeric field to its provenance string."""

    name: str
    description: str
    treatment: str
    E_MPa: float
    poisson_ratio: float
    density_kg_m3: float
    thermal_conductivity_W_mK: float
    specific_heat_J_kgK: float
    sigma_Hlim_MPa: float | None = None
    sigma_Flim_MPa: float | None = None
    yield_strength_MPa: float | None = None
    tensile_strength_MPa: float | None = None
    endurance_limit_MPa: float | None = None
    surface_hardness_HV: float | None = None
    sources: dict = field(default_factory=dict, compare=False, hash=False)

    @property
    def thermal_contact_coefficient_N_per_mm_sqrt_s_K(self) -> float:
        """B_M = sqrt(lambda rho c) [N/(mm s^0.5 K)] (computed, see :func:`thermal_contact_coefficient`)."""
        return thermal_contact_coefficient(self.thermal_conductivity_W_mK, self.density_kg_m3,
                                           self.specific_heat_J_kgK)

    @property
    def brinell_hardness_HB(self) -> float | None:
        """Brinell hardness estimated from the Vickers surface hardness, HB ~ 0.95 HV (ISO 18265 steel table
        trend below ~450 HV; an approximation), or None without a hardness."""
        return None if self.surface_hardness_HV is None else 0.95 * self.surface_hardness_HV

    @property
    def shear_modulus_MPa(self) -> float:
        """G = E / (2 (1 + nu)) [MPa]."""
        return self.E_MPa / (2.0 * (1.0 + self.poisson_ratio))

    def source(self, field_name: str) -> str:
        """Provenance string of a numeric field ("[C] ..." for the computed B_M)."""
        if field_name == "thermal_contact_coefficient_N_per_mm_sqrt_s_K":
            return ("[C] sqrt(lambda rho c) from the fields thermal_conductivity_W_mK, density_kg_m3, "
                    "specific_heat_J_kgK")
        if field_name not in self.sources:
            raise GearoptInputError(f"material {self.name!r} has no source for {field_name!r}")
        return self.sources[field_name]

    def require(self, field_name: str) -> float:
        """A field's value, or a GearoptInputError naming the material if it is not given (None)."""
        value = getattr(self, field_name)
        if value is None:
            raise GearoptInputError(f"material {self.name!r} has no {field_name} (not applicable or unknown); "
                                    f"choose another material or pass the value explicitly")
        return value


def _load_toml(filename: str) -> dict[str, Any]:
    with resources.files("gearopt.data").joinpath(filename).open("rb") as fh:
        return tomllib.load(fh)


def merge_catalogue(default_materials: dict, extra_materials: dict) -> dict[str, dict]:
    """Merge two ``{name: table}`` material dicts key by key; a key present in both raises GearoptInputError."""
    merged = {name: dict(table) for name, table in default_materials.items()}
    for name, table in extra_materials.items():
        target = merged.setdefault(name, {})
        clash = sorted(set(target) & set(table))
        if clash:
            raise GearoptInputError(f"material {name!r}: key(s) {clash} given both in default_train.toml and "
                                    f"materials.toml; each number must have one source")
        target.update(table)
    return merged


def _build(name: str, table: dict) -> Material:
    missing = [k for k in _REQUIRED if k not in table]
    if missing:
        raise GearoptInputError(f"material {name!r} lacks {missing}")
    treatment = table.get("treatment", "")
    if treatment not in TREATMENTS:
        raise GearoptInputError(f"material {name!r}: treatment={treatment!r} must be one of {TREATMENTS}")
    values = {}
    sources = {}
    for key in _NUMERIC_FIELDS:
        if key in table:
            values[key] = float(table[key])
            src = table.get(f"{key}_source")
            if not src:
                raise GearoptInputError(f"material {name!r}: {key} has no {key}_source provenance string")
            sources[key] = str(src)
    return Material(name=name, description=str(table.get("description", "")), treatment=treatment,
                    sources=sources, **values)


@lru_cache(maxsize=1)
def _catalogue() -> dict[str, Material]:
    default = _load_toml("default_train.toml").get("materials", {})
    extra = _load_toml("materials.toml").get("materials", {})
    return {name: _build(name, table) for name, table in merge_catalogue(default, extra).items()}


def material_names() -> tuple[str, ...]:
    """Names of the catalogue's materials."""
    return tuple(_catalogue())


def material(name) -> Material:
    """The catalogue material ``name`` (e.g. ``"20MnCr5"``, ``"42CrMo4"``, ``"31CrMoV9"``, ``"GJS-600-3"``,
    ``"GJL-250"``) as a frozen :class:`Material`; a :class:`Material` passes through unchanged."""
    if isinstance(name, Material):
        return name
    cat = _catalogue()
    if name not in cat:
        raise GearoptInputError(f"material={name!r} is not in the catalogue {sorted(cat)}")
    return cat[name]


def material_pair(materials) -> tuple[Material, Material]:
    """(gear 1, gear 2) materials from one name/Material or a 2-tuple of them."""
    if isinstance(materials, (tuple, list)):
        if len(materials) != 2:
            raise GearoptInputError(f"material={materials!r} must be one material or a 2-tuple (gear 1, gear 2)")
        return material(materials[0]), material(materials[1])
    m = material(materials)
    return m, m


def elasticity_factor_sqrt_MPa(material1, material2=None):
    """ISO 6336-2 elasticity factor Z_E = sqrt(1 / (pi [(1-nu1^2)/E1 + (1-nu2^2)/E2])) [sqrt(MPa)] of two materials
    (189.8 sqrt(MPa) for steel/steel, E 206000 MPa, nu 0.3). ISO 6336-2:2006 clause 7."""
    m1 = material(material1)
    m2 = m1 if material2 is None else material(material2)
    compliance = (1.0 - m1.poisson_ratio ** 2) / m1.E_MPa + (1.0 - m2.poisson_ratio ** 2) / m2.E_MPa
    return math.sqrt(1.0 / (math.pi * compliance))


__all__ = ["TREATMENTS", "Material", "material", "material_names", "material_pair", "merge_catalogue",
           "thermal_contact_coefficient", "elasticity_factor_sqrt_MPa"]
