"""Single-flank tolerances of cylindrical gears from the ISO 1328-1:1995 accuracy grade, dual-typed.

ISO 1328-1:1995 gives the grade-5 tolerances as formulas in the reference diameter d [mm], the normal module
m_n [mm] and the face width b [mm], and scales them by 2^((Q - 5)/2) for grade Q (0..12):

* single pitch deviation      f_pt = 0.3 (m_n + 0.4 sqrt(d)) + 4
* profile form deviation      f_falpha = 2.5 sqrt(m_n) + 0.17 sqrt(d) + 0.5
* helix slope deviation       f_Hbeta = 0.07 sqrt(d) + 0.45 sqrt(b) + 3
* total helix deviation       F_beta = 0.1 sqrt(d) + 0.63 sqrt(b) + 4.2

and the base pitch deviation used by ISO 6336-1 is f_pb = f_pt cos(alpha_t). **Deviation from the tables:** the
standard tabulates the formulas at the geometric means of its diameter/module/width ranges and rounds the results;
here they are evaluated at the gear's own d, m_n and b, unrounded, so that they are continuous for an NLP. A gear in
the middle of a range gets the tabulated value (e.g. d 341 mm, m_n 14 mm, b 360 mm, grade 6: f_pt 14.7 um here,
14 um in the table; f_falpha 18.5 vs 18 um).
"""

from __future__ import annotations

from .. import numerics as nm
from ..errors import GearoptInputError
from ..units import RAD_PER_DEG
from ..validation import check_range

#: ISO 1328-1:1995 accuracy grades.
ACCURACY_GRADE_RANGE = (0, 12)


def check_accuracy_grade(accuracy_grade) -> None:
    """Raise GearoptInputError unless ``accuracy_grade`` is a number in ISO 1328-1's range 0..12 (symbols pass)."""
    if isinstance(accuracy_grade, bool):
        raise GearoptInputError(f"accuracy_grade={accuracy_grade!r} must be an ISO 1328-1 grade 0..12")
    check_range("accuracy_grade", accuracy_grade, *ACCURACY_GRADE_RANGE)


def grade_scale(accuracy_grade):
    """ISO 1328-1:1995 step factor 2^((Q - 5)/2) from grade 5 to grade Q. Dual-typed."""
    check_accuracy_grade(accuracy_grade)
    return 2.0 ** ((accuracy_grade - 5.0) / 2.0)


def single_pitch_tolerance_um(pitch_diameter_mm, module_mm, accuracy_grade):
    """f_pt [um] = (0.3 (m_n + 0.4 sqrt(d)) + 4) 2^((Q-5)/2), ISO 1328-1:1995 (see module docstring)."""
    return (0.3 * (module_mm + 0.4 * nm.sqrt(pitch_diameter_mm)) + 4.0) * grade_scale(accuracy_grade)


def profile_form_tolerance_um(pitch_diameter_mm, module_mm, accuracy_grade):
    """f_falpha [um] = (2.5 sqrt(m_n) + 0.17 sqrt(d) + 0.5) 2^((Q-5)/2), ISO 1328-1:1995."""
    return (2.5 * nm.sqrt(module_mm) + 0.17 * nm.sqrt(pitch_diameter_mm) + 0.5) * grade_scale(accuracy_grade)


def helix_slope_tolerance_um(pitch_diameter_mm, face_width_mm, accuracy_grade):
    """f_Hbeta [um] = (0.07 sqrt(d) + 0.45 sqrt(b) + 3) 2^((Q-5)/2), ISO 1328-1:1995."""
    return (0.07 * nm.sqrt(pitch_diameter_mm) + 0.45 * nm.sqrt(face_width_mm) + 3.0) * grade_scale(accuracy_grade)


def total_helix_tolerance_um(pitch_diameter_mm, face_width_mm, accuracy_grade):
    """F_beta [um] = (0.1 sqrt(d) + 0.63 sqrt(b) + 4.2) 2^((Q-5)/2), ISO 1328-1:1995."""
    return (0.1 * nm.sqrt(pitch_diameter_mm) + 0.63 * nm.sqrt(face_width_mm) + 4.2) * grade_scale(accuracy_grade)


def pair_deviations_um(pair, accuracy_grade) -> dict:
    """Per-gear tolerances of a pair from one grade or a 2-tuple of grades: ``f_pt``, ``f_pb`` (= f_pt cos
    alpha_t, ISO 6336-1), ``f_falpha``, ``f_Hbeta``, ``F_beta`` -- each a 2-tuple (gear 1, gear 2) [um]."""
    grades = tuple(accuracy_grade) if isinstance(accuracy_grade, (tuple, list)) else (accuracy_grade,) * 2
    if len(grades) != 2:
        raise GearoptInputError(f"accuracy_grade={accuracy_grade!r} must be a grade or a 2-tuple of grades")
    g = pair.geometry()
    d, m, b = g["pitch_diameter_mm"], g["module_mm"], g["face_width_mm"]
    cos_at = nm.cos(g["transverse_pressure_angle_deg"] * RAD_PER_DEG)
    f_pt = tuple(single_pitch_tolerance_um(d[i], m, grades[i]) for i in range(2))
    return {
        "f_pt": f_pt,
        "f_pb": tuple(f * cos_at for f in f_pt),
        "f_falpha": tuple(profile_form_tolerance_um(d[i], m, grades[i]) for i in range(2)),
        "f_Hbeta": tuple(helix_slope_tolerance_um(d[i], b[i], grades[i]) for i in range(2)),
        "F_beta": tuple(total_helix_tolerance_um(d[i], b[i], grades[i]) for i in range(2)),
    }


__all__ = ["ACCURACY_GRADE_RANGE", "check_accuracy_grade", "grade_scale", "single_pitch_tolerance_um",
           "profile_form_tolerance_um", "helix_slope_tolerance_um", "total_helix_tolerance_um",
           "pair_deviations_um"]
