"""Exact slider-crank kinematics (zero piston-pin offset) and the reciprocating-mass inertia of one cylinder.

Crank angle ``theta`` is measured from the cylinder's top dead centre (TDC) in the direction of rotation; the piston
displacement ``s`` is measured from TDC towards bottom dead centre (BDC), so ``s(0) = 0`` and ``s(pi) = 2 r`` (the
stroke). With ``lambda = r / l`` (crank radius over connecting-rod length, ``0 < lambda < 1``):

    s(theta)   = r (1 - cos theta) + l (1 - sqrt(1 - lambda^2 sin^2 theta))
    s'(theta)  = r [sin theta + lambda sin theta cos theta / sqrt(1 - lambda^2 sin^2 theta)]
    s''(theta) = r [cos theta + lambda (cos 2 theta + lambda^2 sin^4 theta) / (1 - lambda^2 sin^2 theta)^(3/2)]

(derivatives with respect to the crank angle in rad). These are exact: they replace the thesis' garbled Eq. 3.20/3.21
(docs/source-study.md sec. 2; docs/default-data.md sec. 2.4). The connecting-rod angle is ``beta = asin(lambda sin theta)`` and
``s' = r sin(theta + beta) / cos(beta)`` (the classical force-transmission identity, tested).

Every function is dual-typed (floats, numpy arrays, CasADi SX/MX) through :mod:`gearopt.numerics` and is smooth
(C-infinity) in the angle for ``lambda < 1``.
"""

from __future__ import annotations

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import as_number, check_range


def check_values(name: str, value, low: float | None = None, high: float | None = None, *,
                 low_inclusive: bool = True, high_inclusive: bool = True, unit: str = "") -> None:
    """:func:`gearopt.validation.check_range` for scalars *and* numeric arrays (the worst element is reported).

    Symbolic CasADi values are not checked (the caller owns them as NLP constraints or integrator states).
    """
    if nm.is_symbolic(value):
        return
    if isinstance(value, (tuple, list)):  # arithmetic on a tuple fails later: arrays must be numpy arrays
        raise GearoptInputError(f"{name}={value!r:.80} must be a number or a numpy array, not a {type(value).__name__}")
    if not isinstance(value, np.ndarray) and not nm.is_casadi(value):
        as_number(name, value)  # rejects strings, bools and None by name
    elif isinstance(value, np.ndarray) and value.dtype.kind not in "iuf":
        raise GearoptInputError(f"{name} must be an array of real numbers (dtype {value.dtype})")
    try:
        arr = np.asarray(nm.value(value), dtype=float).reshape(-1)
    except (TypeError, ValueError, RuntimeError):
        raise GearoptInputError(f"{name}={value!r} is not a number") from None
    if arr.size == 0:
        return
    if np.any(~np.isfinite(arr)):
        bad = arr[~np.isfinite(arr)][0]
        raise GearoptInputError(f"{name}={bad!r} is not finite")
    for v in (arr.min(), arr.max()):
        check_range(name, float(v), low, high, low_inclusive=low_inclusive, high_inclusive=high_inclusive, unit=unit)


def check_crank_geometry(crank_radius_mm, rod_length_mm) -> None:
    """Raise :class:`GearoptInputError` unless ``crank_radius_mm > 0`` and ``rod_length_mm > crank_radius_mm``."""
    check_values("crank_radius_mm", crank_radius_mm, 0.0, low_inclusive=False, unit="mm")
    check_values("rod_length_mm", rod_length_mm, 0.0, low_inclusive=False, unit="mm")
    if nm.is_numeric(crank_radius_mm, rod_length_mm):
        r = np.asarray(nm.value(crank_radius_mm), dtype=float)
        lr = np.asarray(nm.value(rod_length_mm), dtype=float)
        if np.any(lr <= r):
            raise GearoptInputError(
                f"rod_length_mm={float(np.min(lr)):g} mm is below its limit: must be > crank_radius_mm="
                f"{float(np.max(r)):g} mm (a connecting rod shorter than the crank radius cannot follow the crank)")


def slider_crank(crank_angle_rad, crank_radius_mm, rod_length_mm) -> dict:
    """Exact slider-crank kinematics with zero pin offset (docs/default-data.md sec. 2.4; docs/source-study.md sec. 2).

    Args:
        crank_angle_rad: crank angle from this cylinder's TDC [rad], any real value (2 pi periodic).
        crank_radius_mm: crank radius r = stroke / 2 [mm], > 0.
        rod_length_mm: connecting-rod centre distance l [mm], > r.

    Returns:
        dict with ``piston_displacement_mm`` (s from TDC [mm]), ``ds_dtheta_mm`` (s' [mm/rad]),
        ``d2s_dtheta2_mm`` (s'' [mm/rad^2]), ``rod_angle_rad`` (beta = asin(lambda sin theta) [rad]) and
        ``crank_rod_ratio`` (lambda = r / l [-]); each of the same type as the angle.

    Validity: any angle; 0 < r < l (raises :class:`GearoptInputError` otherwise).
    """
    check_crank_geometry(crank_radius_mm, rod_length_mm)
    return slider_crank_from_sincos(nm.sin(crank_angle_rad), nm.cos(crank_angle_rad), crank_radius_mm,
                                    rod_length_mm)


def slider_crank_from_sincos(sin_theta, cos_theta, crank_radius_mm, rod_length_mm) -> dict:
    """:func:`slider_crank` from ``sin(theta)`` and ``cos(theta)`` (lets callers rotate one sin/cos pair to several
    cylinders' angles instead of calling ``sin``/``cos`` per cylinder). Geometry is not re-checked here."""
    r = crank_radius_mm
    lam = crank_radius_mm / rod_length_mm
    st, ct = sin_theta, cos_theta
    s2 = st * st
    u = 1.0 - lam * lam * s2                      # 1 - lambda^2 sin^2 theta  >= 1 - lambda^2 > 0
    root = nm.sqrt(u)
    s = r * (1.0 - ct) + rod_length_mm * (1.0 - root)
    ds = r * (st + lam * st * ct / root)
    d2s = r * (ct + lam * ((ct * ct - s2) + lam * lam * s2 * s2) / (u * root))
    return {"piston_displacement_mm": s, "ds_dtheta_mm": ds, "d2s_dtheta2_mm": d2s,
            "rod_angle_rad": nm.asin(lam * st), "crank_rod_ratio": lam}


def reciprocating_inertia_kgm2(crank_angle_rad, crank_radius_mm, rod_length_mm, reciprocating_mass_kg):
    """Angle-dependent inertia ``m s'(theta)^2`` [kg m^2] of one cylinder's reciprocating mass about the crank axis.

    The reciprocating-mass torque on the crank is ``T_i = -m s'^2 theta'' - m s' s'' theta'^2``
    (Lagrange with kinetic energy ``m (s' theta')^2 / 2``). A torsional model may either pass the crank acceleration
    to :func:`gearopt.engine.excitation.crank_torque` or, to avoid an algebraic loop, add this inertia to the throw's
    inertia and keep only the velocity term (``crank_acceleration_rad_s2 = 0``). Dual-typed; mean over a revolution
    is about ``m r^2 (1/2 + lambda^2/8)``.
    """
    check_values("reciprocating_mass_kg", reciprocating_mass_kg, 0.0, unit="kg")
    ds_m = slider_crank(crank_angle_rad, crank_radius_mm, rod_length_mm)["ds_dtheta_mm"] * 1e-3
    return reciprocating_mass_kg * ds_m * ds_m


__all__ = ["check_crank_geometry", "check_values", "reciprocating_inertia_kgm2", "slider_crank", "slider_crank_from_sincos"]
