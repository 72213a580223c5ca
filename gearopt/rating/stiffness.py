"""Mesh stiffness and mesh damping of cylindrical gear pairs, dual-typed (floats, arrays or CasADi symbols).

Three models, each with its source:

* :func:`iso6336_stiffness` -- ISO 6336-1 method B: theoretical single stiffness c'_th from the regression
  q' = 1/c'_th in the virtual tooth numbers and profile shifts, corrected to the single stiffness c' and the mean
  mesh stiffness c_gamma_alpha / c_gamma_beta. The standard's stiffness for load-capacity factors and the one the
  rest of gearopt uses.
* :func:`line_of_contact_stiffness` -- the thesis' approach (Eqs. 3.22-3.23, Coy & Zaretsky 1975 / AGMA): a
  stiffness per unit length of contact line times the length of the contact lines. Implemented with the exact
  length of the contact lines (:func:`contact_line_length_mm`); the thesis' printed formulas are available as
  :func:`thesis_contact_line_length_mm` for comparison (they are inconsistent with each other, see there).
* :func:`mesh_damping` -- viscous mesh damping c = 2 zeta sqrt(k m_eq) with the equivalent mass of the two gears
  along the line of action (thesis Eqs. 3.26-3.27, which are dimensionally and physically correct).

:func:`mesh_stiffness_table` collects them for every mesh of a :class:`~gearopt.geometry.GearTrain` (the analogue
of the thesis' Table 3.6).

Units: lengths mm, stiffness per unit face width N/(mm*um) (ISO's unit; numerically equal to GN/m^2), stiffness
N/um or N/m, inertia kg*m^2, mass kg, damping N*s/m, Young's modulus MPa.
"""

from __future__ import annotations

import math
import warnings
import numpy as np
import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range
from ..geometry.pair import GearPair
from ..units import RAD_PER_DEG

#: ISO 6336-1 method B coefficients C1..C9 of q' [mm*um/N] (identical in python-gearbox and the MATLAB class
#: ``ISO_6336``/``Gear_Set`` of gfsReboucas/Drivetrain; docs/default-data.md sec. 1.1).
Q_PRIME_COEFFICIENTS = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
#: ISO 6336-1 correction from theoretical to measured stiffness of solid-disc steel gears.
THEORY_CORRECTION_FACTOR_C_M = 0.8
#: Young's modulus of the steel the method-B regression was made for [MPa] (ISO 6336-1:2019 E/E_st factor).
E_STEEL_MPA = 206000.0
#: ISO 6336-1 validity of the method-B stiffness as asserted in public codes (python-gearbox, gfsReboucas/Drivetrain).
SUM_OF_PROFILE_SHIFTS_RANGE = (-0.5, 2.0)
#: c_gamma_alpha = c'(0.75 eps_alpha + 0.25) holds for eps_alpha >= 1.2 (one public code multiplies by 0.9 below).
MIN_CONTACT_RATIO_FOR_MESH_STIFFNESS = 1.2
#: ISO 6336-1 blank factor C_R: web-to-face-width ratio range and minimum rim-thickness ratio s_R/m_n.
WEB_RATIO_RANGE = (0.2, 1.2)
MIN_RIM_RATIO = 1.0
#: Line load below which the (unverified) light-load correction reduces c' [N/mm].
LIGHT_LOAD_LIMIT_N_PER_MM = 100.0
#: Damping ratio of a gear mesh used by the thesis ("Cummins technical data", sec. 3.6).
THESIS_DAMPING_RATIO = 0.08
#: AGMA factor in the thesis' helical contact-length formula (Eq. 3.22).
AGMA_CONTACT_LENGTH_FACTOR = 0.95
STEEL_DENSITY_KG_M3 = 7850.0

_VALIDITY_MODES = ("warn", "raise", "ignore")


class StiffnessValidityWarning(UserWarning):
    """A numeric input lies outside the published validity of a stiffness formula (the value is still computed)."""


# ----------------------------------------------------------------------------------------------------------------
# ISO 6336-1 method B
# ----------------------------------------------------------------------------------------------------------------

def iso6336_theoretical_single_stiffness(virtual_teeth, profile_shifts) -> dict:
    """ISO 6336-1 method B flexibility q' [mm*um/N] and theoretical single stiffness c'_th = 1/q' [N/(mm*um)].

    ``virtual_teeth`` (z_n1, z_n2) and ``profile_shifts`` (x1, x2) with gear 1 the **pinion** (fewer teeth):
    q' = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1^2 + C9 x2^2
    (C9 multiplies x2^2: the public MATLAB code's C9 x1^2 is a typo). ``z_n2 = math.inf`` gives a rack.
    Dual-typed. Validity (ISO 6336-1 as asserted in public codes): external steel gears, x1 >= x2,
    -0.5 <= x1 + x2 <= 2.0; not checked here (see :func:`iso6336_stiffness`).
    """
    c1, c2, c3, c4, c5, c6, c7, c8, c9 = Q_PRIME_COEFFICIENTS
    zn1, zn2 = virtual_teeth
    x1, x2 = profile_shifts
    inv_zn2 = 0.0 if (isinstance(zn2, float) and math.isinf(zn2)) else 1.0 / zn2
    q = (c1 + c2 / zn1 + c3 * inv_zn2 + c4 * x1 + c5 * x1 / zn1 + c6 * x2 + c7 * x2 * inv_zn2
         + c8 * x1 * x1 + c9 * x2 * x2)
    return {"q_prime": q, "theoretical_single_stiffness": 1.0 / q}


def iso6336_basic_rack_factor(dedendum_coefficient, pressure_angle_deg):
    """ISO 6336-1 basic rack factor C_B = [1 + 0.5(1.2 - h_fP/m_n)] [1 - 0.02(20 deg - alpha_Pn)] (dimensionless).

    ``dedendum_coefficient`` = h_fP/m_n of the basic rack, ``pressure_angle_deg`` = alpha_Pn [deg]. 0.975 for the
    standard rack (1.25, 20 deg); 0.9 for h_fP = 1.4 m_n (ISO/TR 6336-30 example 1). For two different racks the
    2019 edition averages the gears' factors, C_B = (C_B1 + C_B2)/2. Dual-typed.
    """
    return (1.0 + 0.5 * (1.2 - dedendum_coefficient)) * (1.0 - 0.02 * (20.0 - pressure_angle_deg))


def iso6336_blank_factor(web_thickness_mm, rim_thickness_mm, face_width_mm, module_mm):
    """ISO 6336-1 gear blank factor of a web (disc) gear, C_R = 1 + ln(b_s/b) / (5 exp(s_R/(5 m_n))).

    ``web_thickness_mm`` b_s, ``rim_thickness_mm`` s_R (below the root circle), ``face_width_mm`` b, ``module_mm``
    m_n. s_R/m_n enters the exponent once (two public codes divide by m_n twice -- a bug avoided here). Solid disc
    gears: C_R = 1. Validity: 0.2 <= b_s/b <= 1.2 and s_R/m_n >= 1; outside, the ratios are held at those limits
    (as the public codes do; the exponent form itself is tagged [M] in docs/default-data.md sec. 1.1) -- the caller reports it
    (:func:`iso6336_stiffness`). Dual-typed.
    """
    web_ratio = nm.clip(web_thickness_mm / face_width_mm, WEB_RATIO_RANGE[0], WEB_RATIO_RANGE[1])
    rim_ratio = nm.fmax(rim_thickness_mm / module_mm, MIN_RIM_RATIO)
    return 1.0 + nm.log(web_ratio) / (5.0 * nm.exp(rim_ratio / 5.0))


def iso6336_light_load_factor(line_load_N_per_mm):
    """Light-load reduction of c', (min(w, 100)/100)^0.25 with w = F_t K_A / b [N/mm] (dimensionless, <= 1).

    **Unverified** (docs/default-data.md sec. 1.1 tags it [M]: quoted for ISO 6336-1 / DIN 3990 but not found in a public
    source here). Applied only when asked for (``line_load_N_per_mm`` of :func:`iso6336_stiffness`). Dual-typed;
    w must be > 0.
    """
    check_range("line_load_N_per_mm", line_load_N_per_mm, 0.0, None, low_inclusive=False, unit="N/mm")
    w = nm.fmax(line_load_N_per_mm, 1e-9)
    return (nm.fmin(w, LIGHT_LOAD_LIMIT_N_PER_MM) / LIGHT_LOAD_LIMIT_N_PER_MM) ** 0.25


def _pinion_order(pair: GearPair) -> tuple[int, int] | None:
    """Indices (pinion, wheel): the gear with fewer teeth is the pinion; ``None`` for equal tooth counts."""
    z1, z2 = pair.teeth
    if z1 == z2:
        return None
    return (0, 1) if z1 < z2 else (1, 0)


def _blank_factor_pair(pair: GearPair, solid_blanks, rim_thickness_mm, web_thickness_mm, notes):
    """C_R of the pair: ISO's formula per web gear, the mean of both gears' factors (1 for a solid gear)."""
    if solid_blanks:
        if rim_thickness_mm is not None or web_thickness_mm is not None:
            raise GearoptInputError("rim_thickness_mm/web_thickness_mm given with solid_blanks=True; pass "
                                    "solid_blanks=False to use them")
        return 1.0
    if rim_thickness_mm is None or web_thickness_mm is None:
        raise GearoptInputError("solid_blanks=False needs rim_thickness_mm and web_thickness_mm (scalars for both "
                                "gears, or 2-tuples with None for a solid gear)")
    rims = tuple(rim_thickness_mm) if isinstance(rim_thickness_mm, (tuple, list)) else (rim_thickness_mm,) * 2
    webs = tuple(web_thickness_mm) if isinstance(web_thickness_mm, (tuple, list)) else (web_thickness_mm,) * 2
    if len(rims) != 2 or len(webs) != 2:
        raise GearoptInputError(f"rim_thickness_mm={rim_thickness_mm!r} / web_thickness_mm={web_thickness_mm!r} "
                                f"must be scalars or 2-tuples (gear 1, gear 2)")
    factors = []
    for i in range(2):
        if (rims[i] is None) != (webs[i] is None):
            raise GearoptInputError(f"gear {i + 1}: give both rim_thickness_mm and web_thickness_mm, or neither "
                                    f"(solid gear)")
        if rims[i] is None:
            factors.append(1.0)
            continue
        b, m = pair.face_width_mm[i], pair.module_mm
        check_range(f"web_thickness_mm[{i}]", webs[i], 0.0, None, low_inclusive=False, unit="mm")
        check_range(f"rim_thickness_mm[{i}]", rims[i], 0.0, None, low_inclusive=False, unit="mm")
        if nm.is_numeric(webs[i], rims[i], b, m):
            web_ratio, rim_ratio = nm.to_float(webs[i] / b), nm.to_float(rims[i] / m)
            if not WEB_RATIO_RANGE[0] <= web_ratio <= WEB_RATIO_RANGE[1]:
                notes.append(f"gear {i + 1} ({pair.names[i]}): web ratio b_s/b={web_ratio:.3f} outside ISO 6336-1's "
                             f"C_R range [{WEB_RATIO_RANGE[0]}, {WEB_RATIO_RANGE[1]}]; held at the limit")
            if rim_ratio < MIN_RIM_RATIO:
                notes.append(f"gear {i + 1} ({pair.names[i]}): rim ratio s_R/m_n={rim_ratio:.3f} below ISO "
                             f"6336-1's C_R limit {MIN_RIM_RATIO}; held at the limit")
        factors.append(iso6336_blank_factor(webs[i], rims[i], b, m))
    return 0.5 * (factors[0] + factors[1])


def _shift_validity(x_pinion, x_wheel, names, notes) -> None:
    if not nm.is_numeric(x_pinion, x_wheel):
        return
    xp, xw = nm.to_float(x_pinion), nm.to_float(x_wheel)
    if xp < xw:
        notes.append(f"profile shift of the pinion x1={xp:.4f} ({names[0]}) is below the wheel's x2={xw:.4f} "
                     f"({names[1]}): ISO 6336-1 method B stiffness assumes x1 >= x2")
    low, high = SUM_OF_PROFILE_SHIFTS_RANGE
    if not low <= xp + xw <= high:
        notes.append(f"sum of profile shifts x1+x2={xp + xw:.4f} outside ISO 6336-1 method B's range "
                     f"[{low}, {high}]")


def _report(notes: list[str], validity: str, where: str) -> None:
    if not notes or validity == "ignore":
        return
    message = f"{where}: outside the published validity -- " + "; ".join(notes)
    if validity == "raise":
        raise GearoptInputError(message)
    warnings.warn(message, StiffnessValidityWarning, stacklevel=3)


def iso6336_stiffness(pair: GearPair, *, solid_blanks: bool = True, rim_thickness_mm=None, web_thickness_mm=None,
                      basic_rack_factor=None, line_load_N_per_mm=None, E_MPa=E_STEEL_MPA,
                      validity: str = "warn") -> dict:
    """Tooth stiffness of a gear pair by ISO 6336-1 method B (sec. 9 of the 2006 edition), dual-typed.

    Returns a dict, all stiffnesses per unit face width in N/(mm*um) (= N/mm of face width per um of deflection
    along the line of action):

    - ``q_prime`` [mm*um/N]: minimum flexibility of a tooth pair (method-B regression, docs/default-data.md sec. 1.1);
    - ``theoretical_single_stiffness`` (alias ``single_stiffness_theoretical``) c'_th = 1/q';
    - ``single_stiffness`` c' = c'_th C_M C_R C_B cos(beta) (E/E_st) (light-load factor if asked for): the maximum
      stiffness of one tooth pair;
    - ``mesh_stiffness`` c_gamma_alpha = c'(0.75 eps_alpha + 0.25): mean stiffness of all pairs in mesh (used for
      K_v, K_Halpha; the mean mesh stiffness of the pair is c_gamma_alpha * b, b = the smaller face width);
    - ``mesh_stiffness_beta`` c_gamma_beta = 0.85 c_gamma_alpha (used for K_Hbeta);
    - factors ``C_M`` (0.8, theory to measurement for solid discs), ``C_R`` (gear blank), ``C_B`` (basic rack),
      ``material_factor`` E/E_st, ``light_load_factor``;
    - ``pinion``: index (0/1) of the gear treated as gear 1 of the regression, ``virtual_teeth`` (pinion first),
      ``validity_violations`` (tuple of messages; empty for symbolic inputs, which cannot be checked).

    Gear 1 of the regression is the pinion (fewer teeth); for equal tooth counts it is the gear with the larger
    profile shift (``nm.where``, so numeric and symbolic evaluations agree and the value is continuous where the
    shifts are equal). Virtual teeth z_n = z/(cos^2 beta_b cos beta) (ISO 21771 eq. 24, as the pair computes
    them): with these the ISO/TR 6336-30 example 1 values are reproduced; z/cos^3 beta would be 1 % off there.

    Arguments: ``solid_blanks`` (C_R = 1) or ``solid_blanks=False`` with ``rim_thickness_mm`` s_R and
    ``web_thickness_mm`` b_s -- scalars (both gears webbed; ISO's pair formula) or 2-tuples with ``None`` for a
    solid gear; a pair of one web and one solid gear takes the mean of the two factors ([E], as the 2019 edition
    does for C_B). ``basic_rack_factor`` overrides C_B (default: from the pair's h_fP/m_n and alpha_n).
    ``line_load_N_per_mm`` = F_t K_A / b enables the **unverified** light-load correction (see
    :func:`iso6336_light_load_factor`). ``E_MPa``: Young's modulus of both gears (steel 206 000 MPa; the E/E_st
    scaling follows ISO 6336-1:2019 as implemented in a public code).

    Validity (ISO 6336-1 as asserted in public codes): external steel gears, x1 >= x2 (pinion, wheel),
    -0.5 <= x1 + x2 <= 2.0, eps_alpha >= 1.2 for c_gamma_alpha, and for C_R 0.2 <= b_s/b <= 1.2, s_R/m_n >= 1.
    Numeric inputs outside are reported according to ``validity``: ``"warn"`` (default) emits a
    :class:`StiffnessValidityWarning` and returns the formula's value (no clipping, except the two C_R ratios which
    the standard's codes hold at their limits -- the warning says so); ``"raise"`` raises
    :class:`~gearopt.errors.GearoptInputError` naming each value and limit; ``"ignore"`` stays silent (the messages
    are still in ``validity_violations``). Symbolic inputs cannot be checked: impose the limits as constraints.
    """
    if validity not in _VALIDITY_MODES:
        raise GearoptInputError(f"validity={validity!r} must be one of {_VALIDITY_MODES}")
    check_range("E_MPa", E_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    g = pair.geometry()
    notes: list[str] = []
    zn = g["virtual_teeth"]
    x = pair.profile_shifts
    order = _pinion_order(pair)
    if order is not None:
        p, w = order
        q = iso6336_theoretical_single_stiffness((zn[p], zn[w]), (x[p], x[w]))["q_prime"]
        _shift_validity(x[p], x[w], (pair.names[p], pair.names[w]), notes)
        pinion = p
    else:  # equal teeth: the gear with the larger shift plays the pinion, so x1 >= x2 holds by construction
        q12 = iso6336_theoretical_single_stiffness(zn, x)["q_prime"]
        q21 = iso6336_theoretical_single_stiffness(zn[::-1], x[::-1])["q_prime"]
        q = nm.where(x[0] >= x[1], q12, q21)
        pinion = None
        if nm.is_numeric(x[0], x[1]):
            pinion = 0 if nm.to_float(x[0]) >= nm.to_float(x[1]) else 1
            q = nm.to_float(q)
            _shift_validity(max(nm.to_float(x[0]), nm.to_float(x[1])), min(nm.to_float(x[0]), nm.to_float(x[1])),
                            pair.names if pinion == 0 else pair.names[::-1], notes)
    c_th = 1.0 / q
    c_r = _blank_factor_pair(pair, solid_blanks, rim_thickness_mm, web_thickness_mm, notes)
    c_b = (iso6336_basic_rack_factor(pair.dedendum_coefficient, pair.pressure_angle_deg)
           if basic_rack_factor is None else basic_rack_factor)
    check_range("basic_rack_factor", c_b, 0.0, None, low_inclusive=False)
    material = E_MPa / E_STEEL_MPA
    light = 1.0 if line_load_N_per_mm is None else iso6336_light_load_factor(line_load_N_per_mm)
    cos_beta = nm.cos(pair.helix_angle_deg * RAD_PER_DEG)
    c_single = c_th * THEORY_CORRECTION_FACTOR_C_M * c_r * c_b * cos_beta * material * light
    eps = g["transverse_contact_ratio"]
    if nm.is_numeric(eps) and nm.to_float(eps) < MIN_CONTACT_RATIO_FOR_MESH_STIFFNESS:
        notes.append(f"transverse_contact_ratio={nm.to_float(eps):.4f} below "
                     f"{MIN_CONTACT_RATIO_FOR_MESH_STIFFNESS}: c_gamma_alpha = c'(0.75 eps + 0.25) is not validated "
                     f"there (a public code reduces it by 10 %)")
    c_gamma_alpha = c_single * (0.75 * eps + 0.25)
    _report(notes, validity, f"iso6336_stiffness of {pair.names[0]}-{pair.names[1]} (z={pair.teeth[0]}/"
                             f"{pair.teeth[1]})")
    zn_out = zn if pinion != 1 else zn[::-1]
    return {
        "q_prime": q,
        "theoretical_single_stiffness": c_th,
        "single_stiffness_theoretical": c_th,
        "single_stiffness": c_single,
        "mesh_stiffness": c_gamma_alpha,
        "mesh_stiffness_beta": 0.85 * c_gamma_alpha,
        "C_M": THEORY_CORRECTION_FACTOR_C_M,
        "C_R": c_r,
        "C_B": c_b,
        "material_factor": material,
        "light_load_factor": light,
        "pinion": pinion,
        "virtual_teeth": zn_out,
        "validity_violations": tuple(notes),
    }


# ----------------------------------------------------------------------------------------------------------------
# length of the contact lines and the line-of-contact stiffness (thesis Eqs. 3.22-3.23)
# ----------------------------------------------------------------------------------------------------------------

def _contact_field(pair: GearPair) -> tuple:
    """(eps_alpha, common face width b [mm], base helix angle [rad], base pitch p_bt [mm], path length g [mm])."""
    g = pair.geometry()
    b = nm.fmin(pair.face_width_mm[0], pair.face_width_mm[1])
    return (g["transverse_contact_ratio"], b, g["base_helix_angle_deg"] * RAD_PER_DEG, g["base_pitch_mm"],
            g["length_of_path_of_contact_mm"])


def _total_line_length(offsets, path_mm, width_mm, pitch_mm, tan_bb) -> np.ndarray:
    """Total length (in the plane of action, projected on the face direction, i.e. before / cos beta_b) of the
    contact lines u = u0 + k p + w tan(beta_b) inside the field 0 <= u <= g, 0 <= w <= b, for each offset u0."""
    offsets = np.atleast_1d(np.asarray(offsets, dtype=float))
    k_low = math.floor((-width_mm * tan_bb - pitch_mm) / pitch_mm) - 1
    k_high = math.ceil((path_mm + pitch_mm) / pitch_mm) + 1
    k = np.arange(k_low, k_high + 1)
    u = offsets[:, None] + k[None, :] * pitch_mm  # line position at w = 0
    if tan_bb == 0.0:
        inside = (u >= 0.0) & (u < path_mm)
        return inside.sum(axis=1) * width_mm
    w_lo = np.clip(-u / tan_bb, 0.0, width_mm)
    w_hi = np.clip((path_mm - u) / tan_bb, 0.0, width_mm)
    return np.clip(w_hi - w_lo, 0.0, None).sum(axis=1)


def contact_line_length_mm(pair: GearPair, kind: str = "mean"):
    """Total length of the contact lines of a pair [mm] over the mesh cycle: its mean, minimum or maximum.

    Geometry: in the plane of action the field of contact is the path length g_alpha (transverse) by the common
    face width b; the contact lines are straight, inclined at the base helix angle beta_b, one base pitch p_bt apart.
    ``"mean"``: exactly eps_alpha b / cos(beta_b) (field area over the normal line spacing p_bt cos beta_b);
    dual-typed. ``"minimum"`` / ``"maximum"``: exact extremes over the cycle (the total length is piecewise linear
    in the mesh position, so the extremes lie at the positions where a line end passes a corner of the field);
    numeric pairs only. Limits: spur gears give floor(eps_alpha) b and ceil(eps_alpha) b; an integer overlap ratio
    eps_beta makes the length constant. Source: the plane-of-action construction (e.g. ISO 21771 sec. 5.4; AGMA's
    minimum contact length L_min for the load-sharing ratio is the same quantity).
    """
    eps, b, beta_b, p_bt, g_alpha = _contact_field(pair)
    if kind == "mean":
        return eps * b / nm.cos(beta_b)
    if kind not in ("minimum", "maximum"):
        raise GearoptInputError(f"kind={kind!r} must be 'mean', 'minimum' or 'maximum'")
    if pair.is_symbolic:
        raise GearoptInputError(f"contact_line_length_mm(kind={kind!r}) needs a numeric pair (the extremes are "
                                f"non-smooth); use kind='mean' in an NLP")
    b, beta_b, p_bt, g_alpha = (nm.to_float(v) for v in (b, beta_b, p_bt, g_alpha))
    tan_bb = math.tan(beta_b)
    shift = b * tan_bb
    breaks = np.sort(np.mod([0.0, g_alpha, -shift, g_alpha - shift], p_bt))
    breaks = np.append(breaks, breaks[0] + p_bt)
    mids = 0.5 * (breaks[:-1] + breaks[1:])
    candidates = mids if tan_bb == 0.0 else np.concatenate([breaks[:-1], mids])
    lengths = _total_line_length(candidates, g_alpha, b, p_bt, tan_bb) / math.cos(beta_b)
    return float(lengths.min() if kind == "minimum" else lengths.max())


def thesis_contact_line_length_mm(face_width_mm, contact_ratio, base_helix_angle_deg=0.0):
    """The thesis' contact-line length, Eqs. 3.22-3.23 as printed (Coy & Zaretsky 1975 / AGMA), in mm.

    Helical: L_c = 0.95 b CR / cos(psi); spur (psi = 0): L_c = b. ``contact_ratio`` CR = transverse contact ratio;
    psi must be the **base** helix angle (the contact lines lie in the plane of action; the thesis only says "psi").
    For comparison with the thesis only. The two printed equations are not one model: 3.22 is AGMA's approximate
    *minimum* contact length of helical gears (meant for large overlap ratios, eps_beta >= 2 [M]; the default
    6-degree train has 0.28, where the exact minimum is about b / cos(beta_b), not 0.95 CR b / cos(beta_b)), while
    3.23 is the single-pair length of a spur mesh; as psi -> 0, 3.22 tends to 0.95 CR b, not to b. So the thesis'
    helical/spur stiffness ratios (Table 3.6) reflect 0.95 CR, not the helix. Use
    :func:`contact_line_length_mm` for a consistent length. Dual-typed.
    """
    psi = base_helix_angle_deg * RAD_PER_DEG
    helical = AGMA_CONTACT_LENGTH_FACTOR * face_width_mm * contact_ratio / nm.cos(psi)
    if nm.is_numeric(base_helix_angle_deg):
        return face_width_mm if nm.to_float(base_helix_angle_deg) == 0.0 else helical
    return nm.where(base_helix_angle_deg == 0.0, face_width_mm, helical)


def line_of_contact_stiffness(pair: GearPair, *, length: str = "mean", stiffness_per_length_N_per_mm_um=None,
                              validity: str = "warn", **iso_options) -> dict:
    """Mesh stiffness as a constant stiffness per unit length of contact line times the contact-line length.

    The thesis (sec. 3.6, Eqs. 3.22-3.23) multiplies a confidential constant by the length of the lines of contact.
    Here the constant is ``stiffness_per_length_N_per_mm_um`` K_L [N/um per mm of contact line]; by default ISO
    6336-1's single stiffness spread over one pair's full contact line, K_L = c' b / (b / cos beta_b) = c' cos beta_b
    (:func:`iso6336_stiffness` with ``iso_options``). ``length``: ``"mean"`` (exact mean length, dual-typed),
    ``"minimum"`` / ``"maximum"`` (exact extremes over the cycle, numeric), or ``"thesis"`` (the printed Eqs.
    3.22-3.23, :func:`thesis_contact_line_length_mm`, for comparison only).

    Returns ``contact_line_length_mm``, ``stiffness_per_length_N_per_mm_um``, ``stiffness_N_per_um`` = K_L L and
    ``stiffness_N_per_m``. With the default K_L the mean gives c' eps_alpha b, about 8 % above ISO's
    c_gamma_alpha b = c'(0.75 eps_alpha + 0.25) b for eps_alpha = 1.6: a constant K_L ignores the lower stiffness of
    contacts near tip and root, which ISO's factor accounts for. Prefer ``iso6336_stiffness(...)["mesh_stiffness"]
    * b`` for the mean mesh stiffness; use this model for the min/max range of the contact length.
    """
    if length == "thesis":
        g = pair.geometry()
        b = nm.fmin(pair.face_width_mm[0], pair.face_width_mm[1])
        contact = thesis_contact_line_length_mm(b, g["transverse_contact_ratio"], g["base_helix_angle_deg"])
    elif length in ("mean", "minimum", "maximum"):
        contact = contact_line_length_mm(pair, length)
    else:
        raise GearoptInputError(f"length={length!r} must be 'mean', 'minimum', 'maximum' or 'thesis'")
    if stiffness_per_length_N_per_mm_um is None:
        iso = iso6336_stiffness(pair, validity=validity, **iso_options)
        beta_b = pair.geometry()["base_helix_angle_deg"] * RAD_PER_DEG
        k_l = iso["single_stiffness"] * nm.cos(beta_b)
    else:
        if iso_options:
            raise GearoptInputError(f"ISO options {sorted(iso_options)} are unused when "
                                    f"stiffness_per_length_N_per_mm_um is given")
        check_range("stiffness_per_length_N_per_mm_um", stiffness_per_length_N_per_mm_um, 0.0, None,
                    low_inclusive=False, unit="N/(mm*um)")
        k_l = stiffness_per_length_N_per_mm_um
    k = k_l * contact
    return {"contact_line_length_mm": contact, "stiffness_per_length_N_per_mm_um": k_l, "stiffness_N_per_um": k,
            "stiffness_N_per_m": k * 1e6}


# ----------------------------------------------------------------------------------------------------------------
# damping (thesis Eqs. 3.26-3.27)
# ----------------------------------------------------------------------------------------------------------------

def equivalent_mass_kg(inertias_kgm2, base_radii_mm):
    """Equivalent mass of two meshing gears along the line of action, m_eq = 1/(r_b1^2/J1 + r_b2^2/J2) [kg].

    ``inertias_kgm2`` (J1, J2) [kg*m^2], ``base_radii_mm`` (r_b1, r_b2) [mm]. Equal to the thesis' Eq. 3.27,
    J1 J2 / (J1 r_b2^2 + J2 r_b1^2), written so that a gear of infinite inertia (fixed) gives m_eq = J1/r_b1^2.
    Dual-typed.
    """
    (j1, j2), (r1, r2) = inertias_kgm2, base_radii_mm
    for i, (j, r) in enumerate(zip((j1, j2), (r1, r2))):
        check_range(f"inertias_kgm2[{i}]", j, 0.0, None, low_inclusive=False, unit="kg*m^2", allow_inf=True)
        check_range(f"base_radii_mm[{i}]", r, 0.0, None, low_inclusive=False, unit="mm")
    r1_m, r2_m = r1 * 1e-3, r2 * 1e-3
    return 1.0 / (r1_m * r1_m / j1 + r2_m * r2_m / j2)


def mesh_damping(stiffness_N_per_m, inertias_kgm2, base_radii_mm, damping_ratio=THESIS_DAMPING_RATIO):
    """Viscous mesh damping along the line of action, c = 2 zeta sqrt(k m_eq) [N*s/m] (thesis Eqs. 3.26-3.27).

    ``stiffness_N_per_m`` k: mean mesh stiffness [N/m] (e.g. c_gamma_alpha b x 1e6); ``inertias_kgm2`` (J1, J2);
    ``base_radii_mm`` (r_b1, r_b2); ``damping_ratio`` zeta (thesis: 0.08 from Cummins data; literature values for
    gear meshes are about 0.03-0.17). Checked against physics: sqrt(N/m * kg) = N*s/m; the thesis' J_eq (3.27) is
    the two-inertia mass reduced to the line of action (not garbled); c is the damping that gives the mesh mode of
    the two gears (natural frequency sqrt(k/m_eq)) the ratio zeta. Dual-typed.
    """
    check_range("stiffness_N_per_m", stiffness_N_per_m, 0.0, None, unit="N/m")
    check_range("damping_ratio", damping_ratio, 0.0, None)
    return 2.0 * damping_ratio * nm.sqrt(stiffness_N_per_m * equivalent_mass_kg(inertias_kgm2, base_radii_mm))


def solid_disc_inertia_kgm2(diameter_mm, face_width_mm, bore_diameter_mm=0.0, density_kg_m3=STEEL_DENSITY_KG_M3):
    """Polar inertia of a solid (annular) disc, J = rho pi b (d^4 - d_i^4) / 32 [kg*m^2]; lengths in mm. Dual-typed.

    Used by :func:`mesh_stiffness_table` as an [E] estimate of a gear's inertia (disc to the reference diameter)
    when no inertia is given.
    """
    check_range("diameter_mm", diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("bore_diameter_mm", bore_diameter_mm, 0.0, None, unit="mm")
    d, di, b = diameter_mm * 1e-3, bore_diameter_mm * 1e-3, face_width_mm * 1e-3
    return density_kg_m3 * math.pi * b * (d ** 4 - di ** 4) / 32.0


# ----------------------------------------------------------------------------------------------------------------
# the thesis' Table 3.6 analogue
# ----------------------------------------------------------------------------------------------------------------

def _blank_options(pair: GearPair, blanks: dict | None) -> dict:
    if not blanks or not any(name in blanks for name in pair.names):
        return {}
    rims, webs = [], []
    for name in pair.names:
        spec = blanks.get(name)
        if spec is None:
            rims.append(None)
            webs.append(None)
            continue
        unknown = set(spec) - {"rim_thickness_mm", "web_thickness_mm"}
        if unknown:
            raise GearoptInputError(f"blanks[{name!r}] has unknown keys {sorted(unknown)}; expected "
                                    f"rim_thickness_mm and web_thickness_mm")
        rims.append(spec["rim_thickness_mm"])
        webs.append(spec["web_thickness_mm"])
    return {"solid_blanks": False, "rim_thickness_mm": tuple(rims), "web_thickness_mm": tuple(webs)}


def mesh_stiffness_table(train, *, inertias_kgm2: dict | None = None, blanks: dict | None = None,
                         damping_ratio=THESIS_DAMPING_RATIO, validity: str = "warn") -> pd.DataFrame:
    """One row per mesh of a numeric :class:`~gearopt.geometry.GearTrain`: stiffness and damping (thesis Table 3.6).

    Columns (units in the names): ``mesh``, ``gear_1``, ``gear_2``, ``teeth_1``, ``teeth_2``, ``helix_angle_deg``,
    ``profile_shift_1``, ``profile_shift_2``, ``transverse_contact_ratio``, ``overlap_contact_ratio``,
    ``face_width_mm`` (the smaller one), ``C_R``, ``C_B``, ISO 6336-1 ``theoretical_single_stiffness_N_per_mm_um``,
    ``single_stiffness_N_per_mm_um`` (c'), ``mesh_stiffness_N_per_mm_um`` (c_gamma_alpha),
    ``mesh_stiffness_beta_N_per_mm_um``, ``mean_mesh_stiffness_N_per_um`` (k = c_gamma_alpha b), the contact-line
    lengths ``contact_line_length_{mean,min,max}_mm`` and the line-of-contact stiffness range
    ``line_of_contact_stiffness_{min,max}_N_per_um`` (:func:`line_of_contact_stiffness`),
    ``equivalent_mass_kg``, ``damping_ratio`` and ``damping_N_s_per_m`` (:func:`mesh_damping` with k), and
    ``iso6336_validity`` ("ok" or the violated limits).

    ``inertias_kgm2``: gear name -> J [kg*m^2]; gears not named get a solid steel disc of their reference diameter
    and face width (:func:`solid_disc_inertia_kgm2`, an [E] estimate). ``blanks``: gear name ->
    ``{"rim_thickness_mm": s_R, "web_thickness_mm": b_s}`` for web gears (others solid). ``validity`` as in
    :func:`iso6336_stiffness`.
    """
    inertias_kgm2 = dict(inertias_kgm2 or {})
    rows = []
    for mesh_name, pair in train.pairs.items():
        if pair.is_symbolic:
            raise GearoptInputError(f"mesh_stiffness_table needs a numeric train; mesh {mesh_name!r} is symbolic "
                                    f"(call iso6336_stiffness on its pair instead)")
        g = pair.geometry()
        options = _blank_options(pair, blanks)
        iso = iso6336_stiffness(pair, validity=validity, **options)
        b = min(g["face_width_mm"])
        k_mean = iso["mesh_stiffness"] * b
        k_l = iso["single_stiffness"] * math.cos(math.radians(g["base_helix_angle_deg"]))
        lengths = {kind: contact_line_length_mm(pair, kind) for kind in ("mean", "minimum", "maximum")}
        inertias = tuple(inertias_kgm2[n] if n in inertias_kgm2 else
                         solid_disc_inertia_kgm2(g["pitch_diameter_mm"][i], pair.face_width_mm[i])
                         for i, n in enumerate(pair.names))
        radii = tuple(0.5 * d for d in g["base_diameter_mm"])
        rows.append({
            "mesh": mesh_name, "gear_1": pair.names[0], "gear_2": pair.names[1],
            "teeth_1": pair.teeth[0], "teeth_2": pair.teeth[1], "helix_angle_deg": g["helix_angle_deg"],
            "profile_shift_1": g["profile_shifts"][0], "profile_shift_2": g["profile_shifts"][1],
            "transverse_contact_ratio": g["transverse_contact_ratio"],
            "overlap_contact_ratio": g["overlap_contact_ratio"], "face_width_mm": b,
            "C_R": float(iso["C_R"]), "C_B": float(iso["C_B"]),
            "theoretical_single_stiffness_N_per_mm_um": float(iso["theoretical_single_stiffness"]),
            "single_stiffness_N_per_mm_um": float(iso["single_stiffness"]),
            "mesh_stiffness_N_per_mm_um": float(iso["mesh_stiffness"]),
            "mesh_stiffness_beta_N_per_mm_um": float(iso["mesh_stiffness_beta"]),
            "mean_mesh_stiffness_N_per_um": float(k_mean),
            "contact_line_length_mean_mm": float(lengths["mean"]),
            "contact_line_length_min_mm": lengths["minimum"],
            "contact_line_length_max_mm": lengths["maximum"],
            "line_of_contact_stiffness_min_N_per_um": float(k_l * lengths["minimum"]),
            "line_of_contact_stiffness_max_N_per_um": float(k_l * lengths["maximum"]),
            "equivalent_mass_kg": float(equivalent_mass_kg(inertias, radii)),
            "damping_ratio": float(damping_ratio),
            "damping_N_s_per_m": float(mesh_damping(k_mean * 1e6, inertias, radii, damping_ratio)),
            "iso6336_validity": "; ".join(iso["validity_violations"]) or "ok",
        })
    return pd.DataFrame(rows)


__all__ = [
    "Q_PRIME_COEFFICIENTS", "THEORY_CORRECTION_FACTOR_C_M", "E_STEEL_MPA", "THESIS_DAMPING_RATIO",
    "StiffnessValidityWarning", "iso6336_theoretical_single_stiffness", "iso6336_basic_rack_factor",
    "iso6336_blank_factor", "iso6336_light_load_factor", "iso6336_stiffness", "contact_line_length_mm",
    "thesis_contact_line_length_mm", "line_of_contact_stiffness", "equivalent_mass_kg", "mesh_damping",
    "solid_disc_inertia_kgm2", "mesh_stiffness_table",
]
