"""Tooth microgeometry: profile and lead modifications of each gear of a pair, as deviations along the line of action.

Every modification removes material, so it is a non-negative deviation [um] measured normal to the involute (along
the line of action in the transverse plane), added to the initial gap of a contacting tooth pair. Profile
modifications are functions of the roll angle xi [deg] (LDP and thesis Table 3.8 give relief starts as roll
angles), lead modifications of the face position y in [-b/2, b/2] [mm]. Dual-typed: amounts and starts may be CasADi
symbols (the kinks of linear relief are where Ipopt sees them; use ``relief_shape="parabolic"`` for a C1 profile).

Modifications per gear (2-tuples, gear 1 then gear 2):

- tip relief C_a [um] from a start roll angle (or diameter) to the tip, ``linear`` or ``parabolic`` in roll angle;
  optional second stage (``tip_relief_2_um`` from ``tip_relief_2_start_roll_deg``), added on top (thesis Table 3.8);
- root relief [um] from a start roll angle down to the start of active profile, same shapes;
- profile crown C_alpha [um]: parabola over the active profile, zero at its middle, C_alpha at both ends;
- lead crown C_beta [um]: parabola over the face, zero at the middle, C_beta at both ends;
- lead slope f_Hbeta [um]: linear over the face, +f/2 at y = +b/2 (a helix deviation).

``relief_smoothing_deg`` > 0 rounds the kink at each relief start over about that roll angle (softplus; the
relief is then over-estimated by at most width*ln2 relative to its ramp): an NLP modelling option that makes the gaps
smooth in the start angles. Reports use the exact (0) form.

Pair-level ``misalignment_um``: the gap grows linearly over the face, +m/2 at y = +b/2 (mesh misalignment f_ma);
it may be negative.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range, per_gear

SHAPES = ("linear", "parabolic")


@dataclass(frozen=True)
class Microgeometry:
    """Profile and lead modifications of a pair (amounts in um, starts as roll angles in degrees, or diameters in mm
    via ``tip_relief_start_diameter_mm``/``root_relief_start_diameter_mm``; a start of ``None`` with a nonzero
    amount is an error)."""

    tip_relief_um: Any = (0.0, 0.0)
    tip_relief_start_roll_deg: Any = (None, None)
    tip_relief_start_diameter_mm: Any = (None, None)
    tip_relief_2_um: Any = (0.0, 0.0)
    tip_relief_2_start_roll_deg: Any = (None, None)
    root_relief_um: Any = (0.0, 0.0)
    root_relief_start_roll_deg: Any = (None, None)
    root_relief_start_diameter_mm: Any = (None, None)
    relief_shape: str = "linear"
    profile_crown_um: Any = (0.0, 0.0)
    lead_crown_um: Any = (0.0, 0.0)
    lead_slope_um: Any = (0.0, 0.0)
    misalignment_um: Any = 0.0
    relief_smoothing_deg: float = 0.0

    def __post_init__(self):
        for name in ("tip_relief_um", "tip_relief_start_roll_deg", "tip_relief_start_diameter_mm", "tip_relief_2_um",
                     "tip_relief_2_start_roll_deg", "root_relief_um", "root_relief_start_roll_deg",
                     "root_relief_start_diameter_mm", "profile_crown_um", "lead_crown_um", "lead_slope_um"):
            object.__setattr__(self, name, per_gear(getattr(self, name), name))
        check_range("relief_smoothing_deg", self.relief_smoothing_deg, 0.0, 5.0, unit="deg")
        if self.relief_shape not in SHAPES:
            raise GearoptInputError(f"relief_shape={self.relief_shape!r} must be one of {SHAPES}")
        for name in ("tip_relief_um", "tip_relief_2_um", "root_relief_um", "profile_crown_um", "lead_crown_um"):
            for i, v in enumerate(getattr(self, name)):
                check_range(f"{name}[{i}]", v, 0.0, 1000.0, unit="um")
        for amount, starts, label in (("tip_relief_um", ("tip_relief_start_roll_deg", "tip_relief_start_diameter_mm"),
                                       "tip relief"),
                                      ("tip_relief_2_um", ("tip_relief_2_start_roll_deg",), "second tip relief"),
                                      ("root_relief_um", ("root_relief_start_roll_deg",
                                                          "root_relief_start_diameter_mm"), "root relief")):
            for i in range(2):
                a = getattr(self, amount)[i]
                given = [getattr(self, s)[i] is not None for s in starts]
                if sum(given) > 1:
                    raise GearoptInputError(f"{label} of gear {i + 1}: give its start as a roll angle or a diameter, "
                                            f"not both")
                if not any(given) and not (nm.is_numeric(a) and nm.to_float(a) == 0.0):
                    raise GearoptInputError(f"{label} of gear {i + 1}: {amount}[{i}]={a} needs a start "
                                            f"({' or '.join(starts)})")

    @property
    def has_lead_modification(self) -> bool:
        """True when anything varies over the face (then the LTCA needs more than one slice for a spur pair)."""
        vals = [*self.lead_crown_um, *self.lead_slope_um, self.misalignment_um]
        return any(not (nm.is_numeric(v) and nm.to_float(v) == 0.0) for v in vals)


def _ramp(u, shape, width=0.0):
    """0 for u <= 0, u (linear) or u^2 (parabolic) above; dual-typed, no NaN branch. A positive ``width`` (in units
    of u) rounds the kink at u = 0 with ``numerics.softplus`` (error at most width*ln2)."""
    up = nm.fmax(u, 0.0) if nm.is_numeric(width) and nm.to_float(width) == 0.0 else nm.softplus(u, width)
    return up if shape == "linear" else up * up


def profile_deviation_um(mods: Microgeometry, gear: int, roll_deg, *, sap_roll_deg, eap_roll_deg,
                         base_diameter_mm):
    """Material removed by the profile modifications of gear ``gear`` (0 or 1) at roll angle ``roll_deg`` [um].

    ``sap_roll_deg``/``eap_roll_deg`` bound the active profile of that gear in this mesh (tip relief reaches its
    amount at the EAP, root relief at the SAP, the profile crown is centred between them). Starts given as
    diameters are converted with the gear's base diameter.
    """
    def start_roll(roll_start, diameter_start):
        if roll_start is not None:
            return roll_start
        rho = 0.5 * nm.sqrt(diameter_start ** 2 - base_diameter_mm ** 2)
        return rho / (0.5 * base_diameter_mm) * (180.0 / 3.141592653589793)

    dev = 0.0
    shape, w = mods.relief_shape, float(mods.relief_smoothing_deg)
    if not _is_zero(mods.tip_relief_um[gear]):
        s = start_roll(mods.tip_relief_start_roll_deg[gear], mods.tip_relief_start_diameter_mm[gear])
        dev = dev + mods.tip_relief_um[gear] * _ramp((roll_deg - s) / (eap_roll_deg - s), shape,
                                                     w / (eap_roll_deg - s) if w else 0.0)
    if not _is_zero(mods.tip_relief_2_um[gear]):
        s = mods.tip_relief_2_start_roll_deg[gear]
        dev = dev + mods.tip_relief_2_um[gear] * _ramp((roll_deg - s) / (eap_roll_deg - s), shape,
                                                       w / (eap_roll_deg - s) if w else 0.0)
    if not _is_zero(mods.root_relief_um[gear]):
        s = start_roll(mods.root_relief_start_roll_deg[gear], mods.root_relief_start_diameter_mm[gear])
        dev = dev + mods.root_relief_um[gear] * _ramp((s - roll_deg) / (s - sap_roll_deg), shape,
                                                      w / (s - sap_roll_deg) if w else 0.0)
    if not _is_zero(mods.profile_crown_um[gear]):
        mid, half = 0.5 * (sap_roll_deg + eap_roll_deg), 0.5 * (eap_roll_deg - sap_roll_deg)
        dev = dev + mods.profile_crown_um[gear] * ((roll_deg - mid) / half) ** 2
    return dev


def lead_deviation_um(mods: Microgeometry, gear: int, y_mm, face_width_mm):
    """Material removed by gear ``gear``'s lead modifications at face position ``y_mm`` in [-b/2, b/2] [um]
    (crown; slope may be negative locally, it is a helix deviation)."""
    u = 2.0 * y_mm / face_width_mm
    return mods.lead_crown_um[gear] * u * u + 0.5 * mods.lead_slope_um[gear] * u


def misalignment_gap_um(mods: Microgeometry, y_mm, face_width_mm):
    """Gap added by the pair's misalignment at face position ``y_mm`` [um]."""
    return 0.5 * mods.misalignment_um * (2.0 * y_mm / face_width_mm)


def _is_zero(v) -> bool:
    return nm.is_numeric(v) and nm.to_float(v) == 0.0
