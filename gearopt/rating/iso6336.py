"""Complete ISO 6336 rating of a cylindrical gear pair: computed load factors (ISO 6336-1:2006), permissible
stresses with life, lubrication, roughness, velocity, size, notch and surface factors (ISO 6336-2/-3:2006 method B),
safety factors S_H, S_F per gear and the scuffing safety factors S_B (flash temperature) and S_intS (integral
temperature) of ISO/TR 13989-1/-2 (ISO/TS 6336-20/-21), dual-typed: :func:`rate_iso6336`.

Defaults chosen here (documented, overridable): flank roughness R_a 0.5 um / R_z 3.0 um (ground flanks, R_z ~ 6
R_a), root roughness R_z 10 um (hobbed, unground root); without ``load_cycles`` or ``life_h`` the rating is for
endurance, N_L = 10^10 on both gears; the mesh misalignment f_ma = f_Hbeta (ISO 6336-1:2006 clause 7.6.4, gear pairs
without provision for adjustment) and f_sh from ISO's pinion-body term (no bearing offset) unless
``mesh_misalignment_um`` F_betax is given; the lubricant :func:`~gearopt.rating.lubrication.default_lubricant`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range, per_gear
from .accuracy import check_accuracy_grade, pair_deviations_um
from .contact_stress import contact_stress_iso6336, nominal_tangential_force_N
from .life_factors import (LONG_LIFE_CYCLES, check_load_cycles, finite_life_value, life_factor_contact,
                           life_factor_root, load_cycles_from_life, reference_cycles)
from .load_factors import (dynamic_factor, face_load_factor_contact, face_load_factor_root,
                           initial_equivalent_misalignment_um, reduced_mass_kg_per_mm, resonance_range,
                           resonance_speed_rpm, running_in_allowance_alpha_um, running_in_allowance_beta_um,
                           running_in_tip_relief_um, transverse_load_factors)
from .deflection import iso6336_shaft_misalignment_um
from .lubrication import (Lubricant, default_lubricant, equivalent_roughness_Rz_um, lubricant_factor,
                          relative_radius_of_curvature_mm, roughness_factor, velocity_factor, work_hardening_factor)
from .material_groups import iso6336_material_group
from .materials import material_pair
from .root_stress import root_stress_iso6336
from .size_factors import (relative_notch_sensitivity, relative_notch_sensitivity_static, relative_surface_factor,
                           size_factor_contact, size_factor_root)
from .validity import RatingValidityWarning
from .stiffness import iso6336_stiffness

DEFAULT_FLANK_RA_UM = 0.5
DEFAULT_FLANK_RZ_UM = 3.0
DEFAULT_ROOT_RZ_UM = 10.0
#: Stress correction factor of the standard reference test gear (ISO 6336-3).
Y_ST = 2.0

#: (symbol, unit, clause) of every factor in the result table.
FACTOR_INFO = {
    "K_A": ("-", "ISO 6336-1:2006 cl. 6.2 (given)"),
    "K_gamma": ("-", "ISO 6336-1:2006 mesh load factor (given)"),
    "K_v": ("-", "ISO 6336-1:2006 cl. 6.3 method B"),
    "K_Hbeta": ("-", "ISO 6336-1:2006 cl. 7.6 method C"),
    "K_Fbeta": ("-", "ISO 6336-1:2006 cl. 7.6.5"),
    "K_Halpha": ("-", "ISO 6336-1:2006 cl. 8.3 method B"),
    "K_Falpha": ("-", "ISO 6336-1:2006 cl. 8.3 method B"),
    "Z_H": ("-", "ISO 6336-2:2006 cl. 6.1"), "Z_E": ("sqrt(MPa)", "ISO 6336-2:2006 cl. 7"),
    "Z_eps": ("-", "ISO 6336-2:2006 cl. 8"), "Z_beta": ("-", "ISO 6336-2:2006 cl. 9"),
    "Z_BD": ("-", "ISO 6336-2:2006 cl. 6.2"),
    "Z_NT": ("-", "ISO 6336-2:2006 cl. 10"), "Z_L": ("-", "ISO 6336-2:2006 cl. 11 method B"),
    "Z_v": ("-", "ISO 6336-2:2006 cl. 11 method B"), "Z_R": ("-", "ISO 6336-2:2006 cl. 11 method B"),
    "Z_W": ("-", "ISO 6336-2:2006 cl. 12"), "Z_X": ("-", "ISO 6336-2:2006 cl. 13"),
    "Y_F": ("-", "ISO 6336-3:2006 cl. 6.2 method B"), "Y_S": ("-", "ISO 6336-3:2006 cl. 7.2"),
    "Y_beta": ("-", "ISO 6336-3:2006 cl. 9"), "Y_B": ("-", "ISO 6336-3:2006 cl. 10"),
    "Y_DT": ("-", "ISO 6336-3:2006 cl. 11"), "Y_NT": ("-", "ISO 6336-3:2006 cl. 12"),
    "Y_deltarelT": ("-", "ISO 6336-3:2006 cl. 13 method B"), "Y_RrelT": ("-", "ISO 6336-3:2006 cl. 13 method B"),
    "Y_X": ("-", "ISO 6336-3:2006 cl. 14"), "Y_ST": ("-", "ISO 6336-3:2006 (reference test gear)"),
    "Y_M": ("-", "ISO 6336-3:2019 mean stress factor (given)"),
}


@dataclass
class ISO6336Rating:
    """Result of :func:`rate_iso6336`. ``factors``: ISO symbol -> number (or CasADi) or per-gear 2-tuple;
    ``safety_factors``: ``S_H``, ``S_F`` (2-tuples), ``S_B``, ``S_intS``; ``stresses``: sigma_H, sigma_HP,
    sigma_F, sigma_FP per gear [MPa]; ``details``: intermediate values (resonance ratio, F_betax, y_alpha, ...);
    ``load_cycles`` per gear; ``lubricant``; ``notes`` (validity remarks; those starting with "ISO" are also
    warned as :class:`RatingValidityWarning`); ``table`` (pandas, one row per factor:
    ``factor``, ``gear_1``, ``gear_2``, ``unit``, ``clause``)."""

    factors: dict
    safety_factors: dict
    stresses: dict
    details: dict
    load_cycles: tuple
    lubricant: Lubricant
    notes: tuple = ()
    scuffing: dict = field(default_factory=dict)

    @property
    def table(self) -> pd.DataFrame:
        rows = []
        for key, value in self.factors.items():
            unit, clause = FACTOR_INFO.get(key, ("-", ""))
            pair = value if isinstance(value, tuple) else (value, value)
            rows.append({"factor": key, "gear_1": _num(pair[0]), "gear_2": _num(pair[1]), "unit": unit,
                         "clause": clause})
        for key, value in self.safety_factors.items():
            pair = value if isinstance(value, tuple) else (value, value)
            clause = {"S_H": "ISO 6336-2:2006 cl. 5", "S_F": "ISO 6336-3:2006 cl. 5",
                      "S_B": "ISO/TS 6336-20 (ISO/TR 13989-1) flash temperature",
                      "S_intS": "ISO/TS 6336-21 (ISO/TR 13989-2) integral temperature"}[key]
            rows.append({"factor": key, "gear_1": _num(pair[0]), "gear_2": _num(pair[1]), "unit": "-",
                         "clause": clause})
        return pd.DataFrame(rows)


def _num(x):
    return nm.to_float(x) if nm.is_numeric(x) else x


def _per_gear_positive(name, value, unit):
    vals = per_gear(value, name)
    for i, v in enumerate(vals):
        check_range(f"{name}[{i}]", v, 0.0, None, low_inclusive=False, unit=unit)
    return vals


def _deviations(pair, accuracy_grade, deviations_um):
    dev = pair_deviations_um(pair, accuracy_grade)
    if deviations_um:
        unknown = set(deviations_um) - {"f_pb", "f_falpha", "f_Hbeta"}
        if unknown:
            raise GearoptInputError(f"deviations_um keys {sorted(unknown)} unknown; allowed: f_pb, f_falpha, f_Hbeta")
        for key, value in deviations_um.items():
            vals = per_gear(value, f"deviations_um[{key!r}]")
            for i, v in enumerate(vals):
                check_range(f"deviations_um[{key!r}][{i}]", v, 0.0, None, unit="um")
            dev[key] = vals
    return dev


FLASH_ROUGHNESS = ("Ra", "Rz/6")
"""The flank roughness of the flash-temperature method's roughness factor X_R (ISO/TS 6336-20): ``"Ra"`` the given
mean roughness Ra (default), ``"Rz/6"`` the conventional conversion Ra ~ Rz/6 of the given Rz. A commercial report
(KISSsoft 03/2017, helical stage of the NREL 5 MW drivetrain, tests/validation/test_iso6336_published.py) uses the
latter in its flash method (its friction coefficient 0.041 and flash temperatures are reproduced with Rz/6 = 0.80 um,
not with its stated Ra = 0.60 um) and Ra in its integral method; with "Ra" S_B is 7.8 % above its value."""


def rate_iso6336(pair, torque_Nm, speed_rpm, *, driving_gear=1, application_factor=1.0, accuracy_grade=6,
                 materials="20MnCr5", lubricant=None, flank_roughness_Ra_um=DEFAULT_FLANK_RA_UM,
                 flank_roughness_Rz_um=DEFAULT_FLANK_RZ_UM, root_roughness_Rz_um=DEFAULT_ROOT_RZ_UM,
                 load_cycles=None, life_h=None, long_life_factor=0.85, mesh_misalignment_um=None,
                 tip_relief_um=0.0, deviations_um=None, mesh_load_factor=1.0, Y_M=1.0, solid_blanks=True,
                 rim_thickness_mm=None, web_thickness_mm=None, bore_diameters_mm=None, K_v=None, K_Hbeta=None,
                 K_Halpha=None, flash_roughness: str = "Ra", scuffing: bool = True) -> ISO6336Rating:
    """ISO 6336 rating of ``pair`` with every factor computed (module docstring for the defaults), dual-typed.

    Args:
        pair: :class:`~gearopt.geometry.pair.GearPair` (numeric or CasADi-symbolic).
        torque_Nm, speed_rpm: torque [N m] > 0 and speed [rpm] > 0 of gear ``driving_gear`` (1 or 2).
        application_factor: K_A. accuracy_grade: ISO 1328-1 grade 0..12 (or a 2-tuple); ``deviations_um`` =
            {"f_pb": (g1, g2), "f_falpha": (g1, g2), "f_Hbeta": (g1, g2)} overrides the grade's deviations [um].
        materials: catalogue name, Material, or 2-tuple. lubricant: :class:`Lubricant` (default engine oil).
        flank_roughness_Ra_um, flank_roughness_Rz_um, root_roughness_Rz_um: per gear or one value [um].
        load_cycles: N_L per gear (>= 1), or life_h [h] (N_L = 60 n life_h); neither: endurance (N_L = 1e10).
        long_life_factor: Z_NT = Y_NT at 1e10 cycles (0.85 normal .. 1.0 optimum), held beyond.
        mesh_misalignment_um: F_betax of ISO 6336-1 method C (before running-in); default from f_ma and f_sh.
        tip_relief_um: design tip relief C_a [um] (0: none; a relief above the running-in amount C_ay counts as a
            profile modification for K_Halpha, which then uses f_pb instead of max(f_pb, f_falpha)).
        mesh_load_factor: K_gamma (planetary meshes); Y_M: mean-stress factor per gear (0.7 for an idler).
        solid_blanks, rim_thickness_mm, web_thickness_mm: gear blank of c' (as :func:`iso6336_stiffness`); the rim
            thickness also gives Y_B (s_R/h_t). bore_diameters_mm: per gear, for the reduced mass of K_v.
        K_v, K_Hbeta, K_Halpha: given numbers override the computed factors (K_Falpha follows K_Halpha).
        flash_roughness: ``"Ra"`` or ``"Rz/6"``: the flank roughness of the flash method's X_R
            (:data:`FLASH_ROUGHNESS`).
        scuffing: False skips the scuffing ratings (ISO/TS 6336-20/-21): ``safety_factors`` then holds S_H and S_F
            only (a caller that needs no S_B saves most of a symbolic rating's build time).

    Returns an :class:`ISO6336Rating` (``.factors``, ``.safety_factors``, ``.table``).
    Bad input raises :class:`~gearopt.errors.GearoptInputError` naming the parameter, value and limit; quantities
    outside a formula's stated validity warn with :class:`RatingValidityWarning` naming the clause.
    """
    from .scuffing import scuffing_safety_factors

    if driving_gear not in (1, 2):
        raise GearoptInputError(f"driving_gear={driving_gear!r} must be 1 or 2")
    check_range("torque_Nm", torque_Nm, 0.0, None, low_inclusive=False, unit="N m")
    check_range("speed_rpm", speed_rpm, 0.0, None, low_inclusive=False, unit="rpm")
    check_range("application_factor", application_factor, 1.0, None)
    check_range("mesh_load_factor", mesh_load_factor, 1.0, None)
    y_m = per_gear(Y_M, "Y_M")
    for i in range(2):
        check_range(f"Y_M[{i}]", y_m[i], 0.0, 1.0, low_inclusive=False)
    check_range("tip_relief_um", tip_relief_um, 0.0, None, unit="um")
    for grade in (accuracy_grade if isinstance(accuracy_grade, (tuple, list)) else (accuracy_grade,)):
        check_accuracy_grade(grade)
    ra = _per_gear_positive("flank_roughness_Ra_um", flank_roughness_Ra_um, "um")
    rz = _per_gear_positive("flank_roughness_Rz_um", flank_roughness_Rz_um, "um")
    if flash_roughness not in FLASH_ROUGHNESS:
        raise GearoptInputError(f"flash_roughness={flash_roughness!r} must be one of {FLASH_ROUGHNESS}")
    rz_root = _per_gear_positive("root_roughness_Rz_um", root_roughness_Rz_um, "um")
    if load_cycles is not None and life_h is not None:
        raise GearoptInputError("give load_cycles or life_h, not both")
    lub = default_lubricant() if lubricant is None else lubricant
    if not isinstance(lub, Lubricant):
        raise GearoptInputError(f"lubricant={lubricant!r} must be a gearopt.rating.Lubricant")
    for name, value in (("K_v", K_v), ("K_Hbeta", K_Hbeta), ("K_Halpha", K_Halpha)):
        if value is not None:
            check_range(name, value, 1.0, None)

    mats = material_pair(materials)
    for m in mats:
        m.require("sigma_Hlim_MPa"), m.require("sigma_Flim_MPa")
    s_hlim = (mats[0].sigma_Hlim_MPa, mats[1].sigma_Hlim_MPa)
    notes: list[str] = []
    g = pair.geometry()
    z = g["teeth"]
    p = 0 if z[0] <= z[1] else 1
    w = 1 - p
    d = g["pitch_diameter_mm"]
    speeds = [speed_rpm, speed_rpm]
    speeds[2 - driving_gear] = speed_rpm * z[driving_gear - 1] / z[2 - driving_gear]
    K_A, K_g = application_factor, mesh_load_factor
    F_t = nominal_tangential_force_N(pair, torque_Nm, driving_gear)
    b = nm.fmin(g["face_width_mm"][0], g["face_width_mm"][1])
    v = math.pi * d[p] * speeds[p] / 60000.0  # reference circle [m/s]
    eps_a, eps_b = g["transverse_contact_ratio"], g["overlap_contact_ratio"]
    eps_g = eps_a + eps_b

    # --- deviations and running-in -------------------------------------------------------------------------
    dev = _deviations(pair, accuracy_grade, deviations_um)
    f_pb = nm.fmax(dev["f_pb"][0], dev["f_pb"][1])
    f_fa = nm.fmax(dev["f_falpha"][0], dev["f_falpha"][1])
    f_hb = nm.fmax(dev["f_Hbeta"][0], dev["f_Hbeta"][1])
    y_a = running_in_allowance_alpha_um(f_pb, mats, s_hlim, v)
    y_f = running_in_allowance_alpha_um(f_fa, mats, s_hlim, v)
    c_ay = running_in_tip_relief_um(0.5 * (s_hlim[0] + s_hlim[1]))

    # --- stiffness and dynamic factor --------------------------------------------------------------------------
    stiff = iso6336_stiffness(pair, solid_blanks=solid_blanks, rim_thickness_mm=rim_thickness_mm,
                              web_thickness_mm=web_thickness_mm)
    c1, c_ga, c_gb = stiff["single_stiffness"], stiff["mesh_stiffness"], stiff["mesh_stiffness_beta"]
    bores = (0.0, 0.0) if bore_diameters_mm is None else per_gear(bore_diameters_mm, "bore_diameters_mm")
    d_m = tuple(0.5 * (g["tip_diameter_mm"][i] + g["root_diameter_mm"][i]) for i in range(2))
    for i in range(2):
        check_range(f"bore_diameters_mm[{i}]", bores[i], 0.0, nm.to_float(d_m[i]) if nm.is_numeric(d_m[i]) else None,
                    high_inclusive=False, unit="mm")
    m_red = reduced_mass_kg_per_mm((d_m[p], d_m[w]), (g["base_diameter_mm"][p], g["base_diameter_mm"][w]),
                                   (bores[p], bores[w]), (mats[p].density_kg_m3, mats[w].density_kg_m3), z[w] / z[p])
    n_e1 = resonance_speed_rpm(z[p], c_ga, m_red)
    n_ratio = speeds[p] / n_e1
    w_a = K_A * K_g * F_t / b
    dyn = dynamic_factor(n_ratio, w_a, c1, f_pb - y_a, f_fa - y_f, tip_relief_um, eps_g)
    k_v = dyn["K_v"] if K_v is None else K_v
    if nm.is_numeric(n_ratio, dyn["N_S"]) and K_v is None:
        regime = resonance_range(n_ratio, dyn["N_S"])
        if regime == "main resonance":
            notes.append(f"ISO 6336-1:2006 cl. 6.3.4: resonance ratio N={nm.to_float(n_ratio):.3f} in the main "
                         f"resonance range; operation there should be avoided (method B only estimates K_v)")
    else:
        regime = "given" if K_v is not None else "symbolic"

    # --- face load factors ----------------------------------------------------------------------------------
    f_m_b = w_a * k_v
    if mesh_misalignment_um is None:
        f_sh = iso6336_shaft_misalignment_um(f_m_b, d[p], b)
        f_ma = f_hb
        f_bx = initial_equivalent_misalignment_um(f_sh, f_ma, f_m_b, f_hb)
    else:
        check_range("mesh_misalignment_um", mesh_misalignment_um, 0.0, None, unit="um")
        f_sh, f_ma, f_bx = None, None, mesh_misalignment_um
    y_b = running_in_allowance_beta_um(f_bx, mats, s_hlim, v)
    f_by = f_bx - y_b
    k_hb = face_load_factor_contact(f_by, c_gb, f_m_b) if K_Hbeta is None else K_Hbeta
    h_t = g["whole_depth_mm"]
    bh = nm.fmin(g["face_width_mm"][0] / h_t[0], g["face_width_mm"][1] / h_t[1])
    k_fb = face_load_factor_root(k_hb, bh, 1.0)

    # --- transverse load factors ----------------------------------------------------------------------------
    Z_eps_probe = contact_stress_iso6336(pair, torque_Nm, driving_gear=driving_gear, material=mats)["Z_eps"]
    modified = tip_relief_um > c_ay
    f_alpha = nm.where(modified, f_pb, nm.fmax(f_pb, f_fa)) if nm.is_symbolic(tip_relief_um, c_ay) else \
        (f_pb if nm.to_float(tip_relief_um) > nm.to_float(c_ay) else nm.fmax(f_pb, f_fa))
    trans = transverse_load_factors(eps_a, eps_g, Z_eps_probe, c_ga, f_alpha - y_a, f_m_b * k_hb)
    k_ha = trans["K_Halpha"] if K_Halpha is None else K_Halpha
    k_fa = trans["K_Falpha"] if K_Halpha is None else nm.fmin(K_Halpha, eps_g / (0.25 * eps_a + 0.75))

    # --- stresses -------------------------------------------------------------------------------------------
    cs = contact_stress_iso6336(pair, torque_Nm, driving_gear=driving_gear, K_A=K_A * K_g, K_v=k_v, K_Hbeta=k_hb,
                                K_Halpha=k_ha, material=mats)
    backup = (None, None)
    if not solid_blanks and rim_thickness_mm is not None:
        rims = per_gear(rim_thickness_mm, "rim_thickness_mm")
        backup = tuple(None if rims[i] is None else rims[i] / h_t[i] for i in range(2))
    grade_tuple = accuracy_grade if isinstance(accuracy_grade, (tuple, list)) else (accuracy_grade,) * 2
    rs = root_stress_iso6336(pair, torque_Nm, driving_gear=driving_gear, K_A=K_A * K_g, K_v=k_v, K_Fbeta=k_fb,
                             K_Falpha=k_fa, material=mats, rim_backup_ratio=backup,
                             accuracy_grade=max(grade_tuple) if all(nm.is_numeric(x) for x in grade_tuple) else None)

    # --- load cycles and strength factors -------------------------------------------------------------------
    if load_cycles is not None:
        n_l = per_gear(load_cycles, "load_cycles")
        for i in range(2):
            check_load_cycles(f"load_cycles[{i}]", n_l[i])
    elif life_h is not None:
        n_l = tuple(load_cycles_from_life(life_h, speeds[i]) for i in range(2))
    else:
        n_l = (LONG_LIFE_CYCLES, LONG_LIFE_CYCLES)
    rho_red = relative_radius_of_curvature_mm(pair)
    rz_mean = 0.5 * (rz[0] + rz[1])
    z_nt, z_l, z_v, z_r, z_w, z_x, s_h, sigma_hp = [], [], [], [], [], [], [], []
    y_nt, y_d, y_r, y_x, s_f, sigma_fp = [], [], [], [], [], []
    groups = [iso6336_material_group(m) for m in mats]
    for i, m in enumerate(mats):
        z_nt.append(life_factor_contact(n_l[i], m, long_life_factor=long_life_factor))
        zl = lubricant_factor(lub.viscosity_40C_mm2_s, s_hlim[i])
        zv = velocity_factor(v, s_hlim[i])
        zr = roughness_factor(rz_mean, rho_red, s_hlim[i])
        hard_other = groups[1 - i] in ("Eh", "NT")
        hb = m.brinell_hardness_HB
        if groups[i] in ("V", "GGG", "GG", "St") and hard_other and hb is not None:
            zw = work_hardening_factor(hb, equivalent_roughness_Rz_um(rz[1 - i], rz[i], rho_red,
                                                                      lub.viscosity_40C_mm2_s, v))
        else:
            zw = 1.0
            if groups[i] in ("V", "GGG", "GG", "St") and hard_other:
                notes.append(f"gear {i + 1}: Z_W = 1 (no Brinell hardness for {m.name} in the catalogue)")
        zx = size_factor_contact(g["module_mm"])
        n_static, n_ref = reference_cycles(m, "contact")
        lvr = finite_life_value(n_l[i], 1.0, zl * zv * zr * zw * zx, n_static, n_ref)
        z_l.append(zl), z_v.append(zv), z_r.append(zr), z_w.append(zw), z_x.append(zx)
        strength_h = m.sigma_Hlim_MPa * z_nt[i] * lvr
        sigma_hp.append(strength_h)
        s_h.append(strength_h / cs["sigma_H_MPa"][i])

        gear = rs[f"gear{i + 1}"]
        y_nt.append(life_factor_root(n_l[i], m, long_life_factor=long_life_factor))
        yd = relative_notch_sensitivity(gear["q_s"], m)
        yd_static = relative_notch_sensitivity_static(gear["Y_S"], m)
        yr = relative_surface_factor(rz_root[i], m)
        yx = size_factor_root(g["module_mm"], m)
        n_static, n_ref = reference_cycles(m, "root")
        root_factors = (finite_life_value(n_l[i], yd_static, yd, n_static, n_ref)
                        * finite_life_value(n_l[i], 1.0, yr * yx, n_static, n_ref))
        y_d.append(yd), y_r.append(yr), y_x.append(yx)
        strength_f = m.sigma_Flim_MPa * Y_ST * y_nt[i] * root_factors * y_m[i]
        sigma_fp.append(strength_f)
        s_f.append(strength_f / gear["sigma_F_MPa"])

    factors = {
        "K_A": K_A, "K_gamma": K_g, "K_v": k_v, "K_Hbeta": k_hb, "K_Fbeta": k_fb, "K_Halpha": k_ha, "K_Falpha": k_fa,
        "Z_H": cs["Z_H"], "Z_E": cs["Z_E"], "Z_eps": cs["Z_eps"], "Z_beta": cs["Z_beta"], "Z_BD": cs["Z_BD"],
        "Z_NT": tuple(z_nt), "Z_L": tuple(z_l), "Z_v": tuple(z_v), "Z_R": tuple(z_r), "Z_W": tuple(z_w),
        "Z_X": tuple(z_x),
        "Y_F": (rs["gear1"]["Y_F"], rs["gear2"]["Y_F"]), "Y_S": (rs["gear1"]["Y_S"], rs["gear2"]["Y_S"]),
        "Y_beta": rs["gear1"]["Y_beta"], "Y_B": (rs["gear1"]["Y_B"], rs["gear2"]["Y_B"]),
        "Y_DT": rs["gear1"]["Y_DT"], "Y_NT": tuple(y_nt), "Y_deltarelT": tuple(y_d), "Y_RrelT": tuple(y_r),
        "Y_X": tuple(y_x), "Y_ST": Y_ST, "Y_M": y_m,
    }
    details = {
        "F_t_N": F_t, "pitch_line_velocity_m_s": v, "pinion": p + 1, "speeds_rpm": tuple(speeds),
        "single_stiffness": c1, "mesh_stiffness": c_ga, "mesh_stiffness_beta": c_gb,
        "reduced_mass_kg_per_mm": m_red, "resonance_speed_rpm": n_e1, "resonance_ratio": n_ratio,
        "resonance_range": regime, "N_S": dyn["N_S"], "B_p": dyn["B_p"], "B_f": dyn["B_f"], "B_k": dyn["B_k"],
        "f_pb_um": f_pb, "f_falpha_um": f_fa, "f_Hbeta_um": f_hb, "y_alpha_um": y_a, "y_f_um": y_f,
        "running_in_tip_relief_um": c_ay, "f_sh_um": f_sh, "f_ma_um": f_ma, "F_betax_um": f_bx,
        "y_beta_um": y_b, "F_betay_um": f_by, "line_load_Fm_per_b_N_per_mm": f_m_b, "b_over_h": bh,
        "total_contact_ratio": eps_g,
    }
    stresses = {"sigma_H_MPa": cs["sigma_H_MPa"], "sigma_HG_MPa": tuple(sigma_hp),
                "sigma_F_MPa": (rs["gear1"]["sigma_F_MPa"], rs["gear2"]["sigma_F_MPa"]),
                "sigma_FG_MPa": tuple(sigma_fp)}
    for i, key in enumerate(("gear1", "gear2")):
        q_s = rs[key]["q_s"]
        if nm.is_numeric(q_s) and not 1.0 <= nm.to_float(q_s) < 8.0:
            notes.append(f"ISO 6336-3:2006 cl. 7.2: notch parameter q_s={nm.to_float(q_s):.3f} of gear {i + 1} "
                         f"outside the Y_S fit's range 1 <= q_s < 8")
    safety = {"S_H": tuple(s_h), "S_F": tuple(s_f)}
    scuff: dict = {}
    if scuffing:
        scuff = scuffing_safety_factors(pair, torque_Nm, speed_rpm, driving_gear=driving_gear, lubricant=lub,
                                        materials=mats, flank_roughness_Ra_um=ra, tip_relief_um=tip_relief_um,
                                        flash_roughness_Ra_um=None if flash_roughness == "Ra" else tuple(
                                            r / 6.0 for r in rz),
                                        K_A=K_A * K_g, K_v=k_v, K_Bbeta=k_hb, K_Balpha=k_ha, mesh_stiffness=c_ga,
                                        single_stiffness=c1, accuracy_grade=max(grade_tuple) if all(
                                            nm.is_numeric(x) for x in grade_tuple) else 6)
        safety.update(S_B=scuff["S_B"], S_intS=scuff["S_intS"])
        notes.extend(scuff["notes"])
    for note in notes:
        if note.startswith("ISO"):
            warnings.warn(note, RatingValidityWarning, stacklevel=2)
    return ISO6336Rating(factors=factors, safety_factors=safety, stresses=stresses, details=details,
                         load_cycles=tuple(n_l), lubricant=lub, notes=tuple(notes), scuffing=scuff)


__all__ = ["ISO6336Rating", "rate_iso6336", "FACTOR_INFO", "DEFAULT_FLANK_RA_UM", "DEFAULT_FLANK_RZ_UM",
           "DEFAULT_ROOT_RZ_UM"]
