"""Blok flash temperature of gear teeth and the contact temperature, dual-typed and vectorised.

Blok's flash temperature (Blok 1937; ISO/TR 13989-1, AGMA 925-A03 in the form of docs/default-data.md sec. 3) for a
semi-elliptical (Hertzian) frictional heat source of half-width b_H moving over both surfaces at high Peclet
number::

    theta_fl = 1.11 mu w |v1 - v2| / ( sqrt(2 b_H) (B_M1 sqrt(v1) + B_M2 sqrt(v2)) )

with w the normal load per unit face width, v_i = omega_i rho_i the rolling (tangential) speeds of the flanks, mu the
friction coefficient and B_M = sqrt(lambda rho c) the thermal contact coefficients (Blok's partition: the heat
splits so that both surfaces reach the same maximum temperature). For one material 1.11/sqrt(2) |v1 - v2| /
(sqrt(v1) + sqrt(v2)) = 0.785 |sqrt(v1) - sqrt(v2)| (AGMA 925 rounds 0.785 to 0.80). The constant follows from
1-D transient conduction into each surface: 2 max_xi int_{-1}^{xi} sqrt(1 - s^2)/sqrt(xi - s) ds / pi^1.5 = 0.7860
= 1.1115/sqrt(2) (tested by quadrature).

Units (docs/default-data.md sec. 3): w [N/mm], b_H [mm], v [m/s], B_M [N/(mm s^0.5 K)] -> the SI formula times
sqrt(1000). theta [K]; temperatures [C].

Smoothness for NLPs: |v1 - v2| has a kink at the pitch point (pure rolling). The default is the exact ``fabs``
(derivative 0 at exactly zero sliding); pass ``sliding_smoothing_m_s`` = w_s to use ``numerics.smooth_abs`` with
that width (error at most w_s ln 2 in |v1 - v2|, only near the pitch point; e.g. 0.01 m/s changes theta by
< 0.01 K for the default train). sqrt(v_i) is guarded by a floor of 1e-9 m/s (rolling speeds are positive on the
active flank; the floor only keeps derivatives finite at the base circle).

Validity: Peclet numbers v b_H / (2 k) >> 1 (k = lambda/(rho c) thermal diffusivity; ~ 10-100 for these gears),
Hertzian line contact, constant friction. Helical pairs are evaluated in the transverse section (one slice).
"""

from __future__ import annotations

import math

from .. import numerics as nm
from .hertz import plane_strain_compliance_per_MPa
from ..errors import GearoptInputError
from ..validation import check_range
from ..units import RAD_PER_DEG, rpm2rad_per_s
from .lubrication import DEFAULT_OIL_TEMPERATURE_C
from .materials import material_pair
from .root_stress import _check_array

#: Blok's constant for a semi-elliptical heat source (Blok 1937; ISO/TR 13989-1).
BLOK_CONSTANT = 1.11
#: sqrt(1000): the formula in w [N/mm], b_H [mm], B_M [N/(mm s^0.5 K)], v [m/s] (docs/default-data.md sec. 3).
_UNIT_FACTOR = math.sqrt(1000.0)
_SPEED_FLOOR_M_S = 1e-9


#: Library default mean tooth friction coefficient (Blok): [E] docs/default-data.md sec. 3 flash-temperature example
#: (mineral engine oil, ground flanks). A library default, not read from any data file: a caller with a system passes
#: its own (``friction=system.lubrication.mean_friction_coefficient``). Equal to the packaged default_train.toml's
#: ``[lubrication] mean_friction_coefficient`` (tests/rating/test_library_defaults.py keeps them equal).
DEFAULT_FRICTION_COEFFICIENT = 0.06


def flash_temperature_blok_K(load_N_per_mm, half_width_mm, v1_m_s, v2_m_s, friction, B_M1, B_M2=None, *,
                             sliding_smoothing_m_s=None):
    """Blok flash temperature theta_fl [K] of a line contact (see the module docstring), dual-typed and vectorised.

    Args: ``load_N_per_mm`` w >= 0 [N/mm] (the load on this contact, i.e. already times the load-sharing factor);
    ``half_width_mm`` b_H > 0 [mm]; ``v1_m_s``, ``v2_m_s`` rolling speeds >= 0 [m/s]; ``friction`` mu in [0, 1);
    ``B_M1``, ``B_M2`` thermal contact coefficients > 0 [N/(mm s^0.5 K)] (``B_M2=None``: same as B_M1);
    ``sliding_smoothing_m_s``: None for the exact |v1 - v2|, or a width [m/s] for ``numerics.smooth_abs``.
    """
    if B_M2 is None:
        B_M2 = B_M1
    for name, val, low, high in (("load_N_per_mm", load_N_per_mm, 0.0, math.inf),
                                 ("v1_m_s", v1_m_s, 0.0, math.inf), ("v2_m_s", v2_m_s, 0.0, math.inf)):
        _check_array(name, val, low, high, {"load_N_per_mm": "N/mm"}.get(name, "m/s"))
    _check_array("half_width_mm", half_width_mm, 1e-300, math.inf, "mm")
    check_range("friction", friction, 0.0, 1.0, high_inclusive=False)
    check_range("B_M1", B_M1, 0.0, None, low_inclusive=False, unit="N/(mm s^0.5 K)")
    check_range("B_M2", B_M2, 0.0, None, low_inclusive=False, unit="N/(mm s^0.5 K)")
    dv = v1_m_s - v2_m_s
    sliding = nm.fabs(dv) if sliding_smoothing_m_s is None else nm.smooth_abs(dv, sliding_smoothing_m_s)
    denominator = nm.sqrt(2.0 * half_width_mm) * (B_M1 * nm.sqrt_safe(v1_m_s, _SPEED_FLOOR_M_S)
                                                  + B_M2 * nm.sqrt_safe(v2_m_s, _SPEED_FLOOR_M_S))
    return _UNIT_FACTOR * BLOK_CONSTANT * friction * load_N_per_mm * sliding / denominator


def contact_temperature_C(bulk_temperature_C, flash_temperature_K):
    """Contact temperature theta_B = theta_M + theta_fl [C]: bulk (body) temperature [C] plus flash rise [K]."""
    return bulk_temperature_C + flash_temperature_K


def _speeds_rad_s(pair, speed_rpm, speed_gear: int):
    if speed_gear not in (1, 2):
        raise GearoptInputError(f"speed_gear={speed_gear!r} must be 1 or 2")
    check_range("speed_rpm", speed_rpm, 0.0, None, unit="rpm")
    z1, z2 = pair.teeth
    w = rpm2rad_per_s(speed_rpm)
    return (w, w * z1 / z2) if speed_gear == 1 else (w * z2 / z1, w)


def _path_length_mm(g):
    return g["centre_distance_mm"] * nm.sin(g["working_pressure_angle_deg"] * RAD_PER_DEG)


def rolling_velocities_m_s(pair, speed_rpm, roll_length_mm, *, speed_gear: int = 1):
    """Rolling (tangential) speeds of both flanks at a contact point, v_i = omega_i rho_i [m/s] (transverse section).

    ``speed_rpm``: speed of gear ``speed_gear`` (1 or 2) [rpm]; ``roll_length_mm``: the contact's roll length on
    gear 1, rho_1 [mm] (gear 2: rho_2 = T1T2 - rho_1). Returns (v1, v2); dual-typed, vectorised over roll lengths.
    """
    g = pair.geometry()
    w1, w2 = _speeds_rad_s(pair, speed_rpm, speed_gear)
    rho2 = _path_length_mm(g) - roll_length_mm
    return w1 * roll_length_mm * 1e-3, w2 * rho2 * 1e-3


def sliding_velocity_m_s(pair, speed_rpm, roll_length_mm, *, speed_gear: int = 1):
    """Sliding velocity v1 - v2 [m/s] at a contact point (signed: > 0 where gear 1's flank is faster, i.e. on gear 1's
    addendum). Equals (omega1 + omega2)(rho_1 - rho_C) with rho_C the pitch point's roll length. Args as
    :func:`rolling_velocities_m_s`."""
    v1, v2 = rolling_velocities_m_s(pair, speed_rpm, roll_length_mm, speed_gear=speed_gear)
    return v1 - v2


def flash_temperature_pair_K(pair, torque_Nm, speed_rpm, roll_length_mm, *, driving_gear: int = 1,
                             speed_gear: int = 1, friction=None, load_share=1.0, material="20MnCr5",
                             bulk_temperature_C=None, sliding_smoothing_m_s=None, parts: bool = False):
    """Blok flash temperature [K] of a gear pair at contact point(s) on its path, dual-typed and vectorised.

    Args:
        pair: :class:`~gearopt.geometry.pair.GearPair`.
        torque_Nm: torque [N m] > 0 on gear ``driving_gear`` (1 or 2); normal load w = load_share T/(r_b b),
            b = min(b1, b2).
        speed_rpm: speed of gear ``speed_gear`` [rpm].
        roll_length_mm: contact point(s) as roll length on gear 1 [mm] (scalar, array or CasADi).
        friction: mean friction coefficient (default :data:`DEFAULT_FRICTION_COEFFICIENT`, 0.06, an [E] library
            default; pass ``system.lubrication.mean_friction_coefficient`` for a system's own).
        load_share: X_Gamma, the fraction of the load on this tooth pair (1 single contact; ~0.5 in double contact).
        material: name/Material or 2-tuple: E, nu (Hertz half-width) and B_M of each gear.
        bulk_temperature_C: bulk temperature theta_M [C] for the contact temperature (default
            :data:`~gearopt.rating.lubrication.DEFAULT_OIL_TEMPERATURE_C`, 100 C, an [E] library default oil
            temperature, a lower bound of the bulk temperature; pass ``system.lubrication.oil_temperature_C`` for a
            system's own).
        sliding_smoothing_m_s: see :func:`flash_temperature_blok_K`.
        parts: return a dict instead of theta_fl alone.

    Returns theta_fl [K]; with ``parts`` a dict: ``flash_temperature_K``, ``contact_temperature_C``,
    ``half_width_mm`` (b_H = sqrt(8 w rho_red / (pi E_r)), E_r = 2/[(1-nu1^2)/E1 + (1-nu2^2)/E2]),
    ``load_N_per_mm``, ``v1_m_s``, ``v2_m_s``, ``sliding_velocity_m_s``, ``radii_mm`` (rho_1, rho_2).
    """
    if driving_gear not in (1, 2):
        raise GearoptInputError(f"driving_gear={driving_gear!r} must be 1 or 2")
    check_range("torque_Nm", torque_Nm, 0.0, None, low_inclusive=False, unit="N m")
    check_range("load_share", load_share, 0.0, 1.0, low_inclusive=False)
    mu = DEFAULT_FRICTION_COEFFICIENT if friction is None else friction
    m1, m2 = material_pair(material)
    g = pair.geometry()
    t1t2 = _path_length_mm(g)
    _check_array("roll_length_mm", roll_length_mm, 0.0, nm.to_float(t1t2) if nm.is_numeric(t1t2) else math.inf,
                 "mm")
    rho1, rho2 = roll_length_mm, t1t2 - roll_length_mm
    b = nm.fmin(g["face_width_mm"][0], g["face_width_mm"][1])
    w = load_share * torque_Nm * 1000.0 / (0.5 * g["base_diameter_mm"][driving_gear - 1]) / b
    compliance = plane_strain_compliance_per_MPa(m1.E_MPa, m1.poisson_ratio) \
        + plane_strain_compliance_per_MPa(m2.E_MPa, m2.poisson_ratio)
    # Hertz half-width (as contact.tip_relief.hertz_half_width_mm, written for arrays): sqrt(2w/pi c / (1/(2 rho)...))
    half_width = nm.sqrt(2.0 * w / math.pi * compliance / (0.5 / rho1 + 0.5 / rho2))
    v1, v2 = rolling_velocities_m_s(pair, speed_rpm, rho1, speed_gear=speed_gear)
    theta = flash_temperature_blok_K(w, half_width, v1, v2, mu, m1.thermal_contact_coefficient_N_per_mm_sqrt_s_K,
                                     m2.thermal_contact_coefficient_N_per_mm_sqrt_s_K,
                                     sliding_smoothing_m_s=sliding_smoothing_m_s)
    if not parts:
        return theta
    bulk = DEFAULT_OIL_TEMPERATURE_C if bulk_temperature_C is None else bulk_temperature_C
    return {"flash_temperature_K": theta, "contact_temperature_C": contact_temperature_C(bulk, theta),
            "half_width_mm": half_width, "load_N_per_mm": w, "v1_m_s": v1, "v2_m_s": v2,
            "sliding_velocity_m_s": v1 - v2, "radii_mm": (rho1, rho2), "friction": mu}


__all__ = ["BLOK_CONSTANT", "DEFAULT_FRICTION_COEFFICIENT", "flash_temperature_blok_K", "contact_temperature_C",
           "rolling_velocities_m_s", "sliding_velocity_m_s", "flash_temperature_pair_K"]
