"""The requirements a design must meet, declared once (``[requirements]`` of the data file).

Every verdict gearopt prints is computed from this one list (:func:`gearopt.design.requirements.evaluate_requirements`),
and every design NLP that can move a requirement carries it as a constraint. The section is optional: a key not
stated takes the ``[design_limits]`` value of the same quantity when the file states one, else the default below.

Defaults and their sources:

- joint slip and walk-off (axial) margins >= 1.0 (capacity / demand: below 1 the fit slips or the gear walks),
  static at the design load (weakest fit) and over speed at the dynamic peaks;
- hub yield safety >= 1.0 (hub yield strength / von Mises stress at the bore, nominal fit);
- S_H >= 1.0 and S_F >= 1.4 (ISO 6336-2/-3 leave the minimum safety factors to the user; these are the
  conventional minima for gears of normal reliability, a tooth breakage being worse than pitting), static with
  computed factors and at the dynamic peak torque;
- S_B >= 1.0 (ISO/TS 6336-20 flash-temperature scuffing safety: below 1 the contact temperature reaches the
  scuffing temperature; the standard leaves the minimum to the user);
- contact temperature (bulk + Blok flash) <= 150 degC;
- loaded contact ratio (LTCA, every load case) >= 1.2 and worst-case transverse contact ratio (tolerances) >= 1.2;
- PPTE: the largest PPTE over each mesh's design range <= the unmodified pair's largest (``ppte_form =
  "unmodified"``) or <= ``max_ppte_um`` (``ppte_form = "value"``); with ``ppte_no_load_case_worse = true`` also no
  load case of the range worse than the unmodified pair at that load case;
- the largest PPTE judged again with the flank reliefs at the corners of their manufacturing tolerances -- amounts
  ``ppte_relief_tolerance_um`` = ±2 µm, starts ``ppte_relief_start_tolerance_deg`` = ±0.5° roll, and with
  ``ppte_sharp_start`` the relief's start both blended as designed and sharp (engineering estimates for ground
  profile modifications, about the profile form tolerance f_fα of ISO 1328-1:2013 flank tolerance class 5-6 for
  these gear sizes; the class is an estimate, the values are not read from the standard's tables).
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Any, Mapping

from ..errors import DataFileError

PPTE_FORMS = ("unmodified", "value")


@dataclass(frozen=True)
class Requirements:
    """The limits of every requirement (see the module docstring for their meaning and defaults).

    ``min_*`` are lower limits, ``max_*`` upper limits; ``ppte_form`` ``"unmodified"`` or ``"value"``;
    ``max_ppte_um`` the PPTE limit [um] of the ``"value"`` form; ``ppte_no_load_case_worse`` also fails a design
    worse than the unmodified pair at any load case of the range; ``ppte_relief_tolerance_um``,
    ``ppte_relief_start_tolerance_deg`` and ``ppte_sharp_start`` the tolerances the PPTE is judged over too."""

    min_slip_margin: float = 1.0
    min_axial_margin: float = 1.0
    min_hub_yield_safety: float = 1.0
    min_S_H: float = 1.0
    min_S_F: float = 1.4
    min_S_B: float = 1.0
    max_contact_temperature_C: float = 150.0
    min_loaded_contact_ratio: float = 1.2
    min_contact_ratio: float = 1.2
    ppte_form: str = "unmodified"
    max_ppte_um: float | None = None
    ppte_no_load_case_worse: bool = True
    ppte_relief_tolerance_um: float = 2.0
    ppte_relief_start_tolerance_deg: float = 0.5
    ppte_sharp_start: bool = True

    def __post_init__(self):
        if self.ppte_form not in PPTE_FORMS:
            raise DataFileError(f"requirements.ppte_form={self.ppte_form!r} must be one of {PPTE_FORMS}")
        if self.ppte_form == "value" and self.max_ppte_um is None:
            raise DataFileError("requirements.ppte_form = 'value' needs requirements.max_ppte_um [um]")

    def limit(self, name: str) -> float:
        """The limit named ``name`` (a field of this record)."""
        return getattr(self, name)

    def as_dict(self) -> dict[str, Any]:
        return {f.name: getattr(self, f.name) for f in fields(self)}


#: Keys of ``[design_limits]`` that state the same quantity as a requirement (the requirement takes their value
#: when ``[requirements]`` does not state it; both stated and different is an error: a limit is declared once).
SHARED_WITH_DESIGN_LIMITS = ("max_contact_temperature_C", "min_loaded_contact_ratio")


def requirements_from_data(section: Mapping[str, Any] | None, design_limits: Mapping[str, Any] | None = None, *,
                           source: str = "<data>") -> Requirements:
    """The :class:`Requirements` of a validated ``[requirements]`` table (provenance stripped; None: the section is
    absent), completed from ``[design_limits]`` and the defaults."""
    section = dict(section or {})
    limits = dict(design_limits or {})
    values: dict[str, Any] = {}
    for key in SHARED_WITH_DESIGN_LIMITS:
        if key in limits and limits[key] is not None:
            if key in section and float(section[key]) != float(limits[key]):
                raise DataFileError(f"{source}: requirements.{key} = {section[key]} and design_limits.{key} = "
                                    f"{limits[key]} state one limit twice with different values; keep one")
            values[key] = float(limits[key])
    known = {f.name for f in fields(Requirements)}
    for key, value in section.items():
        if key not in known:
            raise DataFileError(f"{source}: requirements.{key} is not a requirement ({sorted(known)})")
        values[key] = value
    try:
        return Requirements(**values)
    except DataFileError as err:
        raise DataFileError(f"{source}: {err}") from None


__all__ = ["Requirements", "requirements_from_data", "PPTE_FORMS", "SHARED_WITH_DESIGN_LIMITS"]
