"""Scuffing load capacity of cylindrical gears: flash-temperature method (ISO/TS 6336-20, the successor of ISO/TR
13989-1) and integral-temperature method (ISO/TS 6336-21, successor of ISO/TR 13989-2), dual-typed.

Equation numbers are those of ISO/TR 13989-1/-2:2000 (the TS editions keep the methods). Temperatures in C, w in
N/mm, v in m/s (reference circle), a in mm, eta in mPa s, roughness in um:

* scuffing load w_Bt = K_A K_v K_Bbeta K_Balpha F_t / b; helical load factor (integral, eq. 5) K_Bgamma = 1
  (eps_gamma <= 2), 1 + 0.2 sqrt((eps_gamma - 2)(5 - eps_gamma)) (< 3.5), 1.3 beyond;
* thermal flash factor X_M = sqrt(1000) E_r^(1/4) 2/(B_M1 + B_M2), E_r = 2/((1-nu1^2)/E1 + (1-nu2^2)/E2) (50 for
  steel with B_M 13.8); angle factor (part 2 eq. 13, full form) X_alphabeta = 1.22 sin(alpha_wt)^(1/4)
  cos(alpha_n)^(1/4) cos(beta)^(1/4) / (cos(alpha_wt)^(1/2) cos(alpha_t)^(1/2)), used by both methods;
* parameter on the line of action Gamma = rho_1/rho_C1 - 1 (A, B, D, E from the tip diameters, eqs. 30-33);
  geometry factor X_G = 0.51 X_alphabeta sqrt(u + 1) |sqrt(1 + Gamma) - sqrt(1 - Gamma/u)| / ((1 + Gamma)
  (u - Gamma))^(1/4) (eq. A.6); X_BE its value at the pinion tip without X_alphabeta (part 2 eq. 22);
* friction: sum of velocities at the pitch point v_SigmaC = 2 v tan(alpha_wt) cos(alpha_t), normal relative radius
  rho_redC = u/(1 + u)^2 a sin(alpha_wt)/cos(beta_b), roughness factor X_R = 2.2 (R_a/rho_redC)^(1/4), the load in
  the friction formula held at >= 150 N/mm and v at <= 50 m/s (part 2 clause 5.1; applied to both methods);
  base-oil factor X_L (mineral 1.0, PAO 0.8, polyglycol 0.7, ester 1.3, traction 1.5);
* flash method: mu_m = 0.060 (w_Bt/(v_SigmaC rho_redC))^0.2 eta_oil^-0.05 X_L X_R; theta_fl = mu_m X_M X_J X_G
  (X_Gamma w_Bt)^(3/4) v^(1/2) / a^(1/4) (eq. A.5) along the path with the load sharing factor X_Gamma (clause 9:
  unmodified spur / narrow helical (Q - 2)/15 at A rising linearly to 1 at B, 1 to D, falling to (Q - 2)/15 at E,
  Q = max(7, accuracy grade), times the buttressing factor X_but for helical gears; wide helical (eps_gamma > 2)
  X_but/eps_alpha; X_but = 1 + 0.3 min(eps_beta, 1) at A and E falling linearly to 1 over Gamma = 0.2 sin(beta_b),
  eqs. 49-56; the profile-modified branches 9.3/9.5/9.7 are not implemented: a design relief enters through X_J)
  and the approach factor X_J = max(1, 1 + (C_eff - C_a)/50 (|Gamma|/(Gamma_E - Gamma_A))^3) on the approach side
  (eqs. 45-48), C_eff = K_A F_t/(b cos(alpha_t) c_gamma) (eq. B.1); bulk temperature theta_M = theta_oil + 0.47 X_S
  X_mp theta_flm (theta_flm the mean along the path, X_S 1.0 oil bath / 1.2 spray, X_mp 1); scuffing temperature
  theta_S = 80 + (0.85 + 1.4 X_W) X_L' S_FZG^2 with X_L' = eta_oil^-0.05 X_L (eq. 99), X_W 1.0 (1.5 nitrided);
  S_B = (theta_S - theta_oil)/(theta_B,max - theta_oil) (eq. 100);
* integral method: mu_mC = 0.045 (w_Bt K_Bgamma/(v_SigmaC rho_redC))^0.2 eta_oil^-0.05 X_R X_L; theta_flaE = mu_mC
  X_M X_BE X_alphabeta (K_Bgamma w_Bt)^(3/4) v^(1/2)/a^(1/4) X_E/(X_Q X_Ca) (eq. 19); theta_flaint = X_eps
  theta_flaE; theta_M = theta_oil + 0.70 X_S theta_flaint; theta_int = theta_M + 1.5 theta_flaint; contact ratio
  factor X_eps of the addendum contact ratios (eqs. 39-44); tip relief factor X_Ca = 1 + (0.06 + 0.18 C_a/C_eff)
  eps_max + (0.02 + 0.69 C_a/C_eff) eps_max^2 with C_eff = K_A F_t/(b c) (c_gamma helical, c' spur), credited only
  for ISO 1328 grade <= 6 (eqs. 32-38); meshing factor X_Q from the approach/recess ratio (eqs. 25-29); X_E = 1
  (run-in); integral scuffing temperature theta_Sint = 80 + 0.23 T_1T X_L + 1.5 X_WrelT 0.2 T_1T (100/nu_40)^0.02
  X_L with T_1T = 3.726 S_FZG^2 N m (eqs. 94-97); S_intS = theta_Sint/theta_int (eq. 14).

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

#: FZG A/8.3/90 pinion torque per squared load stage, T_1T = 3.726 S_FZG^2 [N m] (ISO/TR 13989-2 eq. 97).
FZG_TORQUE_PER_STAGE_SQUARED_NM = 3.726
#: Friction formulas' lower load and upper speed limits (ISO/TR 13989-2 clause 5.1).
FRICTION_MIN_LOAD_N_PER_MM = 150.0
FRICTION_MAX_SPEED_M_S = 50.0
BASE_OIL_FACTOR = {"mineral": 1.0, "polyalphaolefin": 0.8, "polyglycol": 0.7, "ester": 1.3, "traction": 1.5}
#: Samples per segment of the path of contact (A-B, B-D, D-E and the buttressing ends are sampled separately).
SEGMENT_SAMPLES = 12


def helical_load_factor(total_contact_ratio):
    """K_Bgamma of the integral method (module docstring). Dual-typed."""
    e = total_contact_ratio
    mid = 1.0 + 0.2 * nm.sqrt(nm.fmax((e - 2.0) * (5.0 - e), 0.0))
    return nm.where(e <= 2.0, 1.0, nm.where(e < 3.5, mid, 1.3))


def contact_ratio_factor_integral(eps_alpha, eps_1, eps_2):
    """X_eps of ISO/TR 13989-2 eqs. 39-44 from the transverse and the addendum contact ratios (eps_1 of the pinion):
    eps_alpha < 1; 1 <= eps_alpha < 2 with eps_1, eps_2 < 1, eps_1 >= 1 or eps_2 >= 1; 2 <= eps_alpha < 3 with
    eps_1 >= eps_2 or not (held beyond 3). Dual-typed."""
    k = 1.0 / (2.0 * eps_alpha * eps_1)
    low = eps_1 ** 2 + eps_2 ** 2
    both = 0.70 * (eps_1 ** 2 + eps_2 ** 2) - 0.22 * (eps_1 + eps_2) + 0.52 - 0.60 * eps_1 * eps_2
    one = 0.18 * eps_1 ** 2 + 0.70 * eps_2 ** 2 + 0.82 * eps_1 - 0.52 * eps_2 - 0.30 * eps_1 * eps_2
    two = 0.70 * eps_1 ** 2 + 0.18 * eps_2 ** 2 - 0.52 * eps_1 + 0.82 * eps_2 - 0.30 * eps_1 * eps_2
    hi1 = 0.44 * eps_1 ** 2 + 0.59 * eps_2 ** 2 + 0.30 * eps_1 - 0.30 * eps_2 - 0.15 * eps_1 * eps_2
    hi2 = 0.59 * eps_1 ** 2 + 0.44 * eps_2 ** 2 - 0.30 * eps_1 + 0.30 * eps_2 - 0.15 * eps_1 * eps_2
    mid = nm.where(eps_1 >= 1.0, one, nm.where(eps_2 >= 1.0, two, both))
    high = nm.where(eps_1 >= eps_2, hi1, hi2)
    return k * nm.where(eps_alpha < 1.0, low, nm.where(eps_alpha < 2.0, mid, high))


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


def buttressing_factor(gamma, gamma_a, gamma_e, eps_beta, base_helix_angle_deg):
    """X_but of ISO/TR 13989-1 eqs. 49-56: 1 + 0.3 min(eps_beta, 1) at A and E, falling linearly to 1 over
    Gamma = 0.2 sin(beta_b) from each end; 1 for spur gears. Dual-typed."""
    width = 0.2 * nm.sin(nm.fabs(base_helix_angle_deg) * RAD_PER_DEG) + 1e-12
    peak = 1.0 + 0.3 * nm.fmin(eps_beta, 1.0)
    edge = nm.fmin(gamma - gamma_a, gamma_e - gamma)
    return 1.0 + (peak - 1.0) * nm.fmax(0.0, 1.0 - edge / width)


def load_sharing_factor(gamma, points, eps_alpha, eps_beta, base_helix_angle_deg, accuracy_grade=6):
    """X_Gamma of ISO/TR 13989-1 clause 9 for unmodified profiles (eqs. 57-59, 76) at ``gamma``; ``points`` =
    (Gamma_A, Gamma_B, Gamma_D, Gamma_E). Dual-typed."""
    ga, gb, gd, ge = points
    q = max(7.0, float(accuracy_grade)) if nm.is_numeric(accuracy_grade) else 7.0
    end = (q - 2.0) / 15.0
    shape = nm.where(gamma < gb, end + (1.0 - end) * (gamma - ga) / (gb - ga),
                     nm.where(gamma <= gd, 1.0, end + (1.0 - end) * (ge - gamma) / (ge - gd)))
    shape = nm.clip(shape, 0.0, 1.0)
    x_but = buttressing_factor(gamma, ga, ge, eps_beta, base_helix_angle_deg)
    wide = (eps_alpha + eps_beta > 2.0) if nm.is_numeric(eps_alpha, eps_beta) else None
    helical = x_but / eps_alpha
    if wide is None:
        return nm.where(eps_alpha + eps_beta > 2.0, nm.where(eps_beta > 0.0, helical, shape), shape * x_but)
    if wide and nm.to_float(eps_beta) > 0.0:
        return helical
    return shape * x_but


def _segment_points(lo, hi, n):
    return [lo + (hi - lo) * k / n for k in range(n + 1)]


def scuffing_safety_factors(pair, torque_Nm, speed_rpm, *, driving_gear=1, lubricant, materials="20MnCr5",
                            flank_roughness_Ra_um=0.5, tip_relief_um=0.0, K_A=1.0, K_v=1.0, K_Bbeta=1.0,
                            K_Balpha=1.0, mesh_stiffness=None, single_stiffness=None, accuracy_grade=6,
                            flash_roughness_Ra_um=None) -> dict:
    """S_B (flash) and S_intS (integral) with the intermediate temperatures and factors (module docstring).
    ``speed_rpm`` and ``torque_Nm`` of gear ``driving_gear``; load factors as computed by
    :func:`~gearopt.rating.iso6336.rate_iso6336`; ``mesh_stiffness`` c_gamma and ``single_stiffness`` c'
    [N/(mm um)] for C_eff (default: ISO 6336-1 method B of solid blanks); ``accuracy_grade`` (the coarser of the
    pair) for the load sharing factor and the tip-relief credit; ``flash_roughness_Ra_um`` the flank roughness
    of the flash method's roughness factor X_R when it differs from the integral method's (default
    ``flank_roughness_Ra_um``; :func:`~gearopt.rating.iso6336.rate_iso6336` ``flash_roughness``). Dual-typed in
    the pair, torque, speed and factors."""
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
    at = g["transverse_pressure_angle_deg"] * RAD_PER_DEG
    beta_b = g["base_helix_angle_deg"]
    cos_bb = nm.cos(beta_b * RAD_PER_DEG)
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
    gamma_a, gamma_e = rho_s1 / rho_c1 - 1.0, rho_e1 / rho_c1 - 1.0
    gamma_b, gamma_d = gamma_e - p_bt / rho_c1, gamma_a + p_bt / rho_c1
    rho_red_c = u / (1.0 + u) ** 2 * t1t2 / cos_bb
    v_f = nm.fmin(v, FRICTION_MAX_SPEED_M_S)
    v_sum = 2.0 * v_f * nm.tan(awt) * nm.cos(at)
    E_r = 2.0 / ((1.0 - mats[0].poisson_ratio ** 2) / mats[0].E_MPa + (1.0 - mats[1].poisson_ratio ** 2)
                 / mats[1].E_MPa)
    b_m = [m.thermal_contact_coefficient_N_per_mm_sqrt_s_K for m in mats]
    X_M = math.sqrt(1000.0) * E_r ** 0.25 * 2.0 / (b_m[0] + b_m[1])
    X_ab = (1.22 * nm.sin(awt) ** 0.25 * nm.cos(g["pressure_angle_deg"] * RAD_PER_DEG) ** 0.25
            * nm.cos(g["helix_angle_deg"] * RAD_PER_DEG) ** 0.25 / (nm.cos(awt) ** 0.5 * nm.cos(at) ** 0.5))
    X_R = 2.2 * (0.5 * (ra[0] + ra[1]) / rho_red_c) ** 0.25
    ra_flash = ra if flash_roughness_Ra_um is None else (
        flash_roughness_Ra_um if isinstance(flash_roughness_Ra_um, (tuple, list)) else (flash_roughness_Ra_um,) * 2)
    X_R_flash = 2.2 * (0.5 * (ra_flash[0] + ra_flash[1]) / rho_red_c) ** 0.25
    X_L = BASE_OIL_FACTOR[lubricant.base_oil]
    X_S = 1.2 if lubricant.lubrication == "spray" else 1.0
    theta_oil = lubricant.oil_temperature_C
    eta = lubricant.dynamic_viscosity_mPa_s(theta_oil)
    c_ay = running_in_tip_relief_um(0.5 * (mats[0].sigma_Hlim_MPa + mats[1].sigma_Hlim_MPa))
    c_a = nm.fmax(tip_relief_um, c_ay)
    x_w = [1.5 if iso6336_material_group(m) == "NT" else 1.0 for m in mats]
    X_W = 0.5 * (x_w[0] + x_w[1])
    if mesh_stiffness is None or single_stiffness is None:
        stiff = iso6336_stiffness(pair, validity="ignore")
        mesh_stiffness = stiff["mesh_stiffness"] if mesh_stiffness is None else mesh_stiffness
        single_stiffness = stiff["single_stiffness"] if single_stiffness is None else single_stiffness
    pinion_drives = driving_gear - 1 == p
    w_f = nm.fmax(w_bt, FRICTION_MIN_LOAD_N_PER_MM)

    # --- flash temperature method -------------------------------------------------------------------------
    mu_m = 0.060 * (w_f / (v_sum * rho_red_c)) ** 0.2 * eta ** -0.05 * X_L * X_R_flash
    c_eff_flash = K_A * F_t / (b * nm.cos(at) * mesh_stiffness)
    span = gamma_e - gamma_a
    width = 0.2 * nm.sin(nm.fabs(beta_b) * RAD_PER_DEG)
    knots = [gamma_a, gamma_a + width, gamma_b, gamma_d, gamma_e - width, gamma_e]
    gammas = []
    for lo, hi in zip(knots[:-1], knots[1:]):
        gammas += _segment_points(lo, hi, SEGMENT_SAMPLES)[:-1]
    gammas.append(gamma_e)
    thetas = []
    for gamma in gammas:
        x_gam = load_sharing_factor(gamma, (gamma_a, gamma_b, gamma_d, gamma_e), eps_a, eps_b, beta_b,
                                    accuracy_grade)
        approach = (-gamma if pinion_drives else gamma) / span
        x_j = nm.fmax(1.0, 1.0 + (c_eff_flash - c_a) / 50.0 * nm.fmax(approach, 0.0) ** 3)
        x_g = geometry_factor(gamma, u, X_ab)
        thetas.append(mu_m * X_M * x_j * x_g * (x_gam * w_bt) ** 0.75 * v ** 0.5 / a ** 0.25)
    # mean over the path: trapezoids in Gamma (the knots may be unevenly spaced)
    theta_flm = sum(0.5 * (thetas[k] + thetas[k + 1]) * (gammas[k + 1] - gammas[k])
                    for k in range(len(gammas) - 1)) / span
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
    mu_mc = 0.045 * (w_f * k_bg / (v_sum * rho_red_c)) ** 0.2 * eta ** -0.05 * X_R * X_L
    X_BE = geometry_factor(gamma_e, u, 1.0)
    helical = nm.to_float(g["helix_angle_deg"]) != 0.0 if nm.is_numeric(g["helix_angle_deg"]) else True
    c_eff = K_A * F_t / (b * (mesh_stiffness if helical else single_stiffness))
    eps_max = nm.fmax(eps_1, eps_2)
    credited = not (nm.is_numeric(accuracy_grade) and nm.to_float(accuracy_grade) > 6)
    X_Ca = tip_relief_factor(c_a, c_eff, eps_max) if credited else 1.0
    X_Q = meshing_factor(eps_2, eps_1) if pinion_drives else meshing_factor(eps_1, eps_2)
    X_eps = contact_ratio_factor_integral(eps_a, eps_1, eps_2)
    theta_flae = mu_mc * X_M * X_BE * X_ab * (k_bg * w_bt) ** 0.75 * v ** 0.5 / a ** 0.25 / (X_Q * X_Ca)
    theta_flaint = X_eps * theta_flae
    theta_mc = theta_oil + 0.70 * X_S * theta_flaint
    theta_int = theta_mc + 1.5 * theta_flaint
    if nm.is_symbolic(s_fzg):
        raise GearoptInputError("fzg_load_stage must be numeric")
    t_1t = FZG_TORQUE_PER_STAGE_SQUARED_NM * nm.to_float(s_fzg) ** 2
    theta_sint = (80.0 + 0.23 * t_1t * X_L
                  + 1.5 * X_W * 0.2 * t_1t * (100.0 / lubricant.viscosity_40C_mm2_s) ** 0.02 * X_L)
    if nm.is_numeric(theta_oil) and nm.to_float(theta_oil) >= theta_sint:
        raise GearoptInputError(f"oil_temperature_C={nm.to_float(theta_oil):g} C is at or above the integral "
                                f"scuffing temperature {theta_sint:.1f} C (ISO/TS 6336-21)")
    S_intS = theta_sint / theta_int
    notes = []
    if nm.is_numeric(eps_a) and nm.to_float(eps_a) >= 3.0:
        notes.append(f"ISO/TS 6336-21 (ISO/TR 13989-2) X_eps: transverse contact ratio {nm.to_float(eps_a):.3f} >= 3 "
                     f"is beyond the standard's branches (the last one is held)")
    if nm.is_numeric(c_a, c_eff) and credited and nm.to_float(c_a) > nm.to_float(c_eff):
        notes.append(f"ISO/TS 6336-21 (ISO/TR 13989-2) X_Ca: tip relief {nm.to_float(c_a):.1f} um exceeds C_eff="
                     f"{nm.to_float(c_eff):.1f} um; X_Ca uses C_a/C_eff = 1")
    if nm.is_numeric(w_bt) and nm.to_float(w_bt) < FRICTION_MIN_LOAD_N_PER_MM:
        notes.append(f"ISO/TS 6336-21 (ISO/TR 13989-2 cl. 5.1): scuffing load w_Bt={nm.to_float(w_bt):.0f} N/mm below "
                     f"{FRICTION_MIN_LOAD_N_PER_MM:g} N/mm; the friction coefficients use {FRICTION_MIN_LOAD_N_PER_MM:g}")
    return {"S_B": S_B, "S_intS": S_intS, "w_Bt_N_per_mm": w_bt, "X_M": X_M, "X_alphabeta": X_ab, "X_R": X_R,
            "X_L": X_L, "mu_m": mu_m, "theta_fl_max_C": theta_fl_max, "theta_flm_C": theta_flm,
            "theta_M_C": theta_m, "theta_B_C": theta_b, "theta_S_C": theta_s, "K_Bgamma": k_bg, "mu_mC": mu_mc,
            "Gamma_A": gamma_a, "Gamma_B": gamma_b, "Gamma_D": gamma_d, "Gamma_E": gamma_e,
            "X_BE": X_BE, "X_Ca": X_Ca, "C_eff_um": c_eff, "C_a_um": c_a, "X_Q": X_Q, "X_eps": X_eps,
            "eps_1": eps_1, "eps_2": eps_2, "theta_flaE_C": theta_flae, "theta_flaint_C": theta_flaint,
            "theta_MC_C": theta_mc, "theta_int_C": theta_int, "theta_Sint_C": theta_sint,
            "dynamic_viscosity_mPa_s": eta, "notes": tuple(notes)}


__all__ = ["FZG_TORQUE_PER_STAGE_SQUARED_NM", "BASE_OIL_FACTOR", "buttressing_factor", "load_sharing_factor", "helical_load_factor", "contact_ratio_factor_integral",
           "tip_relief_factor", "meshing_factor", "geometry_factor", "scuffing_safety_factors"]
