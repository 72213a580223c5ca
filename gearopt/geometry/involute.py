"""Involute relations of one cylindrical gear (ISO 21771:2007), dual-typed.

Plain functions of the normal module ``m_n``, normal pressure angle ``alpha_n``, helix angle ``beta`` and tooth
count ``z``; lengths in mm, angles in rad unless the name says ``_deg``. Every function accepts floats, numpy arrays
or CasADi expressions (through :mod:`gearopt.numerics`). External gears only.
"""

from __future__ import annotations

import math

from .. import numerics as nm


def transverse_module(module_mm, helix_angle_rad):
    """Transverse module m_t = m_n / cos(beta) [mm] (ISO 21771 eq. 3)."""
    return module_mm / nm.cos(helix_angle_rad)


def transverse_pressure_angle(pressure_angle_rad, helix_angle_rad):
    """Transverse pressure angle alpha_t = atan(tan(alpha_n)/cos(beta)) [rad] (ISO 21771 eq. 6)."""
    return nm.atan(nm.tan(pressure_angle_rad) / nm.cos(helix_angle_rad))


def base_helix_angle(pressure_angle_rad, helix_angle_rad):
    """Base helix angle beta_b = asin(sin(beta) cos(alpha_n)) [rad] (ISO 21771 eq. 10)."""
    return nm.asin(nm.sin(helix_angle_rad) * nm.cos(pressure_angle_rad))


def virtual_teeth(teeth, helix_angle_rad, base_helix_angle_rad):
    """Virtual number of teeth z_n = z / (cos^2(beta_b) cos(beta)) (ISO 21771 eq. 24)."""
    return teeth / (nm.cos(base_helix_angle_rad) ** 2 * nm.cos(helix_angle_rad))


def reference_diameter(teeth, transverse_module_mm):
    """Reference (pitch) diameter d = z m_t [mm]."""
    return teeth * transverse_module_mm


def base_diameter(reference_diameter_mm, transverse_pressure_angle_rad):
    """Base diameter d_b = d cos(alpha_t) [mm]."""
    return reference_diameter_mm * nm.cos(transverse_pressure_angle_rad)


def roll_length_at(diameter_mm, base_diameter_mm):
    """Roll length (distance along the line of action from the base-circle tangent point) of the involute point on
    diameter d: rho = sqrt(d^2 - d_b^2)/2 [mm]. Guarded: 0 at or below the base circle."""
    return 0.5 * nm.sqrt_safe(diameter_mm ** 2 - base_diameter_mm ** 2)


def diameter_at_roll_length(roll_length_mm, base_diameter_mm):
    """Diameter of the involute point at roll length rho: d = 2 sqrt(r_b^2 + rho^2) [mm]."""
    return 2.0 * nm.sqrt(0.25 * base_diameter_mm ** 2 + roll_length_mm ** 2)


def roll_angle_deg(roll_length_mm, base_diameter_mm):
    """Roll angle xi = rho / r_b in degrees (as LDP and the thesis' Table 3.8 give tip-relief starts)."""
    return nm.fmax(roll_length_mm, 0.0) / (0.5 * base_diameter_mm) * (180.0 / math.pi)


def transverse_tooth_thickness_reference(transverse_module_mm, profile_shift, pressure_angle_rad):
    """Transverse arc tooth thickness on the reference circle s_t = m_t (pi/2 + 2 x tan(alpha_n)) [mm]
    (ISO 21771 eq. 55; zero thickness allowance)."""
    return transverse_module_mm * (0.5 * math.pi + 2.0 * profile_shift * nm.tan(pressure_angle_rad))


def transverse_tooth_thickness_at(diameter_mm, reference_diameter_mm, base_diameter_mm,
                                  transverse_thickness_reference_mm, transverse_pressure_angle_rad):
    """Transverse arc tooth thickness on diameter d_y [mm]:
    s_yt = d_y (s_t/d + inv(alpha_t) - inv(alpha_yt)), cos(alpha_yt) = d_b/d_y (ISO 21771 eq. 57)."""
    alpha_y = nm.acos_safe(base_diameter_mm / diameter_mm)
    return diameter_mm * (transverse_thickness_reference_mm / reference_diameter_mm
                          + nm.involute(transverse_pressure_angle_rad) - nm.involute(alpha_y))


def helix_angle_at(diameter_mm, reference_diameter_mm, helix_angle_rad):
    """Helix angle on diameter d_y: tan(beta_y) = tan(beta) d_y/d [rad] (ISO 21771 eq. 14)."""
    return nm.atan(nm.tan(helix_angle_rad) * diameter_mm / reference_diameter_mm)


def tool_form_height_coefficient(dedendum_coefficient, root_radius_coefficient, pressure_angle_rad):
    """Height of the straight flank of the generating rack below its datum line, h_FfP0/m_n =
    h_fP* - rho_fP* (1 - sin(alpha_n)) (the rack-cutter's addendum is the gear's basic-rack dedendum)."""
    return dedendum_coefficient - root_radius_coefficient * (1.0 - nm.sin(pressure_angle_rad))


def form_roll_length(reference_diameter_mm, transverse_pressure_angle_rad, profile_shift, module_mm,
                     tool_form_height_coefficient_value):
    """Roll length of the generated involute's lowest point (root form diameter d_Ff) for a rack-generated gear:
    rho_Ff = r sin(alpha_t) - (h_FfP0* - x) m_n / sin(alpha_t) [mm]. Negative means the gear is undercut."""
    s = nm.sin(transverse_pressure_angle_rad)
    return 0.5 * reference_diameter_mm * s - (tool_form_height_coefficient_value - profile_shift) * module_mm / s


def undercut_limit_profile_shift(teeth, transverse_pressure_angle_rad, helix_angle_rad,
                                 tool_form_height_coefficient_value):
    """Smallest profile shift without generating undercut, x_min = h_FfP0* - z sin^2(alpha_t) / (2 cos(beta))
    (from ``form_roll_length = 0``; KHK: z_min = 17 for alpha 20 deg, h_a0 = 1)."""
    return tool_form_height_coefficient_value \
        - teeth * nm.sin(transverse_pressure_angle_rad) ** 2 / (2.0 * nm.cos(helix_angle_rad))
