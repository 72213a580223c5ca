"""Taper (cone) fit of a gear hub clamped by a shaft-end nut: torque capacity by the cone-clutch analogy, dual-typed.

The thesis (sec. 3.11, after Bhandari 2010) treats the taper joint as a cone clutch: the nut preload W (thesis
Eq. 3.49, :mod:`gearopt.joints.bolt`) is the axial force on the cone of large diameter D, small diameter d and half
(semi-cone) angle theta, and friction mu on the cone surface holds the torque:

* uniform pressure (thesis Eq. 3.48; Shigley's MED cone-clutch relations)::

      T = mu W (D^3 - d^3) / (3 sin(theta) (D^2 - d^2)),     p = W / (pi/4 (D^2 - d^2))  (axial projection)

* uniform wear (p r = const; Shigley)::

      T = mu W (D + d) / (4 sin(theta)),                     p_max = 2 W / (pi d (D - d))  (at the small end)

Assumptions, stated: rigid members (the pressure distribution is *assumed*, not solved from elasticity -- the thesis
notes this overestimates, and its FEA/company code gave lower capacities); the whole nut preload reaches the cone
(no washer/face contact of the hub against a shaft shoulder); the axial force equilibrium W = N sin(theta) ignores
the friction the hub meets while it is pushed up the taper. That friction is real for a self-locking taper
(tan(theta) < mu): during tightening W = N (sin(theta) + mu cos(theta)), so the normal force that remains locked
in is smaller by sin(theta)/(sin(theta) + mu cos(theta)) (about 1/3.4 for 1:8 and mu 0.15). Both values are
returned; the thesis form is ``torque_capacity_Nm``, the engagement-friction form
``torque_capacity_engagement_friction_Nm``.

An external axial load F_a that pulls the hub off the taper (towards the nut) unloads the cone: with the rigid
model the clamp becomes W - F_a, so slip happens when ``T/T_cap + F_a/W >= 1`` (:func:`taper_slip_utilisation`);
an axial load pushing the hub onto the taper is carried by the cone and does not reduce the capacity here.

Hub stress: the hub over the taper as a thick cylinder (Lame) under the cone pressure at the mean diameter
(uniform pressure) or the small-end diameter (uniform wear, where the pressure peaks).

Units: mm, deg, N, N m, MPa. Every function accepts floats, numpy arrays or CasADi symbols.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_result
from ._checks import check_range_any as check_range
from ._record import ResultRecord
from .bolt import bolt_preload_N as _preload_from_nut_torque

THEORIES = ("uniform_pressure", "uniform_wear")


def cone_friction_radius_mm(large_diameter_mm, small_diameter_mm, theory: str = "uniform_pressure"):
    """Friction radius r_f [mm] of a cone band: uniform pressure ``(D^3-d^3)/(3(D^2-d^2))``; uniform wear
    ``(D+d)/4``; the torque is ``mu W r_f / sin(theta)``."""
    D, d = large_diameter_mm, small_diameter_mm
    if theory == "uniform_pressure":
        return (D ** 3 - d ** 3) / (3.0 * (D ** 2 - d ** 2))
    if theory == "uniform_wear":
        return 0.25 * (D + d)
    raise GearoptInputError(f"theory={theory!r} must be one of {THEORIES}")


@dataclass(frozen=True, eq=False)
class TaperFitResult(ResultRecord):
    """Capacity of a nut-clamped taper fit (:func:`taper_fit`). Values are floats, numpy arrays or CasADi
    expressions; the optional fields are ``None`` when not computed. ``to_dict()`` gives the set fields."""

    theory: str
    """``"uniform_pressure"`` (thesis Eq. 3.48) or ``"uniform_wear"``."""
    bolt_preload_N: Any
    """Nut preload W [N] (given, or from the nut torque, thesis Eq. 3.49)."""
    axial_capacity_N: Any
    """Axial load towards the nut that unloads the cone [N] (= W)."""
    torque_capacity_Nm: Any
    """Torque capacity, thesis form W = N sin(theta) [N m]."""
    torque_capacity_engagement_friction_Nm: Any
    """Torque capacity with the engagement friction, W = N (sin(theta) + mu cos(theta)) [N m]."""
    normal_force_N: Any
    """Total normal force on the cone, thesis form [N]."""
    friction_radius_mm: Any
    """Friction radius r_f of the cone band [mm]."""
    taper_length_mm: Any
    """(D - d) / (2 tan(theta)) [mm]."""
    contact_pressure_MPa: Any
    """Cone pressure [MPa]: mean (uniform pressure) or peak at the small end (uniform wear)."""
    contact_pressure_engagement_friction_MPa: Any
    """Cone pressure with the engagement friction [MPa]."""
    self_locking: Any = None
    """tan(theta) < mu (numeric half angle and friction only)."""
    hub_hoop_stress_MPa: Any = None
    """Hoop stress at the hub bore (with ``hub_outer_diameter_mm``; Lame) [MPa]."""
    hub_von_mises_MPa: Any = None
    """Von Mises stress at the hub bore (with ``hub_outer_diameter_mm``) [MPa]."""
    hub_yield_safety: Any = None
    """Hub yield strength / von Mises stress (with ``hub_yield_MPa``; ``inf`` without preload)."""


def _check_taper(D, d, theta_deg, mu):
    check_range("large_diameter_mm", D, 0.0, None, low_inclusive=False, unit="mm")
    check_range("small_diameter_mm", d, 0.0, None, low_inclusive=False, unit="mm")
    if nm.is_numeric(D, d) and nm.to_float(d) >= nm.to_float(D):
        raise GearoptInputError(f"small_diameter_mm={nm.to_float(d):g} mm must be smaller than large_diameter_mm="
                                f"{nm.to_float(D):g} mm")
    check_range("half_angle_deg", theta_deg, 0.0, 45.0, low_inclusive=False, high_inclusive=False, unit="deg")
    check_range("friction", mu, 0.0, 1.0, low_inclusive=False, high_inclusive=False)


def taper_fit(large_diameter_mm, small_diameter_mm, half_angle_deg, friction, bolt_preload_N=None,
              nut_torque_Nm=None, nut_factor=0.2, thread_diameter_mm=None, theory: str = "uniform_pressure", *,
              hub_outer_diameter_mm=None, hub_yield_MPa=None) -> TaperFitResult:
    """Torque capacity of a nut-clamped taper fit (cone-clutch analogy; see the module docstring).

    Give either ``bolt_preload_N`` W, or ``nut_torque_Nm`` with ``nut_factor`` and ``thread_diameter_mm``
    (W = T_n/(k d), thesis Eq. 3.49). ``theory``: ``"uniform_pressure"`` (thesis Eq. 3.48) or ``"uniform_wear"``.

    Returns a :class:`TaperFitResult`: ``torque_capacity_Nm`` (thesis form, W = N sin(theta)),
    ``torque_capacity_engagement_friction_Nm`` (W = N (sin(theta) + mu cos(theta))), ``bolt_preload_N``,
    ``axial_capacity_N`` (= W: the axial load towards the nut that unloads the cone), ``normal_force_N`` (total
    normal force on the cone, thesis form), ``friction_radius_mm``, ``taper_length_mm`` ((D - d)/(2 tan(theta))),
    ``contact_pressure_MPa`` (mean for uniform pressure, peak at the small end for uniform wear),
    ``contact_pressure_engagement_friction_MPa``, ``self_locking`` (tan(theta) < mu, numeric only) and, with
    ``hub_outer_diameter_mm``, ``hub_hoop_stress_MPa`` and ``hub_von_mises_MPa`` (Lame, at the bore) and with
    ``hub_yield_MPa`` the ``hub_yield_safety`` (``inf`` without preload: a margin with zero demand).

    Errors: half angle outside (0, 45) deg, friction outside (0, 1), small diameter >= large diameter, no or two
    preload inputs.
    """
    D, d, theta_deg, mu = large_diameter_mm, small_diameter_mm, half_angle_deg, friction
    _check_taper(D, d, theta_deg, mu)
    if theory not in THEORIES:
        raise GearoptInputError(f"theory={theory!r} must be one of {THEORIES}")
    if (bolt_preload_N is None) == (nut_torque_Nm is None):
        raise GearoptInputError("give exactly one of bolt_preload_N or nut_torque_Nm (with nut_factor and "
                                "thread_diameter_mm)")
    if hub_yield_MPa is not None:
        check_range("hub_yield_MPa", hub_yield_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    if hub_outer_diameter_mm is not None:
        check_range("hub_outer_diameter_mm", hub_outer_diameter_mm, 0.0, None, low_inclusive=False, unit="mm")
    if bolt_preload_N is None:
        if thread_diameter_mm is None:
            raise GearoptInputError("nut_torque_Nm needs thread_diameter_mm (nominal thread diameter of the nut)")
        W = _preload_from_nut_torque(nut_torque_Nm, nut_factor, thread_diameter_mm)
    else:
        check_range("bolt_preload_N", bolt_preload_N, 0.0, None, unit="N")
        W = bolt_preload_N
    theta = theta_deg * math.pi / 180.0
    s, c = nm.sin(theta), nm.cos(theta)
    r_f = cone_friction_radius_mm(D, d, theory)
    torque = mu * W * r_f / s * 1e-3
    engaged = s / (s + mu * c)  # locked-in normal force / thesis normal force
    if theory == "uniform_pressure":
        p = W / (0.25 * math.pi * (D ** 2 - d ** 2))
        d_hub = 0.5 * (D + d)
    else:
        p = 2.0 * W / (math.pi * d * (D - d))
        d_hub = d
    out = {
        "theory": theory,
        "bolt_preload_N": W,
        "axial_capacity_N": W,
        "torque_capacity_Nm": torque,
        "torque_capacity_engagement_friction_Nm": torque * engaged,
        "normal_force_N": W / s,
        "friction_radius_mm": r_f,
        "taper_length_mm": (D - d) / (2.0 * nm.tan(theta)),
        "contact_pressure_MPa": p,
        "contact_pressure_engagement_friction_MPa": p * engaged,
    }
    if nm.is_numeric(theta_deg, mu):
        out["self_locking"] = bool(math.tan(nm.to_float(theta)) < nm.to_float(mu))
    if hub_outer_diameter_mm is not None:
        if nm.is_numeric(hub_outer_diameter_mm, D) and nm.to_float(hub_outer_diameter_mm) <= nm.to_float(D):
            raise GearoptInputError(f"hub_outer_diameter_mm={nm.to_float(hub_outer_diameter_mm):g} mm must exceed "
                                    f"large_diameter_mm={nm.to_float(D):g} mm")
        Do = hub_outer_diameter_mm
        hoop = p * (Do ** 2 + d_hub ** 2) / (Do ** 2 - d_hub ** 2)
        vm = nm.sqrt(hoop ** 2 + hoop * p + p ** 2)
        out["hub_hoop_stress_MPa"] = hoop
        out["hub_von_mises_MPa"] = vm
        if hub_yield_MPa is not None:
            out["hub_yield_safety"] = hub_yield_MPa / vm if not _is_zero(vm) else math.inf
    numbers = {k: v for k, v in out.items() if not isinstance(v, (bool, str))}
    if nm.is_numeric(*numbers.values()):
        check_result("taper_fit", {k: v for k, v in numbers.items() if k != "hub_yield_safety"},
                     {"large_diameter_mm": D, "small_diameter_mm": d, "half_angle_deg": theta_deg, "friction": mu,
                      "bolt_preload_N": bolt_preload_N, "nut_torque_Nm": nut_torque_Nm})
    return TaperFitResult(**out)


def _is_zero(x) -> bool:
    return nm.is_numeric(x) and np.ndim(nm.value(x)) == 0 and nm.to_float(x) == 0.0


def taper_slip_utilisation(torque_Nm, axial_force_off_N, torque_capacity_Nm, bolt_preload_N):
    """Slip utilisation of a taper joint under torque and an axial load pulling the hub off the taper [-]:
    ``|T|/T_cap + max(F_a, 0)/W`` (rigid cone-clutch model: the axial load unloads the clamp linearly). <= 1 holds."""
    return nm.fabs(torque_Nm) / torque_capacity_Nm + nm.fmax(axial_force_off_N, 0.0) / bolt_preload_N


__all__ = ["taper_fit", "TaperFitResult", "cone_friction_radius_mm", "taper_slip_utilisation", "THEORIES"]
