"""Profile shift under a fixed centre distance: sum of shifts, its split between the gears, ISO/TR 4467 limits.

Angles in rad, lengths in mm. Dual-typed except where a function needs an integer tooth count.
"""

from __future__ import annotations

import math

from .. import numerics as nm
from ..errors import GeometryError, GearoptInputError
from ..validation import as_number


def working_pressure_angle_from_centre_distance(reference_centre_distance_mm, centre_distance_mm,
                                                transverse_pressure_angle_rad):
    """Transverse working pressure angle at centre distance a: cos(alpha_wt) = a_d cos(alpha_t) / a [rad]
    (ISO 21771 eq. 46; thesis Eq. 3.3 is the spur case written with y). Guarded against |cos| > 1 for symbols;
    the caller checks reachability numerically (:func:`check_centre_distance_reachable`)."""
    return nm.acos_safe(reference_centre_distance_mm * nm.cos(transverse_pressure_angle_rad) / centre_distance_mm)


def sum_of_profile_shifts(teeth_sum, working_pressure_angle_rad, transverse_pressure_angle_rad,
                          pressure_angle_rad):
    """Sum of profile-shift coefficients that makes backlash-free mesh at the working pressure angle:
    x1 + x2 = (z1 + z2)(inv alpha_wt - inv alpha_t) / (2 tan alpha_n)  (ISO 21771 eq. 44; thesis Eq. 3.4 is the
    spur case, with the transverse angles generalising it to helical gears)."""
    return teeth_sum * (nm.involute(working_pressure_angle_rad) - nm.involute(transverse_pressure_angle_rad)) \
        / (2.0 * nm.tan(pressure_angle_rad))


def working_pressure_angle_from_shifts(teeth_sum, sum_profile_shift, transverse_pressure_angle_rad,
                                       pressure_angle_rad):
    """Inverse of :func:`sum_of_profile_shifts`: inv(alpha_wt) = inv(alpha_t) + 2 (x1 + x2) tan(alpha_n)/(z1 + z2),
    solved with the (differentiable) inverse involute [rad]."""
    inv_wt = nm.involute(transverse_pressure_angle_rad) \
        + 2.0 * sum_profile_shift * nm.tan(pressure_angle_rad) / teeth_sum
    if nm.is_numeric(inv_wt) and nm.to_float(inv_wt) < 0.0:
        raise GeometryError(
            f"sum of profile shifts x1+x2={nm.to_float(sum_profile_shift):.4f} is too negative: the working "
            f"pressure angle would be below 0 (limit x1+x2 > {-teeth_sum * nm.to_float(nm.involute(transverse_pressure_angle_rad)) / (2 * nm.to_float(nm.tan(pressure_angle_rad))):.4f})")
    return nm.inverse_involute(inv_wt)


def check_centre_distance_reachable(reference_centre_distance_mm: float, centre_distance_mm: float,
                                    transverse_pressure_angle_rad: float) -> None:
    """Raise ``GeometryError`` when no working pressure angle exists for the centre distance (numeric only)."""
    if not nm.is_numeric(reference_centre_distance_mm, centre_distance_mm, transverse_pressure_angle_rad):
        return
    a_min = nm.to_float(reference_centre_distance_mm) * math.cos(nm.to_float(transverse_pressure_angle_rad))
    a = nm.to_float(centre_distance_mm)
    if not a > a_min:
        raise GeometryError(
            f"centre_distance_mm={a:.4f} is unreachable: it must exceed a_d cos(alpha_t) = {a_min:.4f} mm "
            f"(working pressure angle 0 deg)")
    cos_w = nm.to_float(reference_centre_distance_mm) * math.cos(nm.to_float(transverse_pressure_angle_rad)) / a
    alpha_w_deg = math.degrees(math.acos(min(cos_w, 1.0)))
    if alpha_w_deg > 45.0:
        raise GeometryError(f"centre_distance_mm={a:.4f} needs a working pressure angle {alpha_w_deg:.2f} deg, "
                            f"above the admissible 45 deg")


def shift_split_iso_tr_4467(teeth: tuple[int, int], sum_profile_shift, split=0.5):
    """Distribute x1 + x2 between pinion and wheel (ISO/TR 4467, thesis Eqs. 3.6-3.7):
    x1 = lambda (z2 - z1)/(z1 + z2) + (x1 + x2) z1/(z1 + z2),  x2 = (x1 + x2) - x1.

    ``split`` is lambda: 0.5..0.75 recommended for speed-reducing pairs (gear 1 drives the larger gear),
    0..0.5 for speed-increasing pairs (thesis Eqs. 3.13-3.14). Returns ``(x1, x2)``.
    """
    z1, z2 = teeth
    if nm.is_numeric(split):
        lam = as_number("shift_split", split)
        if not -0.5 <= lam <= 1.5:
            raise GearoptInputError(f"shift_split (ISO/TR 4467 lambda)={lam:g} outside its range [-0.5, 1.5] "
                                    f"(recommended 0..0.75)")
    x1 = split * (z2 - z1) / (z1 + z2) + sum_profile_shift * z1 / (z1 + z2)
    return x1, sum_profile_shift - x1


def iso_tr_4467_shift_limits(teeth: int) -> tuple[float, float]:
    """Recommended profile-shift range (lower, upper) of ISO/TR 4467 as quoted by the thesis (Eqs. 3.8-3.12).

    Upper: 0.5 + 0.01 z for 10 < z <= 50, 1.0 above 50. Lower: 0.0375 (20 - z) for 12 < z <= 20, (20 - z)/60 for
    20 < z <= 50, -0.5 above 50. Below the ranges the standard gives no value: ``-inf`` / ``+inf`` are returned so
    only the undercut and pointed-tip checks apply.
    """
    z = int(teeth)
    upper = 0.5 + 0.01 * z if 10 < z <= 50 else (1.0 if z > 50 else math.inf)
    if 12 < z <= 20:
        lower = 0.0375 * (20 - z)
    elif 20 < z <= 50:
        lower = (20 - z) / 60.0
    elif z > 50:
        lower = -0.5
    else:
        lower = -math.inf
    return lower, upper
