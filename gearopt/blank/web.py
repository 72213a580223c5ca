"""A simple closed-form gear-web stress and its Goodman / equivalent-fully-reversed (EFR) fatigue margins for
forward, reverse and forward-reverse tooth loading (thesis sec. 3.10 and 4.6, which used ANSYS; no FEA here).

Web stress model (assumptions stated; the critical section is the web's junction with the hub, radius a):

1. Torque T carried from rim to hub through a flat web of thickness t (thin annular disc in torsion): the shear
   flow is constant around any circle, ``tau_T(r) = T / (2 pi r^2 t)`` -- exact by equilibrium, largest at r = a.
2. The in-plane resultant F of the tooth forces (tangential + radial, vector-summed over the gear's meshes; pass
   an upper bound, the sum of magnitudes, when the mesh layout is not known) passes to the hub as transverse shear
   of a thin-walled ring: ``tau_F,max = F / (pi r t)`` (thin-walled circular section, tau_max = 2 V/A).
3. The net axial tooth force P (helical meshes) bends the web as an annular plate clamped at the hub (r = a) and
   free at the rim (r = b), with P spread evenly round the rim (the tilting moment of a single mesh is not
   modelled). Kirchhoff plate theory gives the radial moment at the clamp (derived in this module, tested
   against a numerical solution of the plate equation and the narrow-ring cantilever limit P (b-a)/(2 pi a))::

       M_r(a) = P/(2 pi) [ (1+nu)/2 ln(b/a) + (1-nu)/4 (1 - a^2/b^2) ] / [ (1+nu)/2 + (1-nu)/2 a^2/b^2 ]

   and ``sigma_b = 6 M_r(a) / t^2`` at the web faces.
4. Lightening pockets: the torsional shear at the pocket pitch radius r_p is raised by the net-section factor
   1/(1 - f) (f = pocket share of the circumference there; for an area fraction spread over the web, f = that
   fraction) and by a stress concentration factor K_t (user-supplied; K_t = 1 by default -- the pocket fillet is
   not modelled). The critical shear is the larger of the hub-junction and pocket values.
5. Von Mises equivalent ``sqrt(sigma_b^2 + 3 tau^2)``, the maxima combined at one point (conservative).

Stresses are linear in the loads, so forward and reverse load sets give forward and reverse equivalent stresses
sigma_f, sigma_r (magnitudes). Cycles (thesis sec. 3.10): forward 0 -> sigma_f; reverse 0 -> sigma_r (von Mises is
unsigned, so its mean is taken as +sigma_r/2 -- conservative); forward-reverse sigma_f <-> sigma_r: alternating
(sigma_f + sigma_r)/2, mean |sigma_f - sigma_r|/2. Modified Goodman: ``sigma_EFR = sigma_a / (1 - sigma_m/S_ut)``;
fatigue margin ``S_e / sigma_EFR`` (thesis 4.6: must exceed 1) and yield margin ``S_y / sigma_max``.

Units: mm, N, N m, MPa. Dual-typed.
"""

from __future__ import annotations

import math

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_array, check_range, check_result


def web_torsion_shear_MPa(torque_Nm, radius_mm, web_thickness_mm):
    """In-plane shear [MPa] of a web carrying torque T [N m] at radius r [mm]: ``T / (2 pi r^2 t)``."""
    return 1e3 * torque_Nm / (2.0 * math.pi * radius_mm ** 2 * web_thickness_mm)


def web_transverse_shear_MPa(force_N, radius_mm, web_thickness_mm):
    """Peak shear [MPa] of a thin ring section of radius r, thickness t under in-plane force F [N]: F/(pi r t)."""
    return force_N / (math.pi * radius_mm * web_thickness_mm)


def clamped_annular_plate_moment_Nmm_per_mm(axial_force_N, inner_radius_mm, outer_radius_mm, nu=0.3):
    """Radial bending moment per unit length [N mm/mm] at the clamped inner edge of an annular plate (inner radius
    a clamped, outer radius b free) under a total axial line load P [N] spread evenly round the outer edge."""
    a, b = inner_radius_mm, outer_radius_mm
    q = (a / b) ** 2
    num = 0.5 * (1.0 + nu) * nm.log(b / a) + 0.25 * (1.0 - nu) * (1.0 - q)
    den = 0.5 * (1.0 + nu) + 0.5 * (1.0 - nu) * q
    return axial_force_N / (2.0 * math.pi) * num / den


def web_stress(torque_Nm, *, hub_outer_diameter_mm, rim_inner_diameter_mm, web_thickness_mm, in_plane_force_N=0.0,
               axial_force_N=0.0, nu=0.3, pocket_area_fraction=0.0, pocket_pitch_diameter_mm=None,
               stress_concentration=1.0) -> dict:
    """Critical web stresses [MPa] (module docstring, items 1-5).

    ``torque_Nm`` carried by the web; ``in_plane_force_N`` resultant of the tooth forces; ``axial_force_N`` net
    axial tooth force; ``pocket_area_fraction`` f and ``pocket_pitch_diameter_mm`` (default: mid-web);
    ``stress_concentration`` K_t at the pockets. Returns ``shear_torsion_hub_MPa``, ``shear_force_hub_MPa``,
    ``shear_pocket_MPa``, ``shear_MPa`` (critical), ``bending_MPa``, ``von_mises_MPa``.
    """
    check_range("web_thickness_mm", web_thickness_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("hub_outer_diameter_mm", hub_outer_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("rim_inner_diameter_mm", rim_inner_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
    for name, value, unit in (("torque_Nm", torque_Nm, "N m"), ("in_plane_force_N", in_plane_force_N, "N"),
                              ("axial_force_N", axial_force_N, "N")):  # numbers or arrays (a load history)
        if isinstance(value, np.ndarray):
            check_array(name, value, unit=unit)
        else:
            check_range(name, value, unit=unit)
    check_range("nu", nu, 0.0, 0.5, low_inclusive=False, high_inclusive=False)
    if pocket_pitch_diameter_mm is not None:
        check_range("pocket_pitch_diameter_mm", pocket_pitch_diameter_mm, hub_outer_diameter_mm
                    if nm.is_numeric(hub_outer_diameter_mm) else None, rim_inner_diameter_mm
                    if nm.is_numeric(rim_inner_diameter_mm) else None, unit="mm")
    check_range("pocket_area_fraction", pocket_area_fraction, 0.0, 0.8)
    check_range("stress_concentration", stress_concentration, 1.0, None)
    if nm.is_numeric(hub_outer_diameter_mm, rim_inner_diameter_mm) and \
            nm.to_float(rim_inner_diameter_mm) <= nm.to_float(hub_outer_diameter_mm):
        raise GearoptInputError(f"rim_inner_diameter_mm={nm.to_float(rim_inner_diameter_mm):g} mm must exceed "
                                f"hub_outer_diameter_mm={nm.to_float(hub_outer_diameter_mm):g} mm")
    a, b, t = 0.5 * hub_outer_diameter_mm, 0.5 * rim_inner_diameter_mm, web_thickness_mm
    r_p = 0.5 * (a + b) if pocket_pitch_diameter_mm is None else 0.5 * pocket_pitch_diameter_mm
    T, F, P = nm.fabs(torque_Nm), nm.fabs(in_plane_force_N), nm.fabs(axial_force_N)
    tau_T = web_torsion_shear_MPa(T, a, t)
    tau_F = web_transverse_shear_MPa(F, a, t)
    tau_hub = tau_T + tau_F
    tau_pocket = stress_concentration * (web_torsion_shear_MPa(T, r_p, t) + web_transverse_shear_MPa(F, r_p, t)) \
        / (1.0 - pocket_area_fraction)
    tau = nm.fmax(tau_hub, tau_pocket)
    sigma_b = 6.0 * clamped_annular_plate_moment_Nmm_per_mm(P, a, b, nu) / t ** 2
    out = {"shear_torsion_hub_MPa": tau_T, "shear_force_hub_MPa": tau_F, "shear_pocket_MPa": tau_pocket,
           "shear_MPa": tau, "bending_MPa": sigma_b, "von_mises_MPa": nm.sqrt(sigma_b ** 2 + 3.0 * tau ** 2)}
    if nm.is_numeric(*out.values()):
        check_result("web_stress", out, {"torque_Nm": torque_Nm, "axial_force_N": axial_force_N,
                                         "hub_outer_diameter_mm": hub_outer_diameter_mm,
                                         "rim_inner_diameter_mm": rim_inner_diameter_mm,
                                         "web_thickness_mm": web_thickness_mm})
    return out


def goodman_equivalent_fully_reversed_MPa(alternating_MPa, mean_MPa, ultimate_strength_MPa):
    """Equivalent fully reversed stress by the modified Goodman line [MPa]: ``sigma_a / (1 - sigma_m/S_ut)`` for a
    tensile (or zero) mean; a compressive mean gets no credit (sigma_a). Raises (numeric) if sigma_m >= S_ut."""
    if nm.is_numeric(mean_MPa, ultimate_strength_MPa) and np.any(np.asarray(nm.value(mean_MPa))
                                                                 >= nm.to_float(ultimate_strength_MPa)):
        raise GearoptInputError(f"mean stress {mean_MPa!r} MPa reaches the ultimate strength "
                                f"{ultimate_strength_MPa!r} MPa: static failure, no Goodman equivalent")
    m = nm.fmax(mean_MPa, 0.0)
    return alternating_MPa / (1.0 - m / ultimate_strength_MPa)


def web_fatigue(forward_stress_MPa, reverse_stress_MPa, *, endurance_limit_MPa, ultimate_strength_MPa,
                yield_strength_MPa=None) -> dict:
    """Goodman / EFR fatigue margins for forward, reverse and forward-reverse loading (module docstring).

    ``forward_stress_MPa``/``reverse_stress_MPa``: equivalent (von Mises) web stress magnitudes at the forward and
    reverse peak loads. Returns {case: {alternating_MPa, mean_MPa, max_MPa, efr_MPa, fatigue_margin,
    yield_margin (if yield given)}} for cases ``forward``, ``reverse``, ``forward_reverse``.
    """
    check_range("endurance_limit_MPa", endurance_limit_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    check_range("ultimate_strength_MPa", ultimate_strength_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    sf, sr = nm.fabs(forward_stress_MPa), nm.fabs(reverse_stress_MPa)
    cases = {"forward": (0.5 * sf, 0.5 * sf, sf), "reverse": (0.5 * sr, 0.5 * sr, sr),
             "forward_reverse": (0.5 * (sf + sr), 0.5 * nm.fabs(sf - sr), nm.fmax(sf, sr))}
    out = {}
    for name, (alt, mean, peak) in cases.items():
        efr = goodman_equivalent_fully_reversed_MPa(alt, mean, ultimate_strength_MPa)
        row = {"alternating_MPa": alt, "mean_MPa": mean, "max_MPa": peak, "efr_MPa": efr,
               "fatigue_margin": _ratio(endurance_limit_MPa, efr)}
        if yield_strength_MPa is not None:
            row["yield_margin"] = _ratio(yield_strength_MPa, peak)
        out[name] = row
    return out


def _ratio(capacity, demand):
    """capacity/demand, inf where a numeric demand is exactly zero (an unloaded case has no finite margin)."""
    if nm.is_symbolic(capacity, demand):
        return capacity / demand
    c, d = np.asarray(nm.value(capacity), dtype=float), np.asarray(nm.value(demand), dtype=float)
    r = np.where(d > 0.0, c / np.where(d > 0.0, d, 1.0), np.inf)
    return float(r) if r.ndim == 0 else r


def forward_reverse_from_history(torque_history_Nm) -> tuple[float, float]:
    """(largest forward torque, largest reverse torque magnitude) [N m] of a torque history (0 if never reached)."""
    t = np.asarray(torque_history_Nm, dtype=float)
    return float(max(np.max(t), 0.0)), float(max(-np.min(t), 0.0))


__all__ = ["web_stress", "web_fatigue", "web_torsion_shear_MPa", "web_transverse_shear_MPa",
           "clamped_annular_plate_moment_Nmm_per_mm", "goodman_equivalent_fully_reversed_MPa",
           "forward_reverse_from_history"]
