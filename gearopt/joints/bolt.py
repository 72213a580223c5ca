"""Bolt / nut preload from tightening torque: the nut-factor relation, nut-factor tables with sources, the nut factor
from thread and collar friction, and the ISO thread stress area. Dual-typed where a model may feed an NLP.

``T = K F d`` (thesis Eq. 3.49 written for the preload W_b = T_n/(k D_b); Shigley's MED Eq. 8-27): T tightening
torque [N m -> N mm], F preload [N], d nominal thread diameter [mm], K nut factor. The nut factor lumps thread and
under-nut friction; its scatter (tables below) dominates the preload uncertainty, so joint margins should be
evaluated at the *largest* nut factor of the range (lowest preload).
"""

from __future__ import annotations

import math

from .. import numerics as nm
from ..errors import GearoptInputError
from ._checks import check_range_any as check_range

#: Nut-factor ranges by surface condition, each with its source. ``(min, max)``; a single value has min = max.
NUT_FACTORS: dict[str, dict] = {
    # thesis Table 3.11 (data [thesis.table_3_11]), which cites Fastenal (2005)
    "thesis/no plating": {"min": 0.20, "max": 0.30, "source": "[T] thesis Table 3.11 (Fastenal 2005)"},
    "thesis/zinc plated": {"min": 0.17, "max": 0.22, "source": "[T] thesis Table 3.11 (Fastenal 2005)"},
    "thesis/lubricated": {"min": 0.12, "max": 0.16, "source": "[T] thesis Table 3.11 (Fastenal 2005)"},
    "thesis/cadmium plated": {"min": 0.11, "max": 0.15, "source": "[T] thesis Table 3.11 (Fastenal 2005)"},
    # Shigley's MED Table 8-15 (torque factors K for Eq. 8-27): quoted from the literature, not re-read here
    "shigley/non-plated black finish": {"min": 0.30, "max": 0.30,
                                        "source": "[M] Shigley's MED Table 8-15 (not retrieved here)"},
    "shigley/zinc-plated": {"min": 0.20, "max": 0.20, "source": "[M] Shigley's MED Table 8-15 (not retrieved here)"},
    "shigley/lubricated": {"min": 0.18, "max": 0.18, "source": "[M] Shigley's MED Table 8-15 (not retrieved here)"},
    "shigley/cadmium-plated": {"min": 0.16, "max": 0.16,
                               "source": "[M] Shigley's MED Table 8-15 (not retrieved here)"},
    "shigley/anti-seize": {"min": 0.12, "max": 0.12, "source": "[M] Shigley's MED Table 8-15 (not retrieved here)"},
    # a published calculator table that cites RCSC for the first rows
    "rcsc/as-received dry": {"min": 0.18, "max": 0.22,
                             "source": "[V] steelcalculator.app/tools/bolt-torque (cites RCSC)"},
    "rcsc/lubricated": {"min": 0.12, "max": 0.18, "source": "[V] steelcalculator.app/tools/bolt-torque (cites RCSC)"},
    "rcsc/cadmium-plated": {"min": 0.12, "max": 0.16,
                            "source": "[V] steelcalculator.app/tools/bolt-torque ('historical')"},
}


def nut_factor_range(condition: str) -> tuple[float, float]:
    """(min, max) nut factor of a condition key of :data:`NUT_FACTORS` (e.g. ``"thesis/lubricated"``)."""
    if condition not in NUT_FACTORS:
        raise GearoptInputError(f"condition={condition!r} is not in NUT_FACTORS: one of {sorted(NUT_FACTORS)}")
    row = NUT_FACTORS[condition]
    return row["min"], row["max"]


def _check_nut(nut_factor, thread_diameter_mm):
    check_range("nut_factor", nut_factor, 0.0, 1.0, low_inclusive=False)
    check_range("thread_diameter_mm", thread_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")


def bolt_preload_N(nut_torque_Nm, nut_factor, thread_diameter_mm):
    """Preload [N] from the tightening torque [N m]: ``F = T / (K d)`` (thesis Eq. 3.49, Shigley Eq. 8-27)."""
    _check_nut(nut_factor, thread_diameter_mm)
    check_range("nut_torque_Nm", nut_torque_Nm, 0.0, None, unit="N m")
    return 1e3 * nut_torque_Nm / (nut_factor * thread_diameter_mm)


def nut_torque_Nm(preload_N, nut_factor, thread_diameter_mm):
    """Tightening torque [N m] for a preload [N]: ``T = K F d``."""
    _check_nut(nut_factor, thread_diameter_mm)
    check_range("preload_N", preload_N, 0.0, None, unit="N")
    return nut_factor * preload_N * thread_diameter_mm * 1e-3


def nut_factor_from_friction(thread_diameter_mm, pitch_mm, thread_friction, collar_friction,
                             thread_angle_deg=60.0, collar_diameter_mm=None):
    """Nut factor from thread geometry and friction (Shigley's MED Eq. 8-26 with the power-screw torque):

    ``K = d_m/(2 d) (tan(lambda) + f sec(a)) / (1 - f tan(lambda) sec(a)) + f_c d_c / (2 d)``

    with the thread mean diameter ``d_m = d - 0.6495 p`` (ISO 60 deg profile: pitch diameter d2), lead angle
    ``tan(lambda) = p / (pi d_m)``, half thread angle ``a`` (30 deg) and collar (nut face) mean diameter ``d_c``
    (default 1.25 d as Shigley takes for a standard hex nut, giving the 0.625 f_c term). Single-start threads.
    """
    _check_nut(0.5, thread_diameter_mm)
    check_range("pitch_mm", pitch_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("thread_friction", thread_friction, 0.0, 1.0)
    check_range("collar_friction", collar_friction, 0.0, 1.0)
    d = thread_diameter_mm
    d_m = d - 0.649519 * pitch_mm
    tan_lead = pitch_mm / (math.pi * d_m)
    sec_a = 1.0 / nm.cos(0.5 * thread_angle_deg * math.pi / 180.0)
    d_c = 1.25 * d if collar_diameter_mm is None else collar_diameter_mm
    thread = d_m / (2.0 * d) * (tan_lead + thread_friction * sec_a) / (1.0 - thread_friction * tan_lead * sec_a)
    return thread + collar_friction * d_c / (2.0 * d)


def thread_stress_area_mm2(thread_diameter_mm, pitch_mm):
    """Tensile stress area [mm^2] of an ISO metric thread: ``pi/4 (d - 0.9382 p)^2`` (ISO 898-1)."""
    check_range("thread_diameter_mm", thread_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("pitch_mm", pitch_mm, 0.0, None, low_inclusive=False, unit="mm")
    return math.pi / 4.0 * (thread_diameter_mm - 0.938194 * pitch_mm) ** 2


def bolt_preload(nut_torque_Nm_value, thread_diameter_mm, pitch_mm=None, *, condition: str | None = None,
                 nut_factor=None, proof_strength_MPa=None) -> dict:
    """Preload range of one tightened nut: at the table's min/max nut factor (``condition``) or a given one.

    Returns ``preload_N`` (at the nominal factor: mid-range for a condition), ``preload_min_N`` (largest factor),
    ``preload_max_N`` (smallest factor), ``nut_factor``, and with ``pitch_mm`` the ``thread_stress_MPa`` at the
    largest preload and, with ``proof_strength_MPa``, ``proof_utilisation`` (stress / proof strength).
    """
    if (condition is None) == (nut_factor is None):
        raise GearoptInputError("give exactly one of condition= (a NUT_FACTORS key) or nut_factor=")
    if condition is not None:
        k_lo, k_hi = nut_factor_range(condition)
    else:
        k_lo = k_hi = nut_factor
    k_nom = 0.5 * (k_lo + k_hi)
    out = {"nut_factor": k_nom, "nut_factor_min": k_lo, "nut_factor_max": k_hi,
           "preload_N": bolt_preload_N(nut_torque_Nm_value, k_nom, thread_diameter_mm),
           "preload_min_N": bolt_preload_N(nut_torque_Nm_value, k_hi, thread_diameter_mm),
           "preload_max_N": bolt_preload_N(nut_torque_Nm_value, k_lo, thread_diameter_mm)}
    if pitch_mm is not None:
        area = thread_stress_area_mm2(thread_diameter_mm, pitch_mm)
        out["thread_stress_area_mm2"] = area
        out["thread_stress_MPa"] = out["preload_max_N"] / area
        if proof_strength_MPa is not None:
            out["proof_utilisation"] = out["thread_stress_MPa"] / proof_strength_MPa
    return out


__all__ = ["NUT_FACTORS", "nut_factor_range", "bolt_preload_N", "nut_torque_Nm", "nut_factor_from_friction",
           "thread_stress_area_mm2", "bolt_preload"]
