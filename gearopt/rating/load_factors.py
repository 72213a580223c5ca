"""ISO 6336-1:2006 load factors, dual-typed: dynamic factor K_v (method B), face load factors K_Hbeta (method C)
and K_Fbeta, transverse load factors K_Halpha / K_Falpha (method B), with the running-in allowances they use.

Which method and clause (ISO 6336-1:2006):

* running-in allowances y_alpha (clause 8.3.4), y_beta (clause 7.6.3 / 7.7), running-in tip relief C_ay (6.3.2);
* :func:`dynamic_factor` -- method B (clause 6.3): resonance ratio N = n1/n_E1 with n_E1 = 30 000/(pi z1)
  sqrt(c_gamma_alpha/m_red), sub-critical (N <= N_S), main resonance (N_S < N <= 1.15), intermediate (linear between
  N = 1.15 and 1.5) and super-critical (N >= 1.5) ranges with the coefficients C_v1..C_v7 of the total contact ratio
  and B_p, B_f, B_k from the effective deviations after running-in;
* :func:`face_load_factor_contact` -- method C (clause 7.6): F_betay = F_betax - y_beta, K_Hbeta = 1 + F_betay
  c_gamma_beta / (2 F_m/b) while that is <= 2, else sqrt(2 F_betay c_gamma_beta / (F_m/b));
* :func:`face_load_factor_root` -- K_Fbeta = K_Hbeta^N_F, N_F = (b/h)^2 / (1 + b/h + (b/h)^2) (clause 7.6.5);
* :func:`transverse_load_factors` -- method B (clause 8.3): K_Halpha = K_Falpha from the base pitch deviation after
  running-in and the total contact ratio, bounded by 1 <= K_Halpha <= eps_gamma/(eps_alpha Z_eps^2) and K_Falpha <=
  eps_gamma/(0.25 eps_alpha + 0.75).

Units: deviations um, line loads N/mm, stiffness N/(mm um), mass per face width kg/mm, speeds rpm and m/s.
The range switches are exact (``numerics.where``): the standard's K_v and K_Hbeta are continuous in most but not all
of their switches (K_v jumps at N_S); derivatives are exact inside each range.
"""

from __future__ import annotations

import math

from .. import numerics as nm
from .material_groups import iso6336_material_group

#: ISO 6336-1 method B resonance-range limits of N.
MAIN_RESONANCE_UPPER = 1.15
SUPERCRITICAL_LOWER = 1.5


def _mean_over_gears(func, mats, *args):
    values = [func(iso6336_material_group(m), *args) for m in mats]
    return 0.5 * (values[0] + values[1])


def _speed_limited(value, v_m_s, limit_5_10, limit_above_10):
    """Apply the standard's upper limits of a running-in allowance at 5 < v <= 10 m/s and v > 10 m/s."""
    if limit_5_10 is None:
        return value
    return nm.where(v_m_s <= 5.0, value,
                    nm.where(v_m_s <= 10.0, nm.fmin(value, limit_5_10), nm.fmin(value, limit_above_10)))


def _y_alpha_one(group, f_pb_um, sigma_Hlim_MPa, v_m_s):
    if group in ("St", "V", "GGG"):
        return _speed_limited(160.0 / sigma_Hlim_MPa * f_pb_um, v_m_s, 12800.0 / sigma_Hlim_MPa,
                              6400.0 / sigma_Hlim_MPa)
    if group == "GG":
        return _speed_limited(0.275 * f_pb_um, v_m_s, 22.0, 11.0)
    return nm.fmin(0.075 * f_pb_um, 3.0)  # Eh, IF, NT, NV


def running_in_allowance_alpha_um(f_pb_um, materials, sigma_Hlim_MPa, v_m_s):
    """ISO 6336-1:2006 clause 8.3.4 running-in allowance y_alpha [um] for the base pitch deviation ``f_pb_um``:
    St/V/GGG 160/sigma_Hlim f_pb (at most 12 800/sigma_Hlim for 5 < v <= 10 m/s, 6 400/sigma_Hlim above), GG
    0.275 f_pb (22 / 11 um), case-hardened and nitrided 0.075 f_pb <= 3 um; for two materials the mean of both.
    ``materials``: 2-tuple of catalogue materials; ``sigma_Hlim_MPa``: 2-tuple. Dual-typed in f_pb and v."""
    vals = [_y_alpha_one(iso6336_material_group(materials[i]), f_pb_um, sigma_Hlim_MPa[i], v_m_s)
            for i in range(2)]
    return 0.5 * (vals[0] + vals[1])


def _y_beta_one(group, F_betax_um, sigma_Hlim_MPa, v_m_s):
    if group in ("St", "V", "GGG"):
        return _speed_limited(320.0 / sigma_Hlim_MPa * F_betax_um, v_m_s, 25600.0 / sigma_Hlim_MPa,
                              12800.0 / sigma_Hlim_MPa)
    if group == "GG":
        return _speed_limited(0.55 * F_betax_um, v_m_s, 45.0, 22.0)
    return nm.fmin(0.15 * F_betax_um, 6.0)


def running_in_allowance_beta_um(F_betax_um, materials, sigma_Hlim_MPa, v_m_s):
    """ISO 6336-1:2006 clause 7.6.3 running-in allowance y_beta [um] of the initial equivalent misalignment
    F_betax: St/V/GGG 320/sigma_Hlim F_betax (<= 25 600/sigma_Hlim for 5 < v <= 10 m/s, 12 800/sigma_Hlim above),
    GG 0.55 F_betax (45 / 22 um), case-hardened and nitrided 0.15 F_betax <= 6 um; mean of both gears."""
    vals = [_y_beta_one(iso6336_material_group(materials[i]), F_betax_um, sigma_Hlim_MPa[i], v_m_s)
            for i in range(2)]
    return 0.5 * (vals[0] + vals[1])


def running_in_tip_relief_um(sigma_Hlim_MPa):
    """ISO 6336-1:2006 clause 6.3.2 amount of tip relief produced by running-in, C_ay = (sigma_Hlim/97 - 18.45)^2/18
    + 1.5 [um] (sigma_Hlim in MPa; 2.0 um for 1500 MPa). For two materials pass the mean sigma_Hlim."""
    return (sigma_Hlim_MPa / 97.0 - 18.45) ** 2 / 18.0 + 1.5


# ----------------------------------------------------------------------------------------------------------------
# dynamic factor, method B
# ----------------------------------------------------------------------------------------------------------------

def reduced_mass_kg_per_mm(mean_diameters_mm, base_diameters_mm, bore_diameters_mm, densities_kg_m3, gear_ratio):
    """ISO 6336-1:2006 clause 6.3.2 (eq. 30) reduced mass of a pair per unit face width [kg/mm], index 0 = pinion:

        m_red = (pi/8) (d_m1/d_b1)^2 d_m1^2 / ( 1/((1 - q1^4) rho1) + 1/((1 - q2^4) rho2 u^2) ),

    d_m = (d_a + d_f)/2 the mean tooth diameter, q = d_i/d_m (bore over mean diameter, 0 for a solid gear), rho the
    density (converted to kg/mm^3), u = z2/z1 >= 1. Dual-typed."""
    dm1, dm2 = mean_diameters_mm
    q1, q2 = bore_diameters_mm[0] / dm1, bore_diameters_mm[1] / dm2
    rho1, rho2 = densities_kg_m3[0] * 1e-9, densities_kg_m3[1] * 1e-9
    ratio = dm1 / base_diameters_mm[0]
    return (math.pi / 8.0) * ratio * ratio * dm1 * dm1 / (1.0 / ((1.0 - q1 ** 4) * rho1)
                                                          + 1.0 / ((1.0 - q2 ** 4) * rho2 * gear_ratio ** 2))


def resonance_speed_rpm(pinion_teeth, mesh_stiffness, reduced_mass):
    """ISO 6336-1:2006 eq. 29 resonance speed of the pinion, n_E1 = 30 000/(pi z1) sqrt(c_gamma_alpha/m_red) [rpm]
    (c_gamma_alpha in N/(mm um), m_red in kg/mm). Dual-typed."""
    return 30000.0 / (math.pi * pinion_teeth) * nm.sqrt(mesh_stiffness / reduced_mass)


def dynamic_coefficients(total_contact_ratio) -> dict:
    """ISO 6336-1:2006 Table 8 coefficients C_v1..C_v7 of the total contact ratio eps_gamma (1 < eps_gamma;
    the eps_gamma <= 2 and > 2 columns, C_v7 in three ranges). Dual-typed."""
    e = total_contact_ratio
    high = e > 2.0
    safe = nm.fmax(e, 2.0 + 1e-9)  # keeps the unused branch finite
    return {
        "C_v1": 0.32,
        "C_v2": nm.where(high, 0.57 / (safe - 0.3), 0.34),
        "C_v3": nm.where(high, 0.096 / (safe - 1.56), 0.23),
        "C_v4": nm.where(high, (0.57 - 0.05 * safe) / (safe - 1.44), 0.90),
        "C_v5": 0.47,
        "C_v6": nm.where(high, 0.12 / (safe - 1.74), 0.47),
        "C_v7": nm.where(e <= 1.5, 0.75, nm.where(e <= 2.5, 0.125 * nm.sin(math.pi * (e - 2.0)) + 0.875, 1.0)),
    }


def dynamic_factor(resonance_ratio, line_load_N_per_mm, single_stiffness, f_pb_eff_um, f_falpha_eff_um,
                   tip_relief_um, total_contact_ratio) -> dict:
    """ISO 6336-1:2006 method B dynamic factor K_v (clause 6.3.2-6.3.5). Dual-typed.

    Args: ``resonance_ratio`` N = n1/n_E1; ``line_load_N_per_mm`` = K_A F_t / b; ``single_stiffness`` c' [N/(mm um)];
    ``f_pb_eff_um`` = f_pb - y_p and ``f_falpha_eff_um`` = f_falpha - y_f (effective deviations after running-in,
    floored at 0); ``tip_relief_um`` C_a; ``total_contact_ratio`` eps_gamma.

    B_p = c' f_pb,eff / (K_A F_t/b), B_f = c' f_falpha,eff / (K_A F_t/b), B_k = |1 - c' C_a / (K_A F_t/b)|;
    N_S = 0.5 + 0.35 sqrt(K_A F_t/(100 b)) below 100 N/mm, else 0.85. Ranges: N <= N_S: K_v = N K + 1,
    K = C_v1 B_p + C_v2 B_f + C_v3 B_k; N_S < N <= 1.15: K_v = C_v1 B_p + C_v2 B_f + C_v4 B_k + 1; N >= 1.5:
    K_v = C_v5 B_p + C_v6 B_f + C_v7; in between linear in N. Returns a dict with ``K_v``, ``N_S``, ``B_p``,
    ``B_f``, ``B_k`` and the coefficients.
    """
    w = line_load_N_per_mm
    c = dynamic_coefficients(total_contact_ratio)
    b_p = single_stiffness * nm.fmax(f_pb_eff_um, 0.0) / w
    b_f = single_stiffness * nm.fmax(f_falpha_eff_um, 0.0) / w
    b_k = nm.fabs(1.0 - single_stiffness * tip_relief_um / w)
    n_s = nm.where(w < 100.0, 0.5 + 0.35 * nm.sqrt(nm.fmin(w, 100.0) / 100.0), 0.85)
    n = resonance_ratio
    sub = n * (c["C_v1"] * b_p + c["C_v2"] * b_f + c["C_v3"] * b_k) + 1.0
    main = c["C_v1"] * b_p + c["C_v2"] * b_f + c["C_v4"] * b_k + 1.0
    sup = c["C_v5"] * b_p + c["C_v6"] * b_f + c["C_v7"]
    inter = sup + (main - sup) * (SUPERCRITICAL_LOWER - n) / (SUPERCRITICAL_LOWER - MAIN_RESONANCE_UPPER)
    k_v = nm.where(n <= n_s, sub, nm.where(n <= MAIN_RESONANCE_UPPER, main,
                                           nm.where(n < SUPERCRITICAL_LOWER, inter, sup)))
    return {"K_v": k_v, "N_S": n_s, "B_p": b_p, "B_f": b_f, "B_k": b_k, **c}


def resonance_range(resonance_ratio, N_S) -> str:
    """Name of the K_v range of a numeric resonance ratio: "subcritical", "main resonance", "intermediate",
    "supercritical"."""
    n, ns = nm.to_float(resonance_ratio), nm.to_float(N_S)
    if n <= ns:
        return "subcritical"
    if n <= MAIN_RESONANCE_UPPER:
        return "main resonance"
    return "intermediate" if n < SUPERCRITICAL_LOWER else "supercritical"


# ----------------------------------------------------------------------------------------------------------------
# face load factors, method C
# ----------------------------------------------------------------------------------------------------------------

def initial_equivalent_misalignment_um(f_sh_um, f_ma_um, line_load_Fm_per_b, f_Hbeta_um, B1=1.0, B2=1.0):
    """ISO 6336-1:2006 clause 7.6.2 initial equivalent misalignment F_betax = 1.33 B1 f_sh + B2 f_ma [um] (B1 = B2 = 1
    without helix modification), not less than F_betax,min = max(0.005 F_m/b, 0.5 f_Hbeta) [um with F_m/b in N/mm].
    Dual-typed."""
    raw = 1.33 * B1 * f_sh_um + B2 * nm.fabs(f_ma_um)
    return nm.fmax(raw, nm.fmax(0.005 * line_load_Fm_per_b, 0.5 * f_Hbeta_um))


def face_load_factor_contact(F_betay_um, mesh_stiffness_beta, line_load_Fm_per_b):
    """ISO 6336-1:2006 method C (clause 7.6.1): K_Hbeta = 1 + F_betay c_gamma_beta / (2 F_m/b) while that is <= 2,
    else sqrt(2 F_betay c_gamma_beta / (F_m/b)) (continuous at 2). ``F_betay_um`` effective misalignment after
    running-in [um], ``mesh_stiffness_beta`` c_gamma_beta [N/(mm um)], ``line_load_Fm_per_b`` F_m/b = F_t K_A K_v
    K_gamma / b [N/mm]. Dual-typed."""
    x = F_betay_um * mesh_stiffness_beta / line_load_Fm_per_b
    return nm.where(x <= 2.0, 1.0 + 0.5 * x, nm.sqrt(2.0 * nm.fmax(x, 2.0)))


def face_load_factor_root(K_Hbeta, face_width_mm, tooth_depth_mm):
    """ISO 6336-1:2006 clause 7.6.5: K_Fbeta = K_Hbeta^N_F, N_F = (b/h)^2 / (1 + b/h + (b/h)^2), b/h the smaller
    face-width-to-depth ratio of the pair, held at >= 3. Dual-typed."""
    r = nm.fmax(face_width_mm / tooth_depth_mm, 3.0)
    n_f = r * r / (1.0 + r + r * r)
    return K_Hbeta ** n_f


# ----------------------------------------------------------------------------------------------------------------
# transverse load factors, method B
# ----------------------------------------------------------------------------------------------------------------

def transverse_load_factors(transverse_contact_ratio, total_contact_ratio, Z_eps, mesh_stiffness, f_pb_eff_um,
                            line_load_FtH_per_b) -> dict:
    """ISO 6336-1:2006 method B (clause 8.3.2): with F_tH/b = F_t K_A K_v K_Hbeta / b [N/mm] and f_pb,eff = f_pb -
    y_alpha [um] (for unmodified profiles the larger of f_pb and f_falpha, minus y_alpha),

        eps_gamma <= 2: K_Halpha = K_Falpha = eps_gamma/2 (0.9 + 0.4 c_gamma_alpha f_pb,eff / (F_tH/b))
        eps_gamma > 2:  K_Halpha = K_Falpha = 0.9 + 0.4 sqrt(2 (eps_gamma - 1)/eps_gamma) c_gamma_alpha f_pb,eff
                        / (F_tH/b)

    bounded: 1 <= K_Halpha <= eps_gamma/(eps_alpha Z_eps^2), 1 <= K_Falpha <= eps_gamma/(0.25 eps_alpha + 0.75)
    (clause 8.3.3). Returns ``K_Halpha``, ``K_Falpha`` and the unbounded ``K_alpha_formula``. Dual-typed."""
    ea, eg = transverse_contact_ratio, total_contact_ratio
    term = mesh_stiffness * nm.fmax(f_pb_eff_um, 0.0) / line_load_FtH_per_b
    low = eg / 2.0 * (0.9 + 0.4 * term)
    high = 0.9 + 0.4 * nm.sqrt(2.0 * (nm.fmax(eg, 1.0) - 1.0) / eg) * term
    k = nm.where(eg <= 2.0, low, high)
    k_h = nm.fmax(1.0, nm.fmin(k, eg / (ea * Z_eps * Z_eps)))
    k_f = nm.fmax(1.0, nm.fmin(k, eg / (0.25 * ea + 0.75)))
    return {"K_Halpha": k_h, "K_Falpha": k_f, "K_alpha_formula": k}


__all__ = ["MAIN_RESONANCE_UPPER", "SUPERCRITICAL_LOWER", "running_in_allowance_alpha_um",
           "running_in_allowance_beta_um", "running_in_tip_relief_um", "reduced_mass_kg_per_mm",
           "resonance_speed_rpm", "dynamic_coefficients", "dynamic_factor", "resonance_range",
           "initial_equivalent_misalignment_um", "face_load_factor_contact", "face_load_factor_root",
           "transverse_load_factors"]
