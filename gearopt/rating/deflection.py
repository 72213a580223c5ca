"""Mesh misalignment from shaft and gear-body deflection, f_sh [um], for ISO 6336-1 method C's K_Hbeta and the
LTCA's lead-slope input, dual-typed.

Two models:

* :func:`iso6336_shaft_misalignment_um` -- ISO 6336-1:2006 clause 7.6.4 (method C): f_sh = 0.023 gamma F_m/b [um]
  with gamma = (|B* + K' l s/d1^2 (d1/d_sh)^4 - 0.3| + 0.3) (b/d1)^2, the pinion-offset constant K' of
  :data:`PINION_OFFSET_CONSTANTS` (arrangements a-e, stiff when d1/d_sh >= 1.15) and B* = 1 for one power path.
* :func:`beam_shaft_misalignment_um` -- a simple beam model per shaft (Euler-Bernoulli, two rigid bearings, the
  tooth force at the face centre, gear on or outside the span) plus the torsional wind-up of each gear body across
  the face width: f_sh = 1000 b |theta_1 + theta_2| + 1000 sum_i r_bi T_i b / (2 G J_i). The bending slopes theta_i
  are in the plane of the line of action, both signed in one axial coordinate (deflection away from the mesh
  positive); the torsion term assumes the torque enters at one face end and is shed uniformly across the face
  (twist T b/(2 G J), J = pi d^4/32 of the body diameter). An approximation: bearing clearances and stiffness,
  housing deflection and the load distribution's feedback on the load position are ignored.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range

#: ISO 6336-1:2006 Figure 13 / Table 14 pinion-offset constant K' (stiff, non-stiff) by arrangement a..e.
PINION_OFFSET_CONSTANTS = {"a": (0.48, 0.8), "b": (-0.48, -0.8), "c": (1.33, 1.33), "d": (-0.36, -0.6),
                           "e": (-0.6, -1.0)}
#: d1/d_sh from which the pinion counts as stiff (ISO 6336-1 clause 7.6.4).
STIFF_PINION_RATIO = 1.15
STEEL_E_MPA = 206000.0
STEEL_G_MPA = 79200.0


def pinion_offset_constant(arrangement: str, pinion_diameter_mm, shaft_diameter_mm) -> float:
    """K' of ISO 6336-1:2006 Table 14 for ``arrangement`` "a".."e" and stiff (d1/d_sh >= 1.15) or non-stiff
    pinions (numeric diameters)."""
    if arrangement not in PINION_OFFSET_CONSTANTS:
        raise GearoptInputError(f"arrangement={arrangement!r} must be one of {sorted(PINION_OFFSET_CONSTANTS)} "
                                f"(ISO 6336-1:2006 Figure 13)")
    stiff = nm.to_float(pinion_diameter_mm) / nm.to_float(shaft_diameter_mm) >= STIFF_PINION_RATIO
    return PINION_OFFSET_CONSTANTS[arrangement][0 if stiff else 1]


def iso6336_shaft_misalignment_um(line_load_Fm_per_b, pinion_diameter_mm, face_width_mm, *, arrangement="a",
                                  bearing_span_mm=None, offset_mm=0.0, shaft_diameter_mm=None, power_split=1.0):
    """ISO 6336-1:2006 clause 7.6.4 f_sh = 0.023 gamma F_m/b [um], gamma = (|B* + K' l s/d1^2 (d1/d_sh)^4 - 0.3| +
    0.3) (b/d1)^2, B* = 1 + 2 (1 - k)/k with k = ``power_split`` the fraction of the power through the mesh side
    (1: one path). ``bearing_span_mm`` l and ``offset_mm`` s of the pinion from mid-span; without a span the K'
    term is zero (pinion body deflection only). ``shaft_diameter_mm`` d_sh defaults to d1. Dual-typed in the
    loads and lengths."""
    check_range("power_split", power_split, 0.0, 1.0, low_inclusive=False)
    d1 = pinion_diameter_mm
    d_sh = d1 if shaft_diameter_mm is None else shaft_diameter_mm
    b_star = 1.0 + 2.0 * (1.0 - power_split) / power_split
    k_term = 0.0
    if bearing_span_mm is not None:
        check_range("bearing_span_mm", bearing_span_mm, 0.0, None, low_inclusive=False, unit="mm")
        k = pinion_offset_constant(arrangement, d1, d_sh)
        k_term = k * bearing_span_mm * offset_mm / (d1 * d1) * (d1 / d_sh) ** 4
    gamma = (nm.fabs(b_star + k_term - 0.3) + 0.3) * (face_width_mm / d1) ** 2
    return 0.023 * gamma * line_load_Fm_per_b


@dataclass(frozen=True)
class ShaftSupport:
    """One gear's shaft for :func:`beam_shaft_misalignment_um`: bearings at axial positions 0 and ``span_mm``, the
    gear's face centre at ``gear_position_mm`` (inside 0..span, or outside for an overhung gear), a uniform
    ``shaft_diameter_mm``, the gear body diameter ``body_diameter_mm`` for the torsion across the face (default:
    the shaft diameter) and Young's/shear moduli [MPa]. Positions use one axial coordinate for both shafts."""

    span_mm: float
    gear_position_mm: float
    shaft_diameter_mm: float
    body_diameter_mm: float | None = None
    E_MPa: float = STEEL_E_MPA
    G_MPa: float = STEEL_G_MPA

    def __post_init__(self):
        check_range("span_mm", self.span_mm, 0.0, None, low_inclusive=False, unit="mm")
        check_range("shaft_diameter_mm", self.shaft_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
        if self.body_diameter_mm is not None:
            check_range("body_diameter_mm", self.body_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")


def beam_slope_at_load_rad(force_N, span_mm, load_position_mm, E_MPa, second_moment_mm4):
    """Slope dw/dx [rad] under a point load F at x = a of a beam on simple supports at x = 0 and x = l (Roark,
    Table 8.1 cases 1e and overhang): 0 < a < l: F b'(l^2 - b'^2 - 3 a^2)/(6 E I l), b' = l - a; a > l (overhang
    c = a - l): F c (2 l + 3 c)/(6 E I); a < 0: mirror image (-F |a| (2 l + 3 |a|)/(6 E I)). Deflection along the
    force positive. Numeric position (chooses the case); dual-typed in F, l, E, I when the case is fixed."""
    a = nm.to_float(load_position_mm)
    l_ = nm.to_float(span_mm)
    ei = E_MPa * second_moment_mm4
    if 0.0 <= a <= l_:
        bp = span_mm - load_position_mm
        return force_N * bp * (span_mm ** 2 - bp ** 2 - 3.0 * load_position_mm ** 2) / (6.0 * ei * span_mm)
    if a > l_:
        c = load_position_mm - span_mm
        return force_N * c * (2.0 * span_mm + 3.0 * c) / (6.0 * ei)
    c = -load_position_mm
    return -force_N * c * (2.0 * span_mm + 3.0 * c) / (6.0 * ei)


def beam_shaft_misalignment_um(pair, torque_Nm, shafts, *, driving_gear: int = 1) -> dict:
    """Mesh misalignment f_sh [um] across the face of ``pair`` from the bending of both shafts and the torsion of
    both gear bodies (module docstring). ``shafts``: 2-tuple of :class:`ShaftSupport` (gear 1, gear 2);
    ``torque_Nm`` on gear ``driving_gear``. Returns ``f_sh_um``, ``bending_um``, ``torsion_um``, ``slopes_rad``
    (signed, per gear), ``bending_signed_um`` (the gap growth across the face, positive where the axial coordinate
    grows: the LTCA's ``Microgeometry(misalignment_um=...)``) and ``normal_force_N``. Dual-typed in the torque and
    pair dimensions. For K_Hbeta pass ``mesh_misalignment_um`` = 1.33 f_sh + f_ma to
    :func:`~gearopt.rating.rate_iso6336`."""
    if len(shafts) != 2:
        raise GearoptInputError(f"shafts={shafts!r} must be a 2-tuple of ShaftSupport (gear 1, gear 2)")
    check_range("torque_Nm", torque_Nm, 0.0, None, low_inclusive=False, unit="N m")
    g = pair.geometry()
    d_b = g["base_diameter_mm"]
    t_drive = torque_Nm * 1000.0
    torques = [t_drive, t_drive]
    torques[2 - driving_gear] = t_drive * d_b[2 - driving_gear] / d_b[driving_gear - 1]
    f_bt = t_drive / (0.5 * d_b[driving_gear - 1])  # force along the transverse line of action [N]
    b = nm.fmin(g["face_width_mm"][0], g["face_width_mm"][1])
    slopes, torsion = [], 0.0
    for i, s in enumerate(shafts):
        inertia = math.pi * s.shaft_diameter_mm ** 4 / 64.0
        slopes.append(beam_slope_at_load_rad(f_bt, s.span_mm, s.gear_position_mm, s.E_MPa, inertia))
        body = s.body_diameter_mm if s.body_diameter_mm is not None else s.shaft_diameter_mm
        polar = math.pi * body ** 4 / 32.0
        torsion = torsion + 0.5 * d_b[i] * torques[i] * b / (2.0 * s.G_MPa * polar) * 1000.0
    signed = 1000.0 * b * (slopes[0] + slopes[1])
    bending = nm.fabs(signed)
    return {"f_sh_um": bending + torsion, "bending_um": bending, "bending_signed_um": signed, "torsion_um": torsion,
            "slopes_rad": tuple(slopes), "normal_force_N": f_bt}


__all__ = ["PINION_OFFSET_CONSTANTS", "STIFF_PINION_RATIO", "pinion_offset_constant", "iso6336_shaft_misalignment_um",
           "ShaftSupport", "beam_slope_at_load_rad", "beam_shaft_misalignment_um"]
