"""Tip-relief physics of a spur gear pair: Hertzian contact, tooth deflection and the minimum tip relief
(thesis section 3.9.1, Eqs. 3.28-3.38, after Markovic & Vrcan 2016), dual-typed.

The minimum tip relief of gear i is the part of the loaded pair's deflection that the tip of gear i must give way
(thesis Eq. 3.38)::

    C_t,i = delta_b,i + delta_H / 2

``delta_b,i`` is the deflection of one tooth of gear i under the full normal load of the pair (Eq. 3.29, Markovic &
Vrcan's fit) and ``delta_H`` the Hertzian approach of the two flanks, split equally; C_t,1 + C_t,2 is the total
deflection of one loaded tooth pair, comparable with ISO 6336-1's w/c' at the pitch point (tested).

What differs from the thesis as printed (see each function and docs/source-study.md sec. 2):

* Eq. 3.36 drops the pi/(2z) term of the base-circle half tooth angle. The correct angle (ISO 21771) is
  ``psi_b = s_t/d + inv(alpha_t) = pi/(2z) + 2 x tan(alpha_n)/z + inv(alpha_t)``; the printed one describes a tooth
  whose reference-circle thickness is 2 x m tan(alpha_n) instead of m (pi/2 + 2 x tan(alpha_n)).
* Eq. 3.35 prints ``omega_b = r_r/r_b - phi``; Eq. 3.34 is only geometric with ``omega_b = tan(alpha_y) - psi_b``
  (roll angle rho/r_b of the load point minus the half tooth angle): then ``alpha_y - omega_b`` is the polar angle of
  the contact point from the tooth centreline and ``r_y cos(alpha_y - omega_b)`` its height along the centreline.
* Eq. 3.28 (Hertzian deformation ``2F(1-nu^2)/(pi b E) [1.27 + 0.78 ln(m/b_H)]``) is not the approach of two elastic
  bodies: plane-strain elasticity fixes the load dependence of any line-contact approach to
  ``2w(1-nu^2)/(pi E) x ln(1/b_H)`` *per body* (the logarithmic near field of the Hertz pressure, independent of the
  far geometry), i.e. a coefficient 2 in front of ``ln(1/b_H)`` for the two flanks, not 0.78. We use Weber's
  (1949) compression of each tooth from the contact to its centreline (:func:`hertz_compression_weber_um`), the
  natural reference of a beam-type tooth deflection (the fit's own reference could not be checked), and offer the approach of the centres
  of the two osculating cylinders (Johnson 1985, :func:`hertz_approach_cylinders_um`) and the printed Eq. 3.28
  (:func:`hertz_approach_thesis_um`) for comparison. The text of Markovic & Vrcan (2016) could not be retrieved
  here, so the fit coefficients of Eqs. 3.30-3.33 are used as the thesis prints them.

Units: lengths mm, load per unit face width N/mm, Young's modulus MPa (= N/mm^2), deflections um at the public
surface, angles rad inside. Spur gears only (the deflection fit is for spur teeth).
"""

from __future__ import annotations

import math
from typing import Any

import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range, per_gear
from ..units import RAD_PER_DEG, UM_PER_MM
from ..rating.hertz import (E_STEEL_MPA, POISSON_STEEL, HALF_WIDTH_SQ_FLOOR_MM2, check_elastic_material,
                            hertz_approach_cylinders_um, hertz_approach_thesis_um, hertz_compression_weber_um,
                            hertz_half_width_mm, plane_strain_compliance_per_MPa)

#: Contact points at which :func:`min_tip_relief_um` can evaluate the deflections (see there).
CONTACT_POINTS = ("pitch", "hpstc", "tip")
#: Hertzian approach models (see :func:`min_tip_relief_um`).
HERTZ_MODELS = ("weber", "cylinders", "thesis")

Number = Any  # float, ndarray or CasADi expression


# ----------------------------------------------------------------------------------------------------------------
# load point on the tooth (thesis Eqs. 3.34-3.36, corrected)
# ----------------------------------------------------------------------------------------------------------------

def base_half_tooth_angle_rad(teeth, profile_shift, pressure_angle_deg=20.0):
    """Half the angular tooth thickness on the base circle, psi_b [rad], of a spur gear (ISO 21771)::

        psi_b = s/d + inv(alpha) = pi/(2 z) + 2 x tan(alpha)/z + inv(alpha)

    with s = m (pi/2 + 2 x tan alpha) the reference-circle tooth thickness (zero thickness allowance). This is the
    corrected thesis Eq. 3.36, which omits pi/(2z) (docs/source-study.md sec. 2). Dual-typed in ``profile_shift`` x and
    ``pressure_angle_deg`` alpha [deg].
    """
    alpha = pressure_angle_deg * RAD_PER_DEG
    return (0.5 * math.pi + 2.0 * profile_shift * nm.tan(alpha)) / teeth + nm.involute(alpha)


def thesis_base_half_tooth_angle_rad(teeth, profile_shift, pressure_angle_deg=20.0):
    """Thesis Eq. 3.36 as printed, phi = 4 x tan(alpha)/(2 z) + inv(alpha) [rad] -- WRONG, for comparison only:
    it lacks pi/(2z), i.e. it is the half angle of a tooth with reference thickness 2 x m tan(alpha)."""
    alpha = pressure_angle_deg * RAD_PER_DEG
    return 4.0 * profile_shift * nm.tan(alpha) / (2.0 * teeth) + nm.involute(alpha)


def load_point_geometry(roll_length_mm, base_diameter_mm, root_diameter_mm, module_mm, half_tooth_angle_rad):
    """Where a normal load acting at a flank point meets the tooth (thesis Eqs. 3.34-3.35, corrected), dual-typed.

    Args: ``roll_length_mm`` rho of the contact point [mm] (> 0); ``base_diameter_mm`` d_b, ``root_diameter_mm``
    d_f [mm]; ``module_mm`` m [mm]; ``half_tooth_angle_rad`` psi_b (:func:`base_half_tooth_angle_rad`).

    Returns a dict (units in the keys):

    * ``radius_mm`` r_y = sqrt(r_b^2 + rho^2) and ``pressure_angle_rad`` alpha_y = atan(rho / r_b);
    * ``polar_angle_rad`` theta = psi_b - inv(alpha_y), the contact point's angle from the tooth centreline;
    * ``load_angle_rad`` omega = tan(alpha_y) - psi_b = alpha_y - theta, the angle between the load line and the
      normal to the tooth centreline (thesis omega_b; ISO 6336-3's load angle alpha_Fen = tan(alpha_en) -
      psi_b has the same form at its load point);
    * ``load_height_modules`` y_bar = (r_y cos(alpha_y - omega) - r_f)/m, the contact point's height above the root
      circle along the centreline in modules (thesis Eq. 3.34);
    * ``centreline_depth_mm`` h = r_y sin(theta)/cos(omega), the distance from the contact point to the tooth
      centreline along the load line (Weber's depth for the Hertz compression).
    """
    check_range("roll_length_mm", roll_length_mm, 0.0, None, low_inclusive=False, unit="mm")
    r_b = 0.5 * base_diameter_mm
    r_f = 0.5 * root_diameter_mm
    tan_alpha = roll_length_mm / r_b
    alpha = nm.atan(tan_alpha)
    radius = nm.sqrt(r_b * r_b + roll_length_mm * roll_length_mm)
    theta = half_tooth_angle_rad - (tan_alpha - alpha)
    omega = tan_alpha - half_tooth_angle_rad
    return {
        "radius_mm": radius,
        "pressure_angle_rad": alpha,
        "polar_angle_rad": theta,
        "load_angle_rad": omega,
        "load_height_modules": (radius * nm.cos(alpha - omega) - r_f) / module_mm,
        "centreline_depth_mm": radius * nm.sin(theta) / nm.cos(omega),
    }


# ----------------------------------------------------------------------------------------------------------------
# tooth deflection (thesis Eqs. 3.29-3.33, Markovic & Vrcan 2016)
# ----------------------------------------------------------------------------------------------------------------

def markovic_vrcan_coefficients(teeth, profile_shift, module_mm):
    """Coefficients (A, B, C, D) of the tooth-deflection fit, thesis Eqs. 3.30-3.33 (Markovic & Vrcan 2016)::

        A = -1.05 + 153 exp(-8.1 x) z^-(1.75 - 1.6 x)
        B = 0.63 + (7.35 - 0.924 x)/z
        C = 1.28 - (2.88 + 3.68 x)/z
        D = -1.06 + 0.638 ln(m z)        (m z in mm: the fit is not dimensionless)

    Dual-typed in ``profile_shift`` x; ``teeth`` z; ``module_mm`` m [mm].
    """
    z = teeth
    ln_z = nm.log(z)
    a = -1.05 + 153.0 * nm.exp(-8.1 * profile_shift - (1.75 - 1.6 * profile_shift) * ln_z)
    b = 0.63 + (7.35 - 0.924 * profile_shift) / z
    c = 1.28 - (2.88 + 3.68 * profile_shift) / z
    d = -1.06 + 0.638 * nm.log(module_mm * z)
    return a, b, c, d


def tooth_deflection_um(load_per_width_N_per_mm, teeth, module_mm, profile_shift, load_height_modules,
                        E_MPa=E_STEEL_MPA, poisson=POISSON_STEEL):
    """Deflection of one spur gear tooth along the load line [um] (thesis Eq. 3.29, Markovic & Vrcan 2016)::

        delta_b = w (1-nu^2)/E [A + B exp(C y_bar) + D]

    Args: ``load_per_width_N_per_mm`` normal load per unit face width w [N/mm]; ``teeth`` z; ``module_mm`` m [mm];
    ``profile_shift`` x; ``load_height_modules`` y_bar, the load point's height above the root circle in modules
    (:func:`load_point_geometry`); ``E_MPa`` [MPa]; ``poisson`` nu.

    Linear in w and in (1-nu^2)/E (plane strain); the bracket is the fit's dimensionless compliance (tooth bending,
    shear and the gear body through D). Validity: the fit's range is not stated in the thesis; use for 20-degree
    full-depth spur teeth, m in mm, about 12 <= z <= 200 and -0.5 <= x <= 1 (the thesis' gears lie inside), and
    0 < y_bar <= the tip height. Returns um.
    """
    a, b, c, d = markovic_vrcan_coefficients(teeth, profile_shift, module_mm)
    return UM_PER_MM * load_per_width_N_per_mm * plane_strain_compliance_per_MPa(E_MPa, poisson) \
        * (a + b * nm.exp(c * load_height_modules) + d)


# ----------------------------------------------------------------------------------------------------------------
# minimum tip relief of a pair (thesis Eq. 3.38)
# ----------------------------------------------------------------------------------------------------------------

def _contact_roll_lengths(g: dict, contact_point: str) -> tuple[tuple, tuple]:
    """For each gear i: (roll length of gear i's load point, roll length of the mating gear at the same contact)."""
    if contact_point == "pitch":
        rho = g["pitch_point_roll_length_mm"]
        return (rho[0], rho[1]), (rho[1], rho[0])
    if contact_point == "hpstc":  # gear 1 at its HPSTC (D) meets gear 2 at its LPSTC, and vice versa
        return (g["hpstc_roll_length_mm"][0], g["lpstc_roll_length_mm"][1]), \
               (g["hpstc_roll_length_mm"][1], g["lpstc_roll_length_mm"][0])
    if contact_point == "tip":  # gear 1's tip (EAP) meets gear 2 at its SAP, and vice versa
        return (g["eap_roll_length_mm"][0], g["sap_roll_length_mm"][1]), \
               (g["eap_roll_length_mm"][1], g["sap_roll_length_mm"][0])
    raise GearoptInputError(f"contact_point={contact_point!r} must be one of {CONTACT_POINTS}")


def normal_load_per_width_N_per_mm(pair, torque_Nm, driving_gear: int = 1):
    """Normal tooth load per unit face width w = F_bn / b [N/mm] when one tooth pair carries ``torque_Nm``.

    ``F_bn = T / r_b`` of the driving gear, which equals ``F_tw / cos(alpha_wt)`` with the tangential force
    ``F_tw = T / r_w`` on the working pitch radius (r_b = r_w cos alpha_wt); b = the common face width
    min(b1, b2) [mm]. ``torque_Nm`` [N m] acts on gear ``driving_gear`` (1 or 2). Spur pairs.
    """
    if driving_gear not in (1, 2):
        raise GearoptInputError(f"driving_gear={driving_gear!r} must be 1 or 2")
    check_range("torque_Nm", torque_Nm, 0.0, None, low_inclusive=False, unit="N m")
    g = pair.geometry()
    r_b = 0.5 * g["base_diameter_mm"][driving_gear - 1]
    b = nm.fmin(g["face_width_mm"][0], g["face_width_mm"][1])
    return torque_Nm * 1000.0 / r_b / b


def _check_spur(pair) -> None:
    beta = pair.helix_angle_deg
    if nm.is_symbolic(beta) or nm.to_float(beta) != 0.0:
        raise GearoptInputError(f"helix_angle_deg={beta!r}: the tip-relief model (Markovic & Vrcan's tooth "
                                f"deflection fit) is for spur pairs; helix_angle_deg must be 0")


def _hertz_approach_um(model, w, b_h, rho, depth, E, nu, module_mm):
    if model == "weber":
        return (hertz_compression_weber_um(w, b_h, depth[0], E[0], nu[0])
                + hertz_compression_weber_um(w, b_h, depth[1], E[1], nu[1]))
    if model == "cylinders":
        return hertz_approach_cylinders_um(w, rho[0], rho[1], E, nu)
    if model == "thesis":
        E_mean = 2.0 / (1.0 / E[0] + 1.0 / E[1])
        nu_mean = 0.5 * (nu[0] + nu[1])
        return hertz_approach_thesis_um(w, b_h, module_mm, E_mean, nu_mean)
    raise GearoptInputError(f"hertz_model={model!r} must be one of {HERTZ_MODELS}")


def min_tip_relief_um(pair, torque_Nm, driving_gear: int = 1, E_MPa=E_STEEL_MPA, poisson=POISSON_STEEL,
                      parts: bool = False, contact_point: str = "pitch", hertz_model: str = "weber"):
    """Minimum tip relief C_t,i = delta_b,i + delta_H/2 of both gears of a spur pair [um] (thesis Eq. 3.38).

    Args:
        pair: a spur :class:`~gearopt.geometry.pair.GearPair` (numeric or CasADi-symbolic).
        torque_Nm: torque [N m] on the driving gear, carried by ONE tooth pair (single contact, as the thesis).
        driving_gear: 1 or 2, the gear that ``torque_Nm`` acts on. The normal load is w = T/(r_b b) =
            F_tw/(b cos alpha_wt) with F_tw on the working pitch radius (:func:`normal_load_per_width_N_per_mm`).
        E_MPa, poisson: Young's modulus [MPa] and Poisson's ratio, scalars or 2-tuples (gear 1, gear 2).
        parts: return the parts (dict below) instead of the 2-tuple.
        contact_point: where the load acts.
            ``"pitch"`` (default, the thesis): Eq. 3.34 evaluates the tooth at r_p and the working pressure angle
            alpha_w, i.e. at the working pitch point, for both gears -- the point at which ISO 6336's single-pair
            stiffness c' is defined, so C_t,1 + C_t,2 = w/c' there. ``"hpstc"``: gear i loaded at its highest point
            of single tooth contact (the largest single-pair deflection). ``"tip"``: gear i loaded at its own tip.
            The Hertz part is evaluated at the same contact (gear i's point and the mating gear's point there).
        hertz_model: ``"weber"`` (default): both teeth compressed from the contact to their centrelines (Weber,
            :func:`hertz_compression_weber_um` with the depths of :func:`load_point_geometry`); ``"cylinders"``:
            approach of the osculating cylinders' axes (:func:`hertz_approach_cylinders_um`); ``"thesis"``: the
            printed Eq. 3.28 (:func:`hertz_approach_thesis_um`).

    Returns (C_t,1, C_t,2) [um]; with ``parts=True`` a dict with ``min_tip_relief_um`` (that 2-tuple),
    ``tooth_deflection_um`` (delta_b per gear), ``hertz_deformation_um`` (delta_H per gear, evaluated at each gear's
    contact; equal for ``"pitch"``), ``hertz_half_width_mm``, ``load_height_modules``, ``centreline_depth_mm``
    (per gear, at its load point), ``load_roll_length_mm`` and the scalar ``normal_load_per_width_N_per_mm``.

    The half-tooth angle includes the pi/(2z) term that thesis Eq. 3.36 drops; see the module docstring for Eq. 3.28.
    Validity: spur, 20-degree-type full-depth teeth, ranges of :func:`tooth_deflection_um`; full load on one pair
    (an upper bound in the double-contact zone).
    """
    _check_spur(pair)
    E, nu = check_elastic_material(E_MPa, poisson)
    if contact_point not in CONTACT_POINTS:
        raise GearoptInputError(f"contact_point={contact_point!r} must be one of {CONTACT_POINTS}")
    if hertz_model not in HERTZ_MODELS:
        raise GearoptInputError(f"hertz_model={hertz_model!r} must be one of {HERTZ_MODELS}")
    g = pair.geometry()
    w = normal_load_per_width_N_per_mm(pair, torque_Nm, driving_gear)
    m = g["module_mm"]
    psi_b = tuple(g["transverse_tooth_thickness_mm"][i] / g["pitch_diameter_mm"][i]
                  + nm.involute(g["transverse_pressure_angle_deg"] * RAD_PER_DEG) for i in range(2))

    def point(i, rho):
        return load_point_geometry(rho, g["base_diameter_mm"][i], g["root_diameter_mm"][i], m, psi_b[i])

    contacts = _contact_roll_lengths(g, contact_point)
    out = {k: [None, None] for k in ("tooth_deflection_um", "hertz_deformation_um", "hertz_half_width_mm",
                                      "load_height_modules", "centreline_depth_mm", "load_roll_length_mm")}
    for i in range(2):
        j = 1 - i
        rho_i, rho_j = contacts[i]
        own, mate = point(i, rho_i), point(j, rho_j)
        rho = (rho_i, rho_j) if i == 0 else (rho_j, rho_i)  # (gear 1, gear 2) at this contact
        depth = (own, mate) if i == 0 else (mate, own)
        b_h = hertz_half_width_mm(w, rho[0], rho[1], E, nu)
        out["hertz_half_width_mm"][i] = b_h
        out["hertz_deformation_um"][i] = _hertz_approach_um(
            hertz_model, w, b_h, rho, (depth[0]["centreline_depth_mm"], depth[1]["centreline_depth_mm"]), E, nu, m)
        out["tooth_deflection_um"][i] = tooth_deflection_um(w, pair.teeth[i], m, pair.profile_shifts[i],
                                                            own["load_height_modules"], E[i], nu[i])
        out["load_height_modules"][i] = own["load_height_modules"]
        out["centreline_depth_mm"][i] = own["centreline_depth_mm"]
        out["load_roll_length_mm"][i] = rho_i
    relief = tuple(out["tooth_deflection_um"][i] + 0.5 * out["hertz_deformation_um"][i] for i in range(2))
    if not parts:
        return relief
    result = {k: tuple(v) for k, v in out.items()}
    result["min_tip_relief_um"] = relief
    result["normal_load_per_width_N_per_mm"] = w
    return result


# ----------------------------------------------------------------------------------------------------------------
# train table (thesis Table 3.7 analogue)
# ----------------------------------------------------------------------------------------------------------------

def min_tip_relief_table(train, torques_Nm: dict, **options) -> pd.DataFrame:
    """Thesis Table 3.7 analogue: Hertzian deformation, tooth (elastic) deformation and minimum tip relief per gear of
    every mesh named in ``torques_Nm``.

    Args: ``train`` a numeric spur :class:`~gearopt.geometry.train.GearTrain`; ``torques_Nm`` {mesh name: torque
    [N m] on that mesh's driving (first) gear}; ``options`` passed to :func:`min_tip_relief_um` (``E_MPa``,
    ``poisson``, ``contact_point``, ``hertz_model``).

    Returns a DataFrame, one row per mesh (in the train's order), columns ``mesh``, ``gear_1``, ``gear_2``,
    ``torque_Nm``, ``normal_load_per_width_N_per_mm``, ``hertz_half_width_mm``, ``hertz_deformation_um`` (pair
    approach delta_H at gear 1's contact; equal for both gears at the pitch point), ``elastic_deformation_1_um``,
    ``elastic_deformation_2_um`` (delta_b), ``min_tip_relief_1_um``, ``min_tip_relief_2_um`` (C_t). The thesis table
    is normalised by the largest value of each quantity; a gear in several meshes needs the largest of its reliefs
    (:func:`governing_tip_relief_um`).
    """
    unknown = sorted(set(torques_Nm) - set(train.pairs))
    if unknown:
        raise GearoptInputError(f"torques_Nm names unknown mesh(es) {unknown}; the train has {sorted(train.pairs)}")
    if not torques_Nm:
        raise GearoptInputError("torques_Nm is empty: give {mesh name: torque on its driving gear [N m]}")
    rows = []
    for name, pair in train.pairs.items():
        if name not in torques_Nm:
            continue
        p = min_tip_relief_um(pair, torques_Nm[name], driving_gear=1, parts=True, **options)
        rows.append({
            "mesh": name,
            "gear_1": pair.names[0],
            "gear_2": pair.names[1],
            "torque_Nm": nm.to_float(torques_Nm[name]),
            "normal_load_per_width_N_per_mm": nm.to_float(p["normal_load_per_width_N_per_mm"]),
            "hertz_half_width_mm": nm.to_float(p["hertz_half_width_mm"][0]),
            "hertz_deformation_um": nm.to_float(p["hertz_deformation_um"][0]),
            "elastic_deformation_1_um": nm.to_float(p["tooth_deflection_um"][0]),
            "elastic_deformation_2_um": nm.to_float(p["tooth_deflection_um"][1]),
            "min_tip_relief_1_um": nm.to_float(p["min_tip_relief_um"][0]),
            "min_tip_relief_2_um": nm.to_float(p["min_tip_relief_um"][1]),
        })
    return pd.DataFrame(rows)


def governing_tip_relief_um(table: pd.DataFrame) -> dict:
    """Largest minimum tip relief [um] of each gear over the meshes of :func:`min_tip_relief_table` (one gear has one
    tip: the thesis' Table 3.7 repeats a gear's largest relief in each of its meshes). Returns {gear name: um}."""
    out: dict[str, float] = {}
    for _, row in table.iterrows():
        for k in (1, 2):
            gear, value = row[f"gear_{k}"], float(row[f"min_tip_relief_{k}_um"])
            out[gear] = max(out.get(gear, value), value)
    return out


__all__ = [
    "E_STEEL_MPA", "POISSON_STEEL", "CONTACT_POINTS", "HERTZ_MODELS", "plane_strain_compliance_per_MPa",
    "hertz_half_width_mm", "hertz_compression_weber_um", "hertz_approach_cylinders_um", "hertz_approach_thesis_um",
    "base_half_tooth_angle_rad", "thesis_base_half_tooth_angle_rad", "load_point_geometry",
    "markovic_vrcan_coefficients", "tooth_deflection_um", "normal_load_per_width_N_per_mm", "min_tip_relief_um",
    "min_tip_relief_table", "governing_tip_relief_um",
]
