"""The vocabulary of a scene: which design variables and quantities exist, their units, and which models each needs.

``needs`` names model *families*; :class:`~gearopt.design.scene.Scene` builds a family only when a requested
quantity needs it:

- ``geometry``: the :class:`~gearopt.geometry.pair.GearPair` of a mesh (symbolic when macro variables are free);
- ``iso6336``: ISO 6336-2/-3 method B contact and root stress (:mod:`gearopt.rating`);
- ``iso6336_rating``: the complete rating with computed factors (:func:`gearopt.rating.rate_iso6336`; needs the load
  case's speed);
- ``ltca``: the smooth CasADi LTCA (:class:`~gearopt.contact.ltca_smooth.LTCAModel`), built once per mesh with one
  face slice for a spur pair without lead modifications; ``ltca_root_stress`` / ``ltca_temperature`` switch on its
  root-stress and flash-temperature outputs;
- ``joint``: the press-fit / taper capacity of a ``[joints.*]`` entry (:func:`gearopt.joints.joint_capacity`);
- ``blank``: the :class:`~gearopt.blank.GearBlank` of a gear (:func:`gearopt.blank.blank_from_data`).

Targets: a mesh (``"pinion-wheel"``), a joint or a blank (a gear name), the train (``"train"``: its root-gear profile
shift at the fixed centre distances and its common helix angle, which move every mesh) or a gear flank
(``"cam:driven"``, :data:`FLANKS`: a microgeometry that every mesh loading that flank sees).

Shapes: ``scalar`` (one value per load case, or one in all), ``max`` (a vector whose largest element is the
quantity: an upper limit is imposed on every element, a minimised objective gets an epigraph variable), ``min``
(the mirror), ``ppte`` (peak-to-peak of the TE over the mesh positions: two epigraph variables per load case, valid for
minimisation and upper limits). ``squared``: the elements are squares of the quantity (contact stress: the square
of the Hertzian stress is smooth at zero load), limits are squared when imposed.

``ppte_um_toleranced``: the largest PPTE of a mesh over the variants of its tip reliefs at the corners of their
manufacturing tolerances (:class:`~gearopt.design.scene_options.ReliefToleranceOptions`,
:func:`~gearopt.contact.relief_tolerances.relief_variants`; the PPTE requirement judged over the tolerances). In the
NLP a vector, one smooth upper bound of the PPTE per blended variant (log-sum-exp maximum minus minimum of its TE),
its rows by exchange; the exact check takes the largest exact PPTE over every variant, sharp starts included. A
limit only (an upper one), beside a ``ppte_um`` objective.

Joint quantities: ``torque_margin`` and ``axial_margin`` (capacity / |demand|, infinite for a zero demand),
``slip_utilisation`` (combined demand over capacity, :func:`gearopt.joints.joint_margins`) and
``axial_utilisation`` (|axial force| / axial capacity = 1 / ``axial_margin``: the walk-off demand of a helical
train as a fraction of what the fit holds, 0 for a spur train; squared, so it stays smooth through a helix angle
of 0 -- the quantity to trade against when the helix angle may go to 0).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import GearoptInputError


@dataclass(frozen=True)
class VariableKind:
    """A design variable of the vocabulary: target kind, group, unit, default bounds (None: required) and scale."""

    name: str
    target_kind: str
    group: str
    unit: str
    scale: float
    lower: float | None = None
    upper: float | None = None
    key: str | None = None   # the model's own name of the value where it differs (joint data entries)


@dataclass(frozen=True)
class QuantityKind:
    """A quantity of the vocabulary (see the module docstring for ``shape`` and ``squared``)."""

    name: str
    target_kind: str
    needs: tuple[str, ...]
    unit: str
    per_load_case: bool
    shape: str = "scalar"
    squared: bool = False
    scale: float = 1.0


FLANKS = ("driving", "driven")
"""The two loaded flanks of a gear in forward operation: ``driving`` (it pushes its mates; the flank facing its
sense of rotation) and ``driven`` (its driver pushes it). A flank target is ``"gear:flank"``."""


def _vars() -> dict[str, VariableKind]:
    out = [VariableKind("root_profile_shift", "train", "train", "", 0.2),
           VariableKind("helix_angle_deg", "train", "train", "deg", 5.0, 0.0),
           VariableKind("profile_shift_1", "mesh", "macro", "", 0.5, -1.0, 2.0),
           VariableKind("tip_diameter_1_mm", "mesh", "macro", "mm", 1.0),
           VariableKind("tip_diameter_2_mm", "mesh", "macro", "mm", 1.0),
           VariableKind("face_width_mm", "mesh", "macro", "mm", 10.0)]
    for i in (1, 2):
        out += [VariableKind(f"tip_relief_{i}_um", "mesh", "micro", "um", 10.0, 0.0, 40.0),
                VariableKind(f"tip_relief_{i}_start_roll_deg", "mesh", "micro", "deg", 1.0),
                VariableKind(f"profile_crown_{i}_um", "mesh", "micro", "um", 1.0, 0.0, 10.0),
                VariableKind(f"lead_crown_{i}_um", "mesh", "micro", "um", 5.0, 0.0, 30.0)]
    out += [VariableKind("tip_relief_um", "flank", "micro", "um", 10.0, 0.0, 40.0),
            VariableKind("tip_relief_start_roll_deg", "flank", "micro", "deg", 1.0),
            VariableKind("profile_crown_um", "flank", "micro", "um", 1.0, 0.0, 10.0),
            VariableKind("lead_crown_um", "flank", "micro", "um", 5.0, 0.0, 30.0)]
    out += [VariableKind("interference_um", "joint", "joint", "um", 50.0, key="diametral_interference_um"),
            VariableKind("fit_length_mm", "joint", "joint", "mm", 10.0),
            VariableKind("nut_torque_Nm", "joint", "joint", "N*m", 50.0),
            VariableKind("web_thickness_mm", "blank", "blank", "mm", 5.0),
            VariableKind("rim_thickness_mm", "blank", "blank", "mm", 5.0),
            VariableKind("pocket_area_fraction", "blank", "blank", "", 0.1, 0.0, 0.8)]
    return {v.name: v for v in out}


def _quantities() -> dict[str, QuantityKind]:
    geo, iso, rate = ("geometry",), ("geometry", "iso6336"), ("geometry", "iso6336_rating")
    q = [QuantityKind("transverse_contact_ratio", "mesh", geo, "", False, scale=0.1),
         QuantityKind("worst_case_transverse_contact_ratio", "mesh", geo, "", False, scale=0.1),
         QuantityKind("tip_thickness_1_mm", "mesh", geo, "mm", False),
         QuantityKind("tip_thickness_2_mm", "mesh", geo, "mm", False),
         QuantityKind("min_tip_thickness_mm", "mesh", geo, "mm", False, shape="min"),
         QuantityKind("geometry_limits", "mesh", geo, "", False, shape="named"),
         QuantityKind("contact_stress_iso6336_MPa", "mesh", iso, "MPa", True, shape="max", scale=100.0),
         QuantityKind("root_stress_iso6336_MPa", "mesh", iso, "MPa", True, shape="max", scale=100.0),
         QuantityKind("contact_safety_factor_iso6336", "mesh", iso, "", True, shape="min", scale=0.1),
         QuantityKind("root_safety_factor_iso6336", "mesh", iso, "", True, shape="min", scale=0.1),
         QuantityKind("contact_safety_factor", "mesh", rate, "", True, shape="min", scale=0.1),
         QuantityKind("root_safety_factor", "mesh", rate, "", True, shape="min", scale=0.1),
         QuantityKind("scuffing_safety_factor_flash", "mesh", rate, "", True, scale=0.1),
         QuantityKind("scuffing_safety_factor_integral", "mesh", rate, "", True, scale=0.1),
         QuantityKind("ppte_um", "mesh", ("geometry", "ltca"), "um", True, shape="ppte", scale=5.0),
         QuantityKind("ppte_um_toleranced", "mesh", ("geometry", "ltca"), "um", True, shape="max", scale=5.0),
         QuantityKind("max_contact_stress_MPa", "mesh", ("geometry", "ltca"), "MPa", True, shape="max",
                      squared=True, scale=100.0),
         QuantityKind("loaded_contact_ratio", "mesh", ("geometry", "ltca"), "", True, scale=0.1),
         QuantityKind("max_root_stress_MPa", "mesh", ("geometry", "ltca", "ltca_root_stress"), "MPa", True,
                      shape="max", scale=100.0),
         QuantityKind("max_contact_temperature_C", "mesh", ("geometry", "ltca", "ltca_temperature"), "C", True,
                      shape="max", scale=10.0),
         QuantityKind("torque_margin", "joint", ("joint",), "", True, scale=0.1),
         QuantityKind("axial_margin", "joint", ("joint",), "", True, scale=0.1),
         QuantityKind("slip_utilisation", "joint", ("joint",), "", True, scale=0.1),
         QuantityKind("axial_utilisation", "joint", ("joint",), "", True, shape="max", squared=True, scale=0.01),
         QuantityKind("torque_capacity_Nm", "joint", ("joint",), "N*m", False, scale=100.0),
         QuantityKind("axial_capacity_N", "joint", ("joint",), "N", False, scale=1e4),
         QuantityKind("hub_yield_safety", "joint", ("joint",), "", False, scale=0.1),
         QuantityKind("inertia_kgm2", "blank", ("blank",), "kg*m^2", False, scale=0.01),
         QuantityKind("mass_kg", "blank", ("blank",), "kg", False, scale=1.0),
         QuantityKind("rim_backup_ratio", "blank", ("blank",), "", False, scale=0.1)]
    return {x.name: x for x in q}


VARIABLES: dict[str, VariableKind] = _vars()
QUANTITIES: dict[str, QuantityKind] = _quantities()


def variable_kind(name: str) -> VariableKind:
    if name not in VARIABLES:
        raise GearoptInputError(f"design variable {name!r} is not in the scene vocabulary ({sorted(VARIABLES)})")
    return VARIABLES[name]


def quantity_kind(name: str) -> QuantityKind:
    if name not in QUANTITIES:
        raise GearoptInputError(f"quantity {name!r} is not in the scene vocabulary ({sorted(QUANTITIES)})")
    return QUANTITIES[name]


__all__ = ["FLANKS", "VariableKind", "QuantityKind", "VARIABLES", "QUANTITIES", "variable_kind", "quantity_kind"]
