"""Cylindrical press (interference) fit of a gear hub on a solid or hollow shaft: elastic Lame theory, dual-typed.

Model (Shigley's Mechanical Engineering Design, "Press and shrink fits", Eqs. 3-56/3-57; DIN 7190 elastic case;
thesis Eqs. 3.45-3.47 with the sign error of Eq. 3.45 corrected, docs/source-study.md sec. 2)::

    p = delta / [ d/E_h ((D_o^2 + d^2)/(D_o^2 - d^2) + nu_h) + d/E_s ((d^2 + d_i^2)/(d^2 - d_i^2) - nu_s) ]
    F_f = mu p pi d l        (friction force the joint can hold, axial or circumferential or their resultant)
    T   = F_f d / 2

with ``delta`` the *effective* diametral interference: nominal interference minus the smoothing of the surface
roughness (DIN 7190), plus the thermal change (parts at different temperatures or expansion coefficients), minus the
centrifugal loss at speed (rotating free discs, plane stress). Both members are plane-stress thick cylinders of the
same length (open ends, no axial stress); end effects (the hub-edge pressure peak) are not modelled. The hub is
represented by an equivalent plain cylinder of outer diameter ``hub_outer_diameter_mm`` (for a gear body: below the
root circle; teeth carry no hoop stress; a webbed gear needs an effective value -- thesis sec. 4.7 found the
formula valid for solid gears only).

Units: lengths mm, interference um (diametral), moduli and stresses MPa, forces N, torques N m, speeds rpm,
temperatures deg C, density kg/m^3. Every function accepts floats, numpy arrays or CasADi symbols.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_choice, check_result
from ._checks import check_range_any as check_range
from ._record import ResultRecord

#: DIN 7190 smoothing rules: diametral loss = factor x (Rz_shaft + Rz_hub).
#: [V] MESYS manual "Surface roughness of shaft and housing" (mesys.ag/manual): DIN 7190-1:2017 reduces the effective
#: interference by 0.4 Rz per surface; the previous edition (DIN 7190:2001) used 0.8 Rz.
SMOOTHING_FACTORS = {"din7190_2001": 0.8, "din7190_2017": 0.4}

_STRESS_PER_RHO_OMEGA2_MM2 = 1e-12  # rho [kg/m^3] * omega^2 [1/s^2] * r^2 [mm^2] -> MPa


def lame_compliance_mm_per_MPa(shaft_diameter_mm, shaft_bore_mm, hub_outer_diameter_mm, shaft_E_MPa, shaft_nu,
                               hub_E_MPa, hub_nu):
    """Diametral interference per unit contact pressure [mm/MPa] of a hub on a (hollow) shaft (Lame, plane stress).

    ``d/E_h ((D_o^2+d^2)/(D_o^2-d^2) + nu_h) + d/E_s ((d^2+d_i^2)/(d^2-d_i^2) - nu_s)`` -- Shigley Eq. 3-56 in
    diametral form; the minus sign on ``nu_s`` is the correction of thesis Eq. 3.45 (docs/source-study.md sec. 2).
    """
    d, di, do = shaft_diameter_mm, shaft_bore_mm, hub_outer_diameter_mm
    hub = d / hub_E_MPa * ((do ** 2 + d ** 2) / (do ** 2 - d ** 2) + hub_nu)
    shaft = d / shaft_E_MPa * ((d ** 2 + di ** 2) / (d ** 2 - di ** 2) - shaft_nu)
    return hub + shaft


def press_fit_pressure_MPa(interference_um, shaft_diameter_mm, shaft_bore_mm, hub_outer_diameter_mm, shaft_E_MPa,
                           shaft_nu, hub_E_MPa, hub_nu):
    """Contact pressure [MPa] for an effective diametral interference [um]; 0 if the interference is lost (< 0)."""
    c = lame_compliance_mm_per_MPa(shaft_diameter_mm, shaft_bore_mm, hub_outer_diameter_mm, shaft_E_MPa, shaft_nu,
                                   hub_E_MPa, hub_nu)
    return nm.fmax(interference_um, 0.0) * 1e-3 / c


def roughness_smoothing_loss_um(shaft_roughness_Rz_um, hub_roughness_Rz_um, rule: str = "din7190_2001"):
    """Diametral interference lost to flattening of the roughness peaks [um]: factor x (Rz_shaft + Rz_hub).

    ``rule``: ``"din7190_2001"`` (0.8, the value the gearopt brief names) or ``"din7190_2017"`` (0.4); see
    :data:`SMOOTHING_FACTORS` for the source.
    """
    if rule not in SMOOTHING_FACTORS:
        raise GearoptInputError(f"smoothing_rule={rule!r} must be one of {sorted(SMOOTHING_FACTORS)}")
    check_range("shaft_roughness_Rz_um", shaft_roughness_Rz_um, 0.0, 100.0, unit="um")
    check_range("hub_roughness_Rz_um", hub_roughness_Rz_um, 0.0, 100.0, unit="um")
    return SMOOTHING_FACTORS[rule] * (shaft_roughness_Rz_um + hub_roughness_Rz_um)


def thermal_interference_change_um(shaft_diameter_mm, shaft_temperature_C, hub_temperature_C,
                                   reference_temperature_C=20.0, shaft_expansion_per_K=11.5e-6,
                                   hub_expansion_per_K=11.5e-6):
    """Change of diametral interference [um] when shaft and hub leave the reference (assembly) temperature:
    ``d [alpha_s (T_s - T_ref) - alpha_h (T_h - T_ref)]`` (free thermal growth of both members; positive = tighter)."""
    dT_s = shaft_temperature_C - reference_temperature_C
    dT_h = hub_temperature_C - reference_temperature_C
    return 1e3 * shaft_diameter_mm * (shaft_expansion_per_K * dT_s - hub_expansion_per_K * dT_h)


def centrifugal_interference_loss_um(speed_rpm, shaft_diameter_mm, shaft_bore_mm, hub_outer_diameter_mm,
                                     shaft_E_MPa, shaft_nu, hub_E_MPa, hub_nu, shaft_density_kg_m3=7850.0,
                                     hub_density_kg_m3=7850.0):
    """Diametral interference lost at speed [um]: the free rotating hub bore grows more than the free shaft.

    Rotating annular discs with free edges, plane stress (Shigley, "Rotating rings"; Timoshenko): hoop stress at
    the hub bore ``rho w^2/4 ((3+nu_h) b^2 + (1-nu_h) a^2)`` and at the shaft surface
    ``rho w^2/4 ((3+nu_s) c^2 + (1-nu_s) a^2)`` (a = d/2, b = D_o/2, c = d_i/2); the radial displacement there is
    ``a sigma_t / E`` because the radial stress vanishes. Loss = 2 (u_hub - u_shaft) >= 0 for equal materials.
    """
    w2 = (speed_rpm * (2.0 * math.pi / 60.0)) ** 2
    a, b, c = 0.5 * shaft_diameter_mm, 0.5 * hub_outer_diameter_mm, 0.5 * shaft_bore_mm
    s_hub = hub_density_kg_m3 * w2 / 4.0 * ((3.0 + hub_nu) * b ** 2 + (1.0 - hub_nu) * a ** 2)
    s_shaft = shaft_density_kg_m3 * w2 / 4.0 * ((3.0 + shaft_nu) * c ** 2 + (1.0 - shaft_nu) * a ** 2)
    u_hub = a * s_hub * _STRESS_PER_RHO_OMEGA2_MM2 / hub_E_MPa
    u_shaft = a * s_shaft * _STRESS_PER_RHO_OMEGA2_MM2 / shaft_E_MPa
    return 2e3 * (u_hub - u_shaft)


def von_mises_plane_MPa(sigma_1, sigma_2):
    """Von Mises equivalent stress of a plane stress state with principal stresses sigma_1, sigma_2 [MPa]."""
    return nm.sqrt(sigma_1 ** 2 - sigma_1 * sigma_2 + sigma_2 ** 2)


@dataclass(frozen=True, eq=False)
class PressFitResult(ResultRecord):
    """Capacity and stresses of a press/shrink fit (:func:`press_fit`). Values are floats, numpy arrays (array
    inputs) or CasADi expressions (symbolic inputs); the optional fields are ``None`` when not computed.
    ``to_dict()`` gives the set fields as a plain dict."""

    smoothing_loss_um: Any
    """Diametral interference lost to the smoothing of the surface roughness (DIN 7190) [um]."""
    thermal_interference_change_um: Any
    """Diametral interference change from the parts' temperatures and expansion coefficients [um] (+ = tighter)."""
    centrifugal_interference_loss_um: Any
    """Diametral interference lost at ``speed_rpm`` (rotating free discs) [um]."""
    effective_interference_um: Any
    """Nominal interference - smoothing loss + thermal change - centrifugal loss [um]."""
    pressure_MPa: Any
    """Fit pressure p [MPa] (Lame, plane stress)."""
    friction_force_N: Any
    """Friction force the fit can hold, mu p pi d l [N]."""
    axial_capacity_N: Any
    """Axial capacity [N] (= ``friction_force_N``)."""
    torque_capacity_Nm: Any
    """Torque capacity F d / 2 [N m]."""
    torque_capacity_with_axial_Nm: Any
    """Torque still held under ``axial_force_N``: d/2 sqrt(F^2 - F_a^2) [N m] (friction-force resultant)."""
    release_speed_rpm: Any
    """Speed at which the centrifugal loss eats the interference at rest [rpm] (``inf``: never released)."""
    hub_hoop_stress_MPa: Any
    """Hoop stress at the hub bore, including the centrifugal hoop stress [MPa]."""
    hub_radial_stress_MPa: Any
    """Radial stress at the hub bore, -p [MPa]."""
    hub_von_mises_MPa: Any
    """Von Mises stress at the hub bore [MPa]."""
    hub_outer_hoop_stress_MPa: Any
    """Hoop stress at the hub's outer diameter [MPa]."""
    shaft_hoop_stress_MPa: Any
    """Hoop stress of the shaft at the fit surface [MPa]."""
    shaft_radial_stress_MPa: Any
    """Radial stress of the shaft at the fit surface, -p [MPa]."""
    shaft_von_mises_MPa: Any
    """Largest von Mises stress of the shaft [MPa] (bore of a hollow shaft, uniform p in a solid one)."""
    fit_lost: Any = None
    """Numeric inputs only: the effective interference is <= 0 (pressure then 0); bool or bool array."""
    hub_yield_safety: Any = None
    """Hub yield strength / hub von Mises stress (with ``hub_yield_MPa``; ``inf`` at zero stress)."""
    shaft_yield_safety: Any = None
    """Shaft yield strength / shaft von Mises stress (with ``shaft_yield_MPa``; ``inf`` at zero stress)."""


def _check_press_fit(d, di, do, length, delta, Es, nus, Eh, nuh, mu):
    check_range("shaft_diameter_mm", d, 0.0, None, low_inclusive=False, unit="mm")
    check_range("shaft_bore_mm", di, 0.0, None, unit="mm")
    check_range("hub_outer_diameter_mm", do, 0.0, None, low_inclusive=False, unit="mm")
    if nm.is_numeric(d, di) and nm.to_float(di) >= nm.to_float(d):
        raise GearoptInputError(f"shaft_bore_mm={nm.to_float(di):g} mm must be smaller than shaft_diameter_mm="
                                f"{nm.to_float(d):g} mm (bore >= diameter leaves no shaft wall)")
    if nm.is_numeric(d, do) and nm.to_float(do) <= nm.to_float(d):
        raise GearoptInputError(f"hub_outer_diameter_mm={nm.to_float(do):g} mm must exceed shaft_diameter_mm="
                                f"{nm.to_float(d):g} mm (the hub bore)")
    check_range("length_mm", length, 0.0, None, low_inclusive=False, unit="mm")
    check_range("interference_um", delta, 0.0, None, unit="um")
    check_range("shaft_E_MPa", Es, 0.0, None, low_inclusive=False, unit="MPa")
    check_range("hub_E_MPa", Eh, 0.0, None, low_inclusive=False, unit="MPa")
    check_range("shaft_nu", nus, 0.0, 0.5, low_inclusive=False, high_inclusive=False)
    check_range("hub_nu", nuh, 0.0, 0.5, low_inclusive=False, high_inclusive=False)
    check_range("friction", mu, 0.0, 1.0, low_inclusive=False, high_inclusive=False)


def press_fit(shaft_diameter_mm, shaft_bore_mm, hub_outer_diameter_mm, length_mm, interference_um, shaft_E_MPa,
              shaft_nu, hub_E_MPa, hub_nu, friction, *, smoothing_loss_um=None, roughness_Rz_um=None,
              smoothing_rule: str = "din7190_2001", shaft_temperature_C=20.0, hub_temperature_C=20.0,
              reference_temperature_C=20.0, shaft_expansion_per_K=11.5e-6, hub_expansion_per_K=11.5e-6,
              speed_rpm=0.0, shaft_density_kg_m3=7850.0, hub_density_kg_m3=7850.0, axial_force_N=0.0,
              shaft_yield_MPa=None, hub_yield_MPa=None) -> PressFitResult:
    """Capacity and stresses of a press/shrink fit (elastic; see the module docstring for model and sources).

    Arguments: ``shaft_diameter_mm`` d (= hub bore, the fit diameter), ``shaft_bore_mm`` d_i (0 = solid),
    ``hub_outer_diameter_mm`` D_o (equivalent plain hub), ``length_mm`` l (engaged length), ``interference_um``
    nominal *diametral* interference (>= 0), moduli [MPa], Poisson ratios, ``friction`` mu (0..1).

    Options: ``smoothing_loss_um`` (explicit diametral loss) or ``roughness_Rz_um=(Rz_shaft, Rz_hub)`` with
    ``smoothing_rule`` (:func:`roughness_smoothing_loss_um`); operating ``shaft_temperature_C`` and
    ``hub_temperature_C`` against ``reference_temperature_C`` with expansion coefficients [1/K]; ``speed_rpm`` with
    densities [kg/m^3] for the centrifugal loss; ``axial_force_N`` for the torque still held under an axial load;
    yield strengths [MPa] for safety factors (von Mises).

    Returns a :class:`PressFitResult`: ``effective_interference_um`` (and its parts ``smoothing_loss_um``,
    ``thermal_interference_change_um``, ``centrifugal_interference_loss_um``), ``fit_lost`` (numeric only: the
    effective interference is <= 0, pressure then 0), ``pressure_MPa``, ``friction_force_N`` = ``axial_capacity_N``
    (mu p pi d l), ``torque_capacity_Nm`` (F d/2), ``torque_capacity_with_axial_Nm`` (d/2 sqrt(F^2 - F_a^2): the
    friction-force resultant of combined torque and axial load), ``release_speed_rpm`` (speed at which the
    centrifugal loss eats the interference; ``inf`` when the fit is never released: zero centrifugal loss per
    rpm^2, e.g. a vanishing fit diameter), stresses ``hub_hoop_stress_MPa`` (at the bore, including the
    centrifugal hoop stress), ``hub_radial_stress_MPa`` (-p), ``hub_von_mises_MPa`` (bore),
    ``hub_outer_hoop_stress_MPa``, ``shaft_hoop_stress_MPa`` (at the fit surface), ``shaft_radial_stress_MPa``,
    ``shaft_von_mises_MPa`` (largest: at the bore of a hollow shaft, uniform p in a solid one), and
    ``hub_yield_safety``/``shaft_yield_safety`` when the yield strengths are given (``inf`` at zero stress). A NaN in
    any output raises :class:`~gearopt.errors.NonFiniteResultError` naming it and the inputs.

    Validity: elastic members (check the yield safeties), equal lengths, plane stress; 0 < nu < 0.5.
    """
    d, di, do, l = shaft_diameter_mm, shaft_bore_mm, hub_outer_diameter_mm, length_mm
    _check_press_fit(d, di, do, l, interference_um, shaft_E_MPa, shaft_nu, hub_E_MPa, hub_nu, friction)
    if smoothing_loss_um is not None and roughness_Rz_um is not None:
        raise GearoptInputError("give either smoothing_loss_um or roughness_Rz_um, not both")
    check_choice("smoothing_rule", smoothing_rule, tuple(SMOOTHING_FACTORS))
    if roughness_Rz_um is not None:
        if not isinstance(roughness_Rz_um, (tuple, list)) or len(roughness_Rz_um) != 2:
            raise GearoptInputError(f"roughness_Rz_um={roughness_Rz_um!r} must be (Rz_shaft, Rz_hub) in um")
        loss = roughness_smoothing_loss_um(roughness_Rz_um[0], roughness_Rz_um[1], smoothing_rule)
    else:
        loss = 0.0 if smoothing_loss_um is None else smoothing_loss_um
        check_range("smoothing_loss_um", loss, 0.0, None, unit="um")
    check_range("speed_rpm", speed_rpm, 0.0, None, unit="rpm")
    for name, v in (("shaft_density_kg_m3", shaft_density_kg_m3), ("hub_density_kg_m3", hub_density_kg_m3)):
        check_range(name, v, 0.0, None, low_inclusive=False, unit="kg/m^3")
    for name, v in (("shaft_temperature_C", shaft_temperature_C), ("hub_temperature_C", hub_temperature_C),
                    ("reference_temperature_C", reference_temperature_C)):
        check_range(name, v, ABSOLUTE_ZERO_C, 2000.0, unit="degC")
    for name, v in (("shaft_expansion_per_K", shaft_expansion_per_K), ("hub_expansion_per_K", hub_expansion_per_K)):
        check_range(name, v, 0.0, 1e-3, unit="1/K")
    check_range("axial_force_N", axial_force_N, 0.0, None, unit="N")
    for name, v in (("shaft_yield_MPa", shaft_yield_MPa), ("hub_yield_MPa", hub_yield_MPa)):
        if v is not None:
            check_range(name, v, 0.0, None, low_inclusive=False, unit="MPa")

    thermal = thermal_interference_change_um(d, shaft_temperature_C, hub_temperature_C, reference_temperature_C,
                                             shaft_expansion_per_K, hub_expansion_per_K)
    loss_per_rpm2 = centrifugal_interference_loss_um(1.0, d, di, do, shaft_E_MPa, shaft_nu, hub_E_MPa, hub_nu,
                                                     shaft_density_kg_m3, hub_density_kg_m3)
    centrifugal = loss_per_rpm2 * speed_rpm ** 2
    at_rest = interference_um - loss + thermal
    effective = at_rest - centrifugal
    p = press_fit_pressure_MPa(effective, d, di, do, shaft_E_MPa, shaft_nu, hub_E_MPa, hub_nu)

    area_mm2 = math.pi * d * l
    friction_force = friction * p * area_mm2
    torque_capacity = friction_force * d / 2000.0
    held = nm.fmax(friction_force ** 2 - axial_force_N ** 2, 0.0)
    torque_with_axial = nm.sqrt(held) * d / 2000.0

    # stresses (Lame, plane stress); centrifugal hoop stress of the free rotating hub added at its bore
    w2 = (speed_rpm * (2.0 * math.pi / 60.0)) ** 2
    a, b = 0.5 * d, 0.5 * do
    hub_centrifugal = hub_density_kg_m3 * w2 / 4.0 * ((3.0 + hub_nu) * b ** 2 + (1.0 - hub_nu) * a ** 2) \
        * _STRESS_PER_RHO_OMEGA2_MM2
    hub_hoop = p * (do ** 2 + d ** 2) / (do ** 2 - d ** 2) + hub_centrifugal
    hub_vm = von_mises_plane_MPa(hub_hoop, -p)
    shaft_hoop_surface = -p * (d ** 2 + di ** 2) / (d ** 2 - di ** 2)
    shaft_bore_hoop = -2.0 * p * d ** 2 / (d ** 2 - di ** 2)
    hollow = nm.is_symbolic(di) or nm.to_float(di) > 0.0
    shaft_vm = nm.fabs(shaft_bore_hoop) if hollow else p
    release_rpm = _release_speed_rpm(at_rest, loss_per_rpm2)

    out = {
        "smoothing_loss_um": loss,
        "thermal_interference_change_um": thermal,
        "centrifugal_interference_loss_um": centrifugal,
        "effective_interference_um": effective,
        "pressure_MPa": p,
        "friction_force_N": friction_force,
        "axial_capacity_N": friction_force,
        "torque_capacity_Nm": torque_capacity,
        "torque_capacity_with_axial_Nm": torque_with_axial,
        "release_speed_rpm": release_rpm,
        "hub_hoop_stress_MPa": hub_hoop,
        "hub_radial_stress_MPa": -p,
        "hub_von_mises_MPa": hub_vm,
        "hub_outer_hoop_stress_MPa": 2.0 * p * d ** 2 / (do ** 2 - d ** 2),
        "shaft_hoop_stress_MPa": shaft_hoop_surface,
        "shaft_radial_stress_MPa": -p,
        "shaft_von_mises_MPa": shaft_vm,
    }
    if nm.is_numeric(effective):
        lost = nm.value(effective) <= 0.0
        out["fit_lost"] = bool(lost) if isinstance(lost, (bool,)) or getattr(lost, "ndim", 0) == 0 else lost
    if hub_yield_MPa is not None:
        out["hub_yield_safety"] = _safety(hub_yield_MPa, hub_vm)
    if shaft_yield_MPa is not None:
        out["shaft_yield_safety"] = _safety(shaft_yield_MPa, shaft_vm)
    if nm.is_numeric(*[v for v in out.values() if not isinstance(v, (bool, str))]):
        check_result("press_fit", {k: v for k, v in out.items() if k not in INFINITE_OK}, {
            "shaft_diameter_mm": d, "shaft_bore_mm": di, "hub_outer_diameter_mm": do, "length_mm": l,
            "interference_um": interference_um, "speed_rpm": speed_rpm})
        check_result("press_fit", {k: out[k] for k in INFINITE_OK if k in out}, {"shaft_diameter_mm": d},
                     allow_inf=True)
    return PressFitResult(**out)


#: Outputs of :func:`press_fit` that may be ``+inf``: ``release_speed_rpm`` when the centrifugal loss never eats
#: the interference (no loss per rpm^2, e.g. a vanishing fit diameter), the yield safeties when the stress is zero.
INFINITE_OK = ("release_speed_rpm", "hub_yield_safety", "shaft_yield_safety")
ABSOLUTE_ZERO_C = -273.15


def _release_speed_rpm(at_rest_um, loss_per_rpm2_um):
    """Speed at which the centrifugal loss eats the interference at rest: sqrt(at_rest / loss per rpm^2); 0 if no
    interference is left at rest, ``inf`` (never released) when the centrifugal loss per rpm^2 is zero. Dual-typed
    (the symbolic form assumes a positive loss per rpm^2)."""
    if nm.is_numeric(at_rest_um, loss_per_rpm2_um):
        rest = np.maximum(np.asarray(nm.value(at_rest_um), dtype=float), 0.0)
        loss = np.asarray(nm.value(loss_per_rpm2_um), dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            rpm = np.where(rest <= 0.0, 0.0, np.where(loss > 0.0, np.sqrt(rest / np.where(loss > 0.0, loss, 1.0)),
                                                       np.inf))
        return float(rpm) if rpm.ndim == 0 else rpm
    return nm.sqrt(nm.fmax(at_rest_um, 0.0) / loss_per_rpm2_um)


def _safety(strength, stress):
    """strength / stress, ``inf`` for a zero stress (a margin with zero demand). Dual-typed."""
    if nm.is_numeric(strength, stress) and np.ndim(nm.value(stress)) == 0 and nm.to_float(stress) == 0.0:
        return math.inf
    return strength / stress


def shrink_fit_assembly_temperature_C(shaft_diameter_mm, max_interference_um, assembly_clearance_um=0.0,
                                      hub_expansion_per_K=11.5e-6, room_temperature_C=20.0):
    """Hub temperature [deg C] that opens the bore by the largest interference plus an assembly clearance [um]
    (shaft at room temperature): ``T_room + (delta_max + clearance) / (alpha_h d)``."""
    check_range("shaft_diameter_mm", shaft_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("max_interference_um", max_interference_um, 0.0, None, unit="um")
    return room_temperature_C + (max_interference_um + assembly_clearance_um) * 1e-3 / (
        hub_expansion_per_K * shaft_diameter_mm)


__all__ = ["press_fit", "PressFitResult", "press_fit_pressure_MPa", "lame_compliance_mm_per_MPa",
           "roughness_smoothing_loss_um", "thermal_interference_change_um", "centrifugal_interference_loss_um",
           "von_mises_plane_MPa", "shrink_fit_assembly_temperature_C", "SMOOTHING_FACTORS"]
