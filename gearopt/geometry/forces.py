"""Force and torque relations of a cylindrical gear mesh (ISO 21771:2007), dual-typed: the one home of the axial
(thrust) force of a helical mesh and of the conversions between a mesh force and the torque it exerts on a gear.

Units: forces N, torques N m, diameters and radii mm, angles deg. Every function accepts floats, numpy arrays and
CasADi symbols (:mod:`gearopt.numerics`) and keeps the sign of its force or torque argument.

Axial force of a helical mesh. The tooth force is normal to the flank, hence to the helix the flank contains on every
coaxial cylinder ``y``: its axial and tangential parts there satisfy ``F_a = F_ty tan(beta_y)`` with the transverse
tangential force ``F_ty = 2000 T / d_y`` and the helix angle ``tan(beta_y) = tan(beta) d_y / d`` on that cylinder
(ISO 21771 eq. 14). The product does not depend on the cylinder:

    F_a = F_t tan(beta) = F_tw tan(beta_w) = F_bt tan(beta_b) = 2000 T tan(beta) / d

at the reference circle (F_t = 2000 T/d, beta), the working pitch circle (F_tw = 2000 T/d_w, beta_w) and the base
circle (the force along the transverse line of action F_bt = F_t / cos(alpha_t) with tan(beta_b) = tan(beta)
cos(alpha_t): eq. 14 at d_y = d_b = d cos(alpha_t)). :func:`axial_force_N` takes any matching pair (F, beta); the
tests check the identity.
"""

from __future__ import annotations

from .. import numerics as nm
from ..units import RAD_PER_DEG


def axial_force_N(force_N, helix_angle_deg):
    """Axial (thrust) force of a helical mesh [N]: ``F_a = F tan(beta)`` (ISO 21771 force components).

    ``force_N`` [N] and ``helix_angle_deg`` [deg] must belong to the same cylinder: the transverse tangential force
    and helix angle at the reference circle (F_t, beta) or the working pitch circle (F_tw, beta_w), or the force
    along the transverse line of action and the base helix angle (F_bt, beta_b) -- all give the same thrust (module
    docstring). Signed like ``force_N`` (the thrust reverses with the loaded flank); 0 for a spur mesh. Dual-typed.
    """
    return force_N * nm.tan(helix_angle_deg * RAD_PER_DEG)


def tangential_force_N(torque_Nm, diameter_mm):
    """Transverse tangential force of a mesh at diameter d [N]: ``F_t = 2000 T / d`` (ISO 6336-1, ISO 21771), with
    ``torque_Nm`` T [N m] on the gear and ``diameter_mm`` d [mm] (reference circle for the nominal F_t of ISO 6336,
    working pitch circle for the force transmitted between the gears, base circle for F_bt). Inverse of
    :func:`mesh_torque_Nm` (``mesh_torque_Nm(tangential_force_N(T, d), d / 2) == T``). Dual-typed."""
    return 2000.0 * torque_Nm / diameter_mm


def mesh_torque_Nm(force_N, radius_mm):
    """Torque [N m] a mesh force exerts on a gear: ``T = F r`` with ``force_N`` F [N] acting tangentially at
    ``radius_mm`` r [mm] (the base radius for the force along the line of action of a dynamics model, the pitch
    radius for a tangential force). Inverse of :func:`tangential_force_N` with ``d = 2 r``. Dual-typed."""
    return force_N * (radius_mm * 1e-3)


def mesh_axial_force_N(torque_Nm, diameter_mm, helix_angle_deg):
    """Axial force of a helical mesh on a gear from its torque [N]: ``F_t tan(beta) = 2000 T tan(beta) / d``
    (:func:`axial_force_N` of :func:`tangential_force_N`), with the torque on that gear [N m] and a matching pair
    (d [mm], beta [deg]): reference or working pitch circle. Dual-typed."""
    return axial_force_N(tangential_force_N(torque_Nm, diameter_mm), helix_angle_deg)


__all__ = ["axial_force_N", "tangential_force_N", "mesh_torque_Nm", "mesh_axial_force_N"]
