"""Scuffing load capacity of cylindrical gears: flash-temperature method (ISO/TS 6336-20, the successor of ISO/TR
13989-1) and integral-temperature method (ISO/TS 6336-21, successor of ISO/TR 13989-2), dual-typed.

Formulas (temperatures in C, w in N/mm, v in m/s, a in mm, eta in mPa s, roughness in um):

* scuffing load w_Bt = K_A K_v K_Bbeta K_Balpha F_t / b; helical load factor (integral) K_Bgamma = 1 (eps_gamma <=
  2), 1 + 0.2 sqrt((eps_gamma - 2)(5 - eps_gamma)) (< 3.5), 1.3 beyond;
* thermal flash factor X_M = sqrt(1000) E_r^(1/4) 2/(B_M1 + B_M2), E_r = 2/((1-nu1^2)/E1 + (1-nu2^2)/E2);
  angle factor X_alphabeta = 1.22 sin(alpha_wt)^(1/4) / (cos(alpha_wt)^(1/2) cos(beta)^(1/4));
* geometry factor along the path, Gamma = rho_1/rho_C1 - 1: X_G = 0.51 X_alphabeta sqrt(u + 1) |sqrt(1 + Gamma) -
  sqrt(1 - Gamma/u)| / ((1 + Gamma)(u - Gamma))^(1/4); X_BE its value at the pinion tip without X_alphabeta;
* roughness factor X_R = 2.2 (R_a/rho_redC)^(1/4) (R_a the mean flank R_a, rho_redC the normal relative radius at the
  pitch point); base-oil factor X_L (mineral 1.0, PAO 0.8, polyglycol 0.7, ester 1.3, traction 1.5);
* flash method: mu_m = 0.060 (w_Bt/(v_SigmaC rho_redC))^0.2 eta_oil^-0.05 X_L X_R; theta_fl = mu_m X_M X_J X_G
  (X_Gamma w_Bt)^(3/4) v^(1/2) / a^(1/4) along the path with the load sharing factor X_Gamma (spur: 1/3 rising to
  2/3 over A-B, 1 over B-D, 2/3 falling to 1/3 over D-E; eps_beta >= 1: X_but/eps_alpha with the buttressing
  factor X_but = 1.3 at A and E falling linearly to 1 over 10 % of the path [approximation of the standard's
  buttressing width]; 0 < eps_beta < 1 interpolated linearly); X_J = 1; bulk temperature theta_M = theta_oil +
  0.47 X_S X_mp theta_flm (theta_flm the mean along the path, X_S 1.0 oil bath / 1.2 spray, X_mp 1); scuffing
  temperature theta_S = 80 + (0.85 + 1.4 X_W) X_L' S_FZG^2 with X_L' = eta_oil^-0.05 X_L (as in a KISSsoft 2017
  report to ISO/TR 13989-1), X_W 1.0 (1.5 nitrided); S_B = (theta_S - theta_oil)/(theta_B,max - theta_oil);
* integral method: mu_mC = 0.045 (w_Bt K_Bgamma/(v_SigmaC rho_redC))^0.2 eta_oil^-0.05 X_R X_L; theta_flaE = mu_mC
  X_M X_BE X_alphabeta (K_Bgamma w_Bt)^(3/4) v^(1/2)/a^(1/4) X_E/(X_Q X_Ca); theta_flaint = X_eps theta_flaE;
  theta_M = theta_oil + 0.70 X_S theta_flaint; theta_int = theta_M + 1.5 theta_flaint; contact ratio factor X_eps
  of the addendum contact ratios eps_1, eps_2 (three cases, continuous); tip relief factor X_Ca = 1 + (0.06 + 0.18
  C_a/C_eff) eps_max + (0.02 + 0.69 C_a/C_eff) eps_max^2, C_eff = K_A F_t/(b c_gamma); meshing factor X_Q from the
  approach/recess ratio; X_E = 1 (run-in); integral scuffing temperature theta_Sint = 80 + 0.23 T_1T X_L + 1.5 X_WrelT
  0.2 T_1T X_L with the FZG pinion torque T_1T of the failure load stage ([M]: recalled, not re-read; reproduces the
  KISSsoft report within 3 %); S_intS = theta_Sint/theta_int.

The tip relief used is max(C_a, C_ay) (running-in produces C_ay where the design relief is smaller). Only the FZG
A/8.3/90 test is implemented. An oil temperature at or above a scuffing temperature raises GearoptInputError.
"""

from __future__ import annotations

import math

from .. import numerics as nm
from ..errors import GearoptInputError
from ..units import RAD_PER_DEG
from .contact_stress import nominal_tangential_force_N
from .load_factors import running_in_tip_relief_um
from .material_groups import iso6336_material_group
from .materials import material_pair
from .stiffness import iso6336_stiffness

#: FZG A/8.3/90 pinion torque T_1 [N m] of load stages 1..14 (ISO 14635-1 as commonly tabulated; [M]).
FZG_PINION_TORQUE_NM = (3.3, 13.7, 35.3, 60.8, 94.1, 135.3, 183.4, 239.3, 302.0, 372.6, 450.1, 534.5, 626.8, 726.0)
BASE_OIL_FACTOR = {"mineral": 1.0, "polyalphaolefin": 0.8, "polyglycol": 0.7, "ester": 1.3, "traction": 1.5}
PATH_SAMPLES = 41


def _fzg_torque(stage):
    if nm.is_symbolic(stage):
        raise GearoptInputError("fzg_load_stage must be numeric")
    s = nm.to_float(stage)
    lo = min(int(math.floor(s)), 13)
    t0, t1 = FZG_PINION_TORQUE_NM[lo - 1], FZG_PINION_TORQUE_NM[lo]
    return t0 + (t1 - t0) * (s - lo) if s < 14 else FZG_PINION_TORQUE_NM[-1]


def helical_load_factor(total_contact_ratio):
    """K_Bgamma of the integral method (module docstring). Dual-typed."""
    e = total_contact_ratio
    mid = 1.0 + 0.2 * nm.sqrt(nm.fmax((e - 2.0) * (5.0 - e), 0.0))
    return nm.where(e <= 2.0, 1.0, nm.where(e < 3.5, mid, 1.3))


def contact_ratio_factor_integral(eps_alpha, eps_1, eps_2):
    """X_eps of ISO/TR 13989-2 from the transverse and the addendum contact ratios (eps_1 of the pinion); three
    cases (eps_1, eps_2 < 1; eps_1 >= 1; eps_2 >= 1), continuous across. Dual-typed."""
    k = 1.0 / (2.0 * eps_alpha * eps_1)
    both = 0.70 * (eps_1 ** 2 + eps_2 ** 2) - 0.22 * (eps_1 + eps_2) + 0.52 - 0.60 * eps_1 * eps_2
    one = 0.18 * eps_1 ** 2 + 0.70 * eps_2 ** 2 + 0.82 * eps_1 - 0.52 * eps_2 - 0.30 * eps_1 * eps_2
    two = 0.70 * eps_1 ** 2 + 0.18 * eps_2 ** 2 - 0.52 * eps_1 + 0.82 * eps_2 - 0.30 * eps_1 * eps_2
    return k * nm.where(eps_1 >= 1.0, one, nm.where(eps_2 >= 1.0, two, both))


def tip_relief_factor(tip_relief_um, effective_relief_um, eps_max):
    """X_Ca = 1 + (0.06 + 0.18 r) eps_max + (0.02 + 0.69 r) eps_max^2, r = min(C_a/C_eff, 1). Dual-typed."""
    r = nm.fmin(tip_relief_um / effective_relief_um, 1.0)
    return 1.0 + (0.06 + 0.18 * r) * eps_max + (0.02 + 0.69 * r) * eps_max ** 2


def meshing_factor(approach_ratio, recess_ratio):
    """X_Q: 1 for eps_approach/eps_recess <= 1.5, 1.40 - 4/15 of the ratio up to 3, 0.6 beyond. Dual-typed."""
    q = approach_ratio / recess_ratio
    return nm.where(q <= 1.5, 1.0, nm.where(q < 3.0, 1.40 - 4.0 / 15.0 * q, 0.6))


def geometry_factor(gamma, gear_ratio, X_alphabeta=1.0):
    """X_G(Gamma) (module docstring). Dual-typed."""
    u = gear_ratio
    return (0.51 * X_alphabeta * nm.sqrt(u + 1.0) * nm.fabs(nm.sqrt(1.0 + gamma) - nm.sqrt(1.0 - gamma / u))
            / ((1.0 + gamma) * (u - gamma)) ** 0.25)


def _load_sharing(s, s_b, s_d, eps_beta, eps_alpha):
    """X_Gamma at path fraction s (0 at A, 1 at E), s_b/s_d the fractions of B and D."""
    spur = nm.where(s < s_b, 1.0 / 3.0 + (1.0 / 3.0) * s / s_b,
                    nm.where(s <= s_d, 1.0, 1.0 / 3.0 + (1.0 / 3.0) * (1.0 - s) / (1.0 - s_d)))
    edge = nm.fmin(s, 1.0 - s)
    x_but = 1.0 + 0.3 * nm.fmax(0.0, 1.0 - edge / 0.1)
    helical = x_but / eps_alpha
    w = nm.fmin(eps_beta, 1.0)
    return (1.0 - w) * spur + w * helical


def scuffing_safety_factors(pair, torque_Nm, speed_rpm, *, driving_gear=1, lubricant, materials="20MnCr5",
                            flank_roughness_Ra_um=0.5, tip_relief_um=0.0, K_A=1.0, K_v=1.0, K_Bbeta=1.0,
                            K_Balpha=1.0, mesh_stiffness=None) -> dict:
    """S_B (flash) and S_intS (integral) with the intermediate temperatures and factors (module docstring).
    ``speed_rpm`` and ``torque_Nm`` of gear ``driving_gear``; load factors as computed by
    :func:`~gearopt.rating.iso6336.rate_iso6336`; ``mesh_stiffness`` c_gamma [N/(mm um)] for C_eff (default: ISO
    6336-1 method B of solid blanks). Dual-typed in the pair, torque, speed and factors."""
    if lubricant.fzg_test != "A/8.3/90":
        raise GearoptInputError(f"fzg_test={lubricant.fzg_test!r}: only the A/8.3/90 scuffing temperature is "
                                f"implemented (ISO/TS 6336-20/-21)")
    mats = material_pair(materials)
    ra = flank_roughness_Ra_um if isinstance(flank_roughness_Ra_um, (tuple, list)) else (flank_roughness_Ra_um,) * 2
    g = pair.geometry()
    z = g["teeth"]
    p = 0 if z[0] <= z[1] else 1
    u = z[1 - p] / z[p]
    d = g["pitch_diameter_mm"]
    n_p = speed_rpm if driving_gear - 1 == p else speed_rpm * z[driving_gear - 1] / z[p]
    v = math.pi * d[p] * n_p / 60000.0
    F_t = nominal_tangential_force_N(pair, torque_Nm, driving_gear)
    b = nm.fmin(g["face_width_mm"][0], g["face_width_mm"][1])
    w_bt = K_A * K_v * K_Bbeta * K_Balpha * F_t / b
    awt = g["working_pressure_angle_deg"] * RAD_PER_DEG
    cos_bb = nm.cos(g["base_helix_angle_deg"] * RAD_PER_DEG)
    a = g["centre_distance_mm"]
    eps_a, eps_b = g["transverse_contact_ratio"], g["overlap_contact_ratio"]
    t1t2 = a * nm.sin(awt)
    rho_c1 = 0.5 * g["base_diameter_mm"][p] * nm.tan(awt)
    rho_a1 = nm.sqrt(0.25 * g["tip_diameter_mm"][p] ** 2 - 0.25 * g["base_diameter_mm"][p] ** 2)  # pinion tip: E
    rho_a2 = nm.sqrt(0.25 * g["tip_diameter_mm"][1 - p] ** 2 - 0.25 * g["base_diameter_mm"][1 - p] ** 2)
    rho_e1, rho_s1 = rho_a1, t1t2 - rho_a2  # pinion roll lengths at E (its tip) and A (wheel tip)
    p_bt = g["base_pitch_mm"]
    eps_1 = (rho_e1 - rho_c1) / p_bt
    eps_2 = (rho_c1 - rho_s1) / p_bt
    rho_red_c = rho_c1 * (t1t2 - rho_c1) / t1t2 / cos_bb
    v_sum = 2.0 * v * nm.sin(awt)
    E_r = 2.0 / ((1.0 - mats[0].poisson_ratio ** 2) / mats[0].E_MPa + (1.0 - mats[1].poisson_ratio ** 2)
                 / mats[1].E_MPa)
    b_m = [m.thermal_contact_coefficient_N_per_mm_sqrt_s_K for m in mats]
    X_M = math.sqrt(1000.0) * E_r ** 0.25 * 2.0 / (b_m[0] + b_m[1])
    X_ab = 1.22 * nm.sin(awt) ** 0.25 / (nm.cos(awt) ** 0.5 * nm.cos(g["helix_angle_deg"] * RAD_PER_DEG) ** 0.25)
    X_R = 2.2 * (0.5 * (ra[0] + ra[1]) / rho_red_c) ** 0.25
    X_L = BASE_OIL_FACTOR[lubricant.base_oil]
    X_S = 1.2 if lubricant.lubrication == "spray" else 1.0
    theta_oil = lubricant.oil_temperature_C
    eta = lubricant.dynamic_viscosity_mPa_s(theta_oil)
    c_ay = running_in_tip_relief_um(0.5 * (mats[0].sigma_Hlim_MPa + mats[1].sigma_Hlim_MPa))
    c_a = nm.fmax(tip_relief_um, c_ay)
    x_w = [1.5 if iso6336_material_group(m) == "NT" else 1.0 for m in mats]
    X_W = 0.5 * (x_w[0] + x_w[1])

    # --- flash temperature method -------------------------------------------------------------------------
    mu_m = 0.060 * (w_bt / (v_sum * rho_red_c)) ** 0.2 * eta ** -0.05 * X_L * X_R
    s_b = p_bt / (rho_e1 - rho_s1)  # B is one base pitch after A
    s_d = 1.0 - s_b
    thetas = []
    for k in range(PATH_SAMPLES):
        s = k / (PATH_SAMPLES - 1)
        rho1 = rho_s1 + s * (rho_e1 - rho_s1)
        gamma = rho1 / rho_c1 - 1.0
        x_g = geometry_factor(gamma, u, X_ab)
        x_gam = _load_sharing(s, s_b, s_d, eps_b, eps_a)
        thetas.append(mu_m * X_M * x_g * (x_gam * w_bt) ** 0.75 * v ** 0.5 / a ** 0.25)
    theta_flm = sum(0.5 * (thetas[k] + thetas[k + 1]) for k in range(PATH_SAMPLES - 1)) / (PATH_SAMPLES - 1)
    theta_fl_max = thetas[0]
    for t in thetas[1:]:
        theta_fl_max = nm.fmax(theta_fl_max, t)
    theta_m = theta_oil + 0.47 * X_S * theta_flm
    theta_b = theta_m + theta_fl_max
    s_fzg = lubricant.fzg_load_stage
    theta_s = 80.0 + (0.85 + 1.4 * X_W) * eta ** -0.05 * X_L * s_fzg ** 2
    if nm.is_numeric(theta_s, theta_oil) and nm.to_float(theta_oil) >= nm.to_float(theta_s):
        raise GearoptInputError(f"oil_temperature_C={nm.to_float(theta_oil):g} C is at or above the scuffing "
                                f"temperature theta_S={nm.to_float(theta_s):.1f} C of FZG load stage {s_fzg} "
                                f"(ISO/TS 6336-20): no scuffing safety exists")
    S_B = (theta_s - theta_oil) / (theta_b - theta_oil)

    # --- integral temperature method ----------------------------------------------------------------------
    eps_g = eps_a + eps_b
    k_bg = helical_load_factor(eps_g)
    mu_mc = 0.045 * (w_bt * k_bg / (v_sum * rho_red_c)) ** 0.2 * eta ** -0.05 * X_R * X_L
    gamma_e = rho_e1 / rho_c1 - 1.0
    X_BE = geometry_factor(gamma_e, u, 1.0)
    c_gamma = iso6336_stiffness(pair, validity="ignore")["mesh_stiffness"] if mesh_stiffness is None else mesh_stiffness
    c_eff = K_A * F_t / (b * c_gamma)
    eps_max = nm.fmax(eps_1, eps_2)
    X_Ca = tip_relief_factor(c_a, c_eff, eps_max)
    pinion_drives = driving_gear - 1 == p
    X_Q = meshing_factor(eps_2, eps_1) if pinion_drives else meshing_factor(eps_1, eps_2)
    X_eps = contact_ratio_factor_integral(eps_a, eps_1, eps_2)
    theta_flae = mu_mc * X_M * X_BE * X_ab * (k_bg * w_bt) ** 0.75 * v ** 0.5 / a ** 0.25 / (X_Q * X_Ca)
    theta_flaint = X_eps * theta_flae
    theta_mc = theta_oil + 0.70 * X_S * theta_flaint
    theta_int = theta_mc + 1.5 * theta_flaint
    t_1t = _fzg_torque(s_fzg)
    theta_sint = 80.0 + 0.23 * t_1t * X_L + 1.5 * 0.2 * t_1t * X_L
    if nm.is_numeric(theta_oil) and nm.to_float(theta_oil) >= theta_sint:
        raise GearoptInputError(f"oil_temperature_C={nm.to_float(theta_oil):g} C is at or above the integral "
                                f"scuffing temperature {theta_sint:.1f} C (ISO/TS 6336-21)")
    S_intS = theta_sint / theta_int
    notes = []
    if nm.is_numeric(eps_a) and nm.to_float(eps_a) >= 2.0:
        notes.append(f"ISO/TS 6336-21 (ISO/TR 13989-2) X_eps: transverse contact ratio {nm.to_float(eps_a):.3f} >= 2 "
                     f"is outside the three cases implemented (eps_alpha < 2)")
    if nm.is_numeric(c_a, c_eff) and nm.to_float(c_a) > nm.to_float(c_eff):
        notes.append(f"ISO/TS 6336-21 (ISO/TR 13989-2) X_Ca: tip relief {nm.to_float(c_a):.1f} um exceeds C_eff="
                     f"{nm.to_float(c_eff):.1f} um; X_Ca uses C_a/C_eff = 1")
    return {"S_B": S_B, "S_intS": S_intS, "w_Bt_N_per_mm": w_bt, "X_M": X_M, "X_alphabeta": X_ab, "X_R": X_R,
            "X_L": X_L, "mu_m": mu_m, "theta_fl_max_C": theta_fl_max, "theta_flm_C": theta_flm,
            "theta_M_C": theta_m, "theta_B_C": theta_b, "theta_S_C": theta_s, "K_Bgamma": k_bg, "mu_mC": mu_mc,
            "X_BE": X_BE, "X_Ca": X_Ca, "C_eff_um": c_eff, "C_a_um": c_a, "X_Q": X_Q, "X_eps": X_eps,
            "eps_1": eps_1, "eps_2": eps_2, "theta_flaE_C": theta_flae, "theta_flaint_C": theta_flaint,
            "theta_MC_C": theta_mc, "theta_int_C": theta_int, "theta_Sint_C": theta_sint,
            "dynamic_viscosity_mPa_s": eta, "notes": tuple(notes)}


__all__ = ["FZG_PINION_TORQUE_NM", "BASE_OIL_FACTOR", "helical_load_factor", "contact_ratio_factor_integral",
           "tip_relief_factor", "meshing_factor", "geometry_factor", "scuffing_safety_factors"]
