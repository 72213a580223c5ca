"""Contact (pitting) stress of a cylindrical gear pair: Hertz line contact (thesis Eqs. 3.37, 3.39-3.41) and
ISO 6336-2:2006 method B (nominal and working contact stress, permissible stress, safety factor S_H), dual-typed.

Which method each output uses:

* :func:`hertz_line_contact_stress_MPa` -- Hertz peak pressure p_H = 2 w / (pi b_H) of two cylinders (thesis
  Eqs. 3.37 + 3.39; Shigley, contact of cylinders), b_H from :func:`gearopt.contact.tip_relief.hertz_half_width_mm`.
* :func:`thesis_contact_stress_MPa` -- thesis Eq. 3.40 with Eq. 3.41 **as printed**: radii d_i sin(alpha)/2 on the
  reference circles and F = F_t / cos(alpha). It is the Hertz stress at the pitch point only when the working and
  reference circles coincide (x1 + x2 = 0, standard centre distance).
* :func:`hertz_contact_stress_pair_MPa` -- the same Hertz formula evaluated where the teeth really touch: radii of
  curvature = roll lengths rho_1, rho_2 of the contact point on the line of action (at the working pitch point
  rho_i = d_wi sin(alpha_wt)/2) and the normal load w = T / (r_b b). This is the thesis method corrected for
  profile-shifted gears at a non-standard centre distance (the redesigned spur train).
* :func:`contact_stress_iso6336` -- ISO 6336-2:2006 method B: sigma_H0 = Z_H Z_E Z_eps Z_beta sqrt(F_t/(d1 b)
  (u+1)/u) at the pitch point, sigma_H = Z_B|Z_D sigma_H0 sqrt(K_A K_v K_Hbeta K_Halpha), sigma_HP and S_H.

Units: forces N, lengths mm, stresses MPa, torques N m, angles deg at the public surface.
"""

from __future__ import annotations

import math

from .. import numerics as nm
from .hertz import hertz_half_width_mm
from ..errors import GearoptInputError
from ..geometry.forces import tangential_force_N
from ..validation import check_range, per_gear
from .validity import check_rating_validity, checked_rating
from ..units import RAD_PER_DEG
from .materials import material_pair

#: The method string attached to ISO contact-stress results.
ISO_CONTACT_METHOD = "ISO 6336-2:2006 method B"
#: Named contact points of :func:`hertz_contact_stress_pair_MPa` (roll lengths on gear 1 from the pair geometry).
CONTACT_POINTS = ("pitch", "lpstc", "hpstc", "sap", "eap")


# ----------------------------------------------------------------------------------------------------------------
# Hertz line contact (thesis)
# ----------------------------------------------------------------------------------------------------------------

def hertz_line_contact_stress_MPa(load_per_width_N_per_mm, radius1_mm, radius2_mm, E_MPa=206000.0, poisson=0.3):
    """Peak Hertz pressure of two parallel cylinders in line contact, p_H = 2 w / (pi b_H) [MPa] (thesis Eq. 3.39
    with b_H of Eq. 3.37; Shigley's Mechanical Engineering Design, contact stresses of cylinders)::

        p_H = sqrt( w (1/R1 + 1/R2) / (pi [(1-nu1^2)/E1 + (1-nu2^2)/E2]) )

    Args: ``load_per_width_N_per_mm`` w [N/mm] >= 0; ``radius1_mm``, ``radius2_mm`` radii of curvature [mm] > 0;
    ``E_MPa`` [MPa] and ``poisson`` scalars or 2-tuples (body 1, body 2). Dual-typed (scalars / CasADi).
    Valid for linear elastic, frictionless line contact with b_H << R_i.
    """
    b_h = hertz_half_width_mm(load_per_width_N_per_mm, radius1_mm, radius2_mm, E_MPa, poisson)
    return 2.0 * load_per_width_N_per_mm / (math.pi * b_h)


def thesis_contact_stress_MPa(tangential_force_N, face_width_mm, pitch_diameters_mm, pressure_angle_deg=20.0,
                              E_MPa=206000.0, poisson=0.3):
    """Thesis Eq. 3.40 with the radii of Eq. 3.41 as printed [MPa]::

        sigma_c = sqrt( F_t / (pi b cos(alpha)) (1/r1 + 1/r2) / [(1-nu1^2)/E1 + (1-nu2^2)/E2] ),
        r_i = d_i sin(alpha) / 2

    Args: ``tangential_force_N`` F_t [N] on the circles ``pitch_diameters_mm`` (d1, d2) [mm]; ``face_width_mm`` b
    [mm]; ``pressure_angle_deg`` alpha; ``E_MPa``, ``poisson`` scalars or 2-tuples. Dual-typed.

    Exact (Hertz at the pitch point) when d_i are the working pitch diameters and alpha the working pressure angle;
    with reference diameters and the tool pressure angle -- the thesis' reading -- only for x1 + x2 = 0. Use
    :func:`hertz_contact_stress_pair_MPa` for a pair.
    """
    check_range("tangential_force_N", tangential_force_N, 0.0, None, unit="N")
    check_range("face_width_mm", face_width_mm, 0.0, None, low_inclusive=False, unit="mm")
    E, nu = per_gear(E_MPa, "E_MPa"), per_gear(poisson, "poisson")
    d = per_gear(pitch_diameters_mm, "pitch_diameters_mm")
    alpha = pressure_angle_deg * RAD_PER_DEG
    r1, r2 = d[0] * nm.sin(alpha) / 2.0, d[1] * nm.sin(alpha) / 2.0
    compliance = (1.0 - nu[0] ** 2) / E[0] + (1.0 - nu[1] ** 2) / E[1]
    return nm.sqrt(tangential_force_N / (math.pi * face_width_mm * nm.cos(alpha)) * (1.0 / r1 + 1.0 / r2)
                   / compliance)


def _driving_torque(torque_Nm, driving_gear):
    if driving_gear not in (1, 2):
        raise GearoptInputError(f"driving_gear={driving_gear!r} must be 1 or 2")
    check_range("torque_Nm", torque_Nm, 0.0, None, low_inclusive=False, unit="N m")


def hertz_contact_stress_pair_MPa(pair, torque_Nm, *, driving_gear: int = 1, point: str = "pitch",
                                  roll_length_mm=None, material="20MnCr5", load_share=1.0):
    """Hertz contact stress of a pair at a point of its path of contact [MPa], the thesis method (Eqs. 3.37-3.41)
    corrected for profile-shifted gears.

    The radii of curvature are the roll lengths of the contact point on each gear, rho_1 and rho_2 = T1T2 - rho_1
    (at the working pitch point rho_i = d_wi sin(alpha_wt)/2), and the normal load per unit face width is
    ``load_share`` x T / (r_b b) of the driving gear (b = min(b1, b2)). ``point``: ``"pitch"`` (working pitch point,
    default), ``"lpstc"``/``"hpstc"`` (gear 1's lowest/highest point of single contact), ``"sap"``/``"eap"``; or
    give ``roll_length_mm`` (roll length on gear 1 [mm], overrides ``point``). ``material``: name/Material or
    2-tuple (gear 1, gear 2). ``load_share``: fraction of the load on this tooth pair (1 = single contact).
    Dual-typed. Spur pairs: the transverse section is the contact section; for helical pairs this is the value of
    one transverse slice carrying the whole load per face width, not the ISO rating.
    """
    _driving_torque(torque_Nm, driving_gear)
    m1, m2 = material_pair(material)
    g = pair.geometry()
    if roll_length_mm is None:
        if point not in CONTACT_POINTS:
            raise GearoptInputError(f"point={point!r} must be one of {CONTACT_POINTS}")
        key = "pitch_point_roll_length_mm" if point == "pitch" else f"{point}_roll_length_mm"
        roll_length_mm = g[key][0]
    t1t2 = g["centre_distance_mm"] * nm.sin(g["working_pressure_angle_deg"] * RAD_PER_DEG)
    b = nm.fmin(g["face_width_mm"][0], g["face_width_mm"][1])
    w = load_share * torque_Nm * 1000.0 / (0.5 * g["base_diameter_mm"][driving_gear - 1]) / b
    return hertz_line_contact_stress_MPa(w, roll_length_mm, t1t2 - roll_length_mm, (m1.E_MPa, m2.E_MPa),
                                         (m1.poisson_ratio, m2.poisson_ratio))


# ----------------------------------------------------------------------------------------------------------------
# ISO 6336-2 method B
# ----------------------------------------------------------------------------------------------------------------

def zone_factor(base_helix_angle_deg, working_pressure_angle_deg, transverse_pressure_angle_deg):
    """ISO 6336-2 zone factor Z_H = sqrt(2 cos(beta_b) cos(alpha_wt) / (cos^2(alpha_t) sin(alpha_wt))) (clause 6.1).
    2.495 for a standard spur pair (20 deg, x1 + x2 = 0). Dual-typed; angles in degrees."""
    bb = base_helix_angle_deg * RAD_PER_DEG
    awt = working_pressure_angle_deg * RAD_PER_DEG
    at = transverse_pressure_angle_deg * RAD_PER_DEG
    return nm.sqrt(2.0 * nm.cos(bb) * nm.cos(awt) / (nm.cos(at) ** 2 * nm.sin(awt)))


def contact_ratio_factor(transverse_contact_ratio, overlap_contact_ratio=0.0):
    """ISO 6336-2 contact ratio factor Z_eps (clause 8): spur sqrt((4 - eps_a)/3); helical with eps_b < 1
    sqrt((4 - eps_a)/3 (1 - eps_b) + eps_b/eps_a); eps_b >= 1: sqrt(1/eps_a). Dual-typed."""
    ea, eb = transverse_contact_ratio, overlap_contact_ratio
    partial = (4.0 - ea) / 3.0 * (1.0 - eb) + eb / ea
    return nm.sqrt(nm.where(eb < 1.0, partial, 1.0 / ea))


def helix_angle_factor_contact(helix_angle_deg):
    """ISO 6336-2:2006 helix angle factor Z_beta = 1/sqrt(cos(beta)) (clause 9). Dual-typed."""
    return 1.0 / nm.sqrt(nm.cos(helix_angle_deg * RAD_PER_DEG))


def single_pair_contact_factors(g: dict, pinion: int):
    """ISO 6336-2 clause 6.2 auxiliary values (M1, M2) and single pair tooth contact factors (Z_B, Z_D).

    M1 = tan(alpha_wt) / sqrt{ [sqrt(d_a1^2/d_b1^2 - 1) - 2 pi/z1] [sqrt(d_a2^2/d_b2^2 - 1) - (eps_a - 1) 2 pi/z2] },
    M2 likewise with the gears swapped (index 1 = pinion, 2 = wheel); M1^2 is the ratio of the relative curvatures
    at the pinion's inner point of single contact and at the pitch point, M2^2 the same at the wheel's.
    Z_B = max(1, M1 - eps_b' (M1 - 1)), Z_D = max(1, M2 - eps_b' (M2 - 1)), eps_b' = min(eps_beta, 1): spur
    max(1, M), helical with eps_beta >= 1 one (ISO's cases in one expression; exact ``fmax``, non-smooth where
    M = 1). ``g``: a pair's geometry dict; ``pinion``: 0 or 1, the index of the pinion. Dual-typed.
    """
    w = 1 - pinion
    z = g["teeth"]
    ea, eb = g["transverse_contact_ratio"], g["overlap_contact_ratio"]
    tan_awt = nm.tan(g["working_pressure_angle_deg"] * RAD_PER_DEG)

    def tan_tip(i):
        ratio = g["tip_diameter_mm"][i] / g["base_diameter_mm"][i]
        return nm.sqrt(ratio * ratio - 1.0)

    m1 = tan_awt / nm.sqrt((tan_tip(pinion) - 2.0 * math.pi / z[pinion])
                           * (tan_tip(w) - (ea - 1.0) * 2.0 * math.pi / z[w]))
    m2 = tan_awt / nm.sqrt((tan_tip(w) - 2.0 * math.pi / z[w])
                           * (tan_tip(pinion) - (ea - 1.0) * 2.0 * math.pi / z[pinion]))
    eb1 = nm.fmin(eb, 1.0)
    z_b = nm.fmax(1.0, m1 - eb1 * (m1 - 1.0))
    z_d = nm.fmax(1.0, m2 - eb1 * (m2 - 1.0))
    return m1, m2, z_b, z_d


def nominal_tangential_force_N(pair, torque_Nm, driving_gear: int = 1):
    """ISO 6336-1 nominal transverse tangential load at the reference cylinder, F_t = 2000 T / d [N], with ``torque_Nm``
    on gear ``driving_gear`` and d its reference diameter [mm] (the same F_t on both gears). Dual-typed."""
    _driving_torque(torque_Nm, driving_gear)
    g = pair.geometry()
    return tangential_force_N(torque_Nm, g["pitch_diameter_mm"][driving_gear - 1])


def _check_factors(**factors):
    """Positive, finite rating factors; a tuple is accepted only for the per-gear life factor (length 2)."""
    for name, value in factors.items():
        if isinstance(value, (tuple, list)):
            if name != "life_factor" or len(value) != 2:
                raise GearoptInputError(f"{name}={value!r} must be a positive number"
                                        + (" or a 2-tuple (gear 1, gear 2)" if name == "life_factor" else ""))
            for i, v in enumerate(value):
                check_range(f"{name}[{i}]", v, 0.0, None, low_inclusive=False)
        else:
            check_range(name, value, 0.0, None, low_inclusive=False)


def contact_stress_iso6336(pair, torque_Nm, *, driving_gear: int = 1, K_A=1.0, K_v=1.0, K_Hbeta=1.0,
                           K_Halpha=1.0, material="20MnCr5", life_factor=1.0, Z_L=1.0, Z_v=1.0, Z_R=1.0,
                           Z_W=1.0, Z_X=1.0, S_Hmin=1.0) -> dict:
    """Contact stress, permissible contact stress and safety factor of a pair, ISO 6336-2:2006 method B. Dual-typed.

    Args:
        pair: :class:`~gearopt.geometry.pair.GearPair` (spur or helical, numeric or CasADi-symbolic).
        torque_Nm: nominal torque [N m] > 0 on gear ``driving_gear`` (1 or 2); F_t = 2000 T/d on its reference
            diameter (:func:`nominal_tangential_force_N`).
        K_A, K_v, K_Hbeta, K_Halpha: application, dynamic, face and transverse load factors (ISO 6336-1), supplied
            by the user (default 1).
        material: catalogue name, :class:`~gearopt.rating.materials.Material`, or a 2-tuple (gear 1, gear 2):
            gives E, nu (Z_E) and sigma_Hlim.
        life_factor: Z_NT (ISO 6336-2 clause 10), scalar or 2-tuple; Z_L, Z_v, Z_R (lubricant, velocity,
            roughness), Z_W (work hardening), Z_X (size): scalars, default 1. S_Hmin: minimum safety factor.

    Returns a dict (per-gear values as 2-tuples (gear 1, gear 2)):
        ``F_t_N``, ``u`` (z_wheel/z_pinion >= 1), ``pinion`` (1 or 2, the gear with fewer teeth; gear 1 if equal),
        ``Z_H``, ``Z_E`` [sqrt(MPa)], ``Z_eps``, ``Z_beta``, ``M1``, ``M2``, ``Z_B`` (pinion), ``Z_D`` (wheel),
        ``Z_BD`` (per gear: Z_B for the pinion, Z_D for the wheel), ``sigma_H0_MPa`` (nominal, pitch point),
        ``sigma_H_MPa`` (per gear), ``sigma_HP_MPa`` (per gear, = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X / S_Hmin),
        ``safety_factor`` (S_H per gear = sigma_Hlim Z_NT Z_L Z_v Z_R Z_W Z_X / sigma_H), ``safety_factor_min``,
        ``method``.

    Formulas (ISO 6336-2:2006): sigma_H0 = Z_H Z_E Z_eps Z_beta sqrt(F_t (u+1) / (d1 b u)) with d1 the pinion's
    reference diameter and b = min(b1, b2) (ISO: the smaller face width); sigma_H = Z_B|Z_D sigma_H0
    sqrt(K_A K_v K_Hbeta K_Halpha); Z_H, Z_eps, Z_beta, Z_B/Z_D as :func:`zone_factor`,
    :func:`contact_ratio_factor`, :func:`helix_angle_factor_contact`, :func:`single_pair_contact_factors`;
    Z_E = sqrt(1 / (pi [(1-nu1^2)/E1 + (1-nu2^2)/E2])). Validity: external cylindrical involute gears, eps_alpha > 1.
    """
    _check_factors(K_A=K_A, K_v=K_v, K_Hbeta=K_Hbeta, K_Halpha=K_Halpha, Z_L=Z_L, Z_v=Z_v, Z_R=Z_R, Z_W=Z_W,
                   Z_X=Z_X, S_Hmin=S_Hmin, life_factor=per_gear(life_factor, "life_factor"))
    z_nt = per_gear(life_factor, "life_factor")
    m1, m2 = material_pair(material)
    for m in (m1, m2):
        m.require("sigma_Hlim_MPa")
    check_rating_validity(pair, ISO_CONTACT_METHOD)
    g = pair.geometry()
    F_t = nominal_tangential_force_N(pair, torque_Nm, driving_gear)
    z = g["teeth"]
    p = 0 if z[0] <= z[1] else 1
    u = z[1 - p] / z[p]
    d1 = g["pitch_diameter_mm"][p]
    b = nm.fmin(g["face_width_mm"][0], g["face_width_mm"][1])
    Z_H = zone_factor(g["base_helix_angle_deg"], g["working_pressure_angle_deg"], g["transverse_pressure_angle_deg"])
    compliance = (1.0 - m1.poisson_ratio ** 2) / m1.E_MPa + (1.0 - m2.poisson_ratio ** 2) / m2.E_MPa
    Z_E = math.sqrt(1.0 / (math.pi * compliance))
    Z_eps = contact_ratio_factor(g["transverse_contact_ratio"], g["overlap_contact_ratio"])
    Z_beta = helix_angle_factor_contact(g["helix_angle_deg"])
    M1, M2, Z_B, Z_D = single_pair_contact_factors(g, p)
    sigma_H0 = Z_H * Z_E * Z_eps * Z_beta * nm.sqrt(F_t / (d1 * b) * (u + 1.0) / u)
    load = nm.sqrt(K_A * K_v * K_Hbeta * K_Halpha)
    z_bd = (Z_B, Z_D) if p == 0 else (Z_D, Z_B)
    sigma_H = tuple(z_bd[i] * sigma_H0 * load for i in range(2))
    strength = tuple(m.sigma_Hlim_MPa * z_nt[i] * Z_L * Z_v * Z_R * Z_W * Z_X for i, m in enumerate((m1, m2)))
    safety = tuple(strength[i] / sigma_H[i] for i in range(2))
    return checked_rating("contact_stress_iso6336", {
        "F_t_N": F_t, "u": u, "pinion": p + 1, "Z_H": Z_H, "Z_E": Z_E, "Z_eps": Z_eps, "Z_beta": Z_beta,
        "M1": M1, "M2": M2, "Z_B": Z_B, "Z_D": Z_D, "Z_BD": z_bd, "sigma_H0_MPa": sigma_H0, "sigma_H_MPa": sigma_H,
        "sigma_HP_MPa": tuple(s / S_Hmin for s in strength), "safety_factor": safety,
        "safety_factor_min": nm.fmin(safety[0], safety[1]), "method": ISO_CONTACT_METHOD,
    }, pair, torque_Nm=torque_Nm, K_A=K_A, K_v=K_v, material=material)


__all__ = ["ISO_CONTACT_METHOD", "CONTACT_POINTS", "hertz_line_contact_stress_MPa", "thesis_contact_stress_MPa",
           "hertz_contact_stress_pair_MPa", "zone_factor", "contact_ratio_factor", "helix_angle_factor_contact",
           "single_pair_contact_factors", "nominal_tangential_force_N", "contact_stress_iso6336"]
