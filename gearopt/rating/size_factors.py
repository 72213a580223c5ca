"""ISO 6336-2/-3:2006 size factors Z_X and Y_X, relative notch sensitivity Y_deltarelT and relative surface factor
Y_RrelT (method B), each with its static value for the finite-life interpolation, dual-typed.

Material groups as in :mod:`gearopt.rating.material_groups` (St, V, GGG, GG, Eh, NT).
"""

from __future__ import annotations

import warnings

import numpy as np

from .. import numerics as nm
from ..validation import check_range
from .material_groups import iso6336_material_group
from .validity import RatingValidityWarning

#: ISO 6336-3:2006 Table 5 slip-layer thickness rho' [mm] of St/V/GGG(perl.) steels against the 0.2 % proof stress
#: [MPa] (St rows 300/400, V/GTS/GGG rows 500..1000), interpolated linearly and held at the ends.
SLIP_LAYER_STEEL = ((300.0, 0.0833), (400.0, 0.0445), (500.0, 0.0281), (600.0, 0.0194), (800.0, 0.0064),
                    (1000.0, 0.0014))
#: rho' [mm] of grey cast iron against the tensile strength [MPa] (150 and 300 MPa rows).
SLIP_LAYER_GREY_IRON = ((150.0, 0.3124), (300.0, 0.3095))
SLIP_LAYER_CASE_HARDENED = 0.0030
SLIP_LAYER_NITRIDED = 0.1005
#: Relative stress gradient of the standard reference test gear (q_sT = 2.5): chi*_T = (1 + 2 q_sT)/5.
CHI_STAR_TEST = 1.2
MAX_ROOT_ROUGHNESS_RZ_UM = 40.0


def size_factor_contact(module_mm=None):
    """ISO 6336-2:2006 clause 13: Z_X = 1 (the standard's recommendation where no experience says otherwise)."""
    return 1.0


def size_factor_root(module_mm, material):
    """ISO 6336-3:2006 clause 14 (Table 6) endurance size factor Y_X of the normal module m_n [mm]:
    St/V/GGG 1.03 - 0.006 m_n (5 < m_n < 30, 0.85 beyond), Eh/NT 1.05 - 0.01 m_n (5 < m_n < 25, 0.8 beyond),
    GG 1.075 - 0.015 m_n (5 < m_n < 25, 0.7 beyond); 1 for m_n <= 5. (Static Y_X = 1.) Dual-typed."""
    check_range("module_mm", module_mm, 0.0, None, low_inclusive=False, unit="mm")
    group = iso6336_material_group(material)
    a, k, floor = {"St": (1.03, 0.006, 0.85), "V": (1.03, 0.006, 0.85), "GGG": (1.03, 0.006, 0.85),
                   "Eh": (1.05, 0.01, 0.8), "NT": (1.05, 0.01, 0.8), "GG": (1.075, 0.015, 0.7)}[group]
    return nm.fmin(1.0, nm.fmax(floor, a - k * module_mm))


def _interp(x, table):
    xs = np.array([p[0] for p in table])
    ys = np.array([p[1] for p in table])
    return float(np.interp(x, xs, ys))


def slip_layer_thickness_mm(material) -> float:
    """ISO 6336-3:2006 Table 5 slip-layer thickness rho' [mm] of a catalogue material (see the module constants)."""
    from .materials import material as get
    m = get(material)
    group = iso6336_material_group(m)
    if group == "Eh":
        return SLIP_LAYER_CASE_HARDENED
    if group == "NT":
        return SLIP_LAYER_NITRIDED
    if group == "GG":
        return _interp(m.require("tensile_strength_MPa"), SLIP_LAYER_GREY_IRON)
    return _interp(m.require("yield_strength_MPa"), SLIP_LAYER_STEEL)


def relative_notch_sensitivity(notch_parameter_q_s, material):
    """ISO 6336-3:2006 clause 13 method B endurance value Y_deltarelT = (1 + sqrt(rho' chi*)) / (1 + sqrt(rho'
    chi*_T)) with the relative stress gradient chi* = (1 + 2 q_s)/5 [1/mm] and chi*_T = 1.2 of the test gear.
    Dual-typed in q_s."""
    rho = slip_layer_thickness_mm(material)
    chi = (1.0 + 2.0 * notch_parameter_q_s) / 5.0
    return (1.0 + nm.sqrt(rho * chi)) / (1.0 + (rho * CHI_STAR_TEST) ** 0.5)


def relative_notch_sensitivity_static(stress_correction_factor_Y_S, material):
    """ISO 6336-3:2006 clause 13 static Y_deltarelT: Eh 0.44 Y_S + 0.12, NT 0.20 Y_S + 0.60, GG 1.0; St/V/GGG
    (1 + 0.93 (Y_S - 1) (200/sigma_0.2)^0.25) / (1 + 0.93 (200/sigma_0.2)^0.25) ([M]: recalled, not re-read).
    Dual-typed in Y_S."""
    from .materials import material as get
    m = get(material)
    group = iso6336_material_group(m)
    y_s = stress_correction_factor_Y_S
    if group == "Eh":
        return 0.44 * y_s + 0.12
    if group == "NT":
        return 0.20 * y_s + 0.60
    if group == "GG":
        return 1.0
    k = 0.93 * (200.0 / m.require("yield_strength_MPa")) ** 0.25
    return (1.0 + k * (y_s - 1.0)) / (1.0 + k)


def relative_surface_factor(root_roughness_Rz_um, material):
    """ISO 6336-3:2006 clause 13 method B endurance Y_RrelT of the root roughness R_z [um]:
    V/GGG/Eh: 1.674 - 0.529 (R_z + 1)^0.1 (1.12 below R_z 1 um); St: 5.306 - 4.203 (R_z + 1)^0.01 (1.07);
    GG/NT: 4.299 - 3.259 (R_z + 1)^0.0058 (1.025). Validity R_z <= 40 um (warning naming the clause above).
    Dual-typed in R_z. (Static Y_RrelT = 1.)"""
    check_range("root_roughness_Rz_um", root_roughness_Rz_um, 0.0, None, low_inclusive=False, unit="um")
    if nm.is_numeric(root_roughness_Rz_um) and nm.to_float(root_roughness_Rz_um) > MAX_ROOT_ROUGHNESS_RZ_UM:
        warnings.warn(f"root_roughness_Rz_um={nm.to_float(root_roughness_Rz_um):g} um exceeds ISO 6336-3:2006 "
                      f"clause 13's range of Y_RrelT (R_z <= {MAX_ROOT_ROUGHNESS_RZ_UM:g} um)", RatingValidityWarning,
                      stacklevel=2)
    group = iso6336_material_group(material)
    rz = root_roughness_Rz_um
    if group in ("V", "GGG", "Eh"):
        rough, smooth = 1.674 - 0.529 * (rz + 1.0) ** 0.1, 1.12
    elif group == "St":
        rough, smooth = 5.306 - 4.203 * (rz + 1.0) ** 0.01, 1.07
    else:
        rough, smooth = 4.299 - 3.259 * (rz + 1.0) ** 0.0058, 1.025
    return nm.where(rz < 1.0, smooth, rough)


__all__ = ["size_factor_contact", "size_factor_root", "slip_layer_thickness_mm",
           "relative_notch_sensitivity", "relative_notch_sensitivity_static", "relative_surface_factor",
           "SLIP_LAYER_STEEL", "SLIP_LAYER_GREY_IRON", "CHI_STAR_TEST"]
