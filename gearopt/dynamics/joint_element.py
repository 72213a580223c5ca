"""The friction element of a press-fitted, keyed gear on its shaft: its data (:class:`FrictionJoint`) and its
dual-typed laws -- the viscoplastic Coulomb slip on a combined capacity, the key and shoulder stops and the gear's
axial motion on the interface layer. The model, its assumptions and definitions are described in
:mod:`gearopt.dynamics.joint_friction`, which integrates these laws with the torsional network.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_range

#: Floor of |D| [N] in the slip direction D/|D| (keeps the direction finite at zero demand; no effect on slip,
#: which needs |D| > C > 0).
DEMAND_FLOOR_N = 1e-3
#: Slip speed [m/s] above which the stuck layer's dashpot is faded out (its force stays below c_c x this, about
#: 100 N for the default gears, far below any capacity).
STICK_DAMPING_FADE_M_S = 1e-3


@dataclass(frozen=True)
class FrictionJoint:
    """A press-fitted gear on its shaft as a friction element (module docstring).

    ``name``; ``gear_node`` the network node carrying the gear; ``fit_diameter_mm`` d; ``capacity_N`` friction
    capacity C = mu p pi d l (default of the integration parameter ``<name>.capacity_N``); ``thrust_signs``
    ((mesh, sign), ...): off-nose axial force on the gear = sum sign x the mesh's axial force output (0 for a spur
    mesh); ``gear_inertia_kgm2`` J_g of the gear (its inertia torque is taken out of the mesh-torque sum; the whole
    node's inertia when the gear is its own node); ``key_clearance_um`` c per side (arc at the fit radius; None = no
    key); ``key_stiffness_N_per_m``; ``shoulder_stiffness_N_per_m``; ``slip_speed_m_s`` V (the
    regularisation: slip speed at 100 % overstress); ``thrust_scale`` multiplies the thrust (1; e.g.
    the ratio of tan(beta) of a lower helix angle, an approximation that keeps the dynamics of the present train;
    negative: the shaft shoulder on the other side of the gear, so that the thrust that pushed the gear off the nose
    now presses it onto the shoulder and vice versa);
    ``gear_mass_kg`` m of the gear in its axial motion; ``interface_stiffness_N_per_m`` k_c the axial (tangential)
    stiffness of the fit interface before it slips and ``interface_damping_ratio`` zeta_c of the gear's mass on it
    (module docstring, "Axial inertia").
    """

    name: str
    gear_node: str
    fit_diameter_mm: float
    capacity_N: float
    thrust_signs: tuple
    gear_inertia_kgm2: float
    key_clearance_um: float | None = 10.0
    key_stiffness_N_per_m: float = 1.0e9
    shoulder_stiffness_N_per_m: float = 5.0e9
    slip_speed_m_s: float = 10.0
    thrust_scale: float = 1.0
    gear_mass_kg: float = 2.0
    interface_stiffness_N_per_m: float = 1.0e9
    interface_damping_ratio: float = 1.0

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise GearoptInputError(f"joint name={self.name!r} must be a non-empty string")
        check_range(f"fit_diameter_mm of {self.name!r}", self.fit_diameter_mm, 0.0, None, low_inclusive=False,
                    unit="mm")
        check_range(f"capacity_N of {self.name!r}", self.capacity_N, 0.0, None, low_inclusive=False, unit="N")
        check_range(f"gear_inertia_kgm2 of {self.name!r}", self.gear_inertia_kgm2, 0.0, None, unit="kg m^2")
        if self.key_clearance_um is not None:
            check_range(f"key_clearance_um of {self.name!r}", self.key_clearance_um, 0.0, None, unit="um")
        check_range(f"key_stiffness_N_per_m of {self.name!r}", self.key_stiffness_N_per_m, 0.0, None,
                    low_inclusive=False, unit="N/m")
        check_range(f"shoulder_stiffness_N_per_m of {self.name!r}", self.shoulder_stiffness_N_per_m, 0.0, None,
                    low_inclusive=False, unit="N/m")
        check_range(f"slip_speed_m_s of {self.name!r}", self.slip_speed_m_s, 0.0, None,
                    low_inclusive=False, unit="m/s")
        check_range(f"thrust_scale of {self.name!r}", self.thrust_scale, None, None, unit="-")
        check_range(f"gear_mass_kg of {self.name!r}", self.gear_mass_kg, 0.0, None, low_inclusive=False, unit="kg")
        check_range(f"interface_stiffness_N_per_m of {self.name!r}", self.interface_stiffness_N_per_m, 0.0, None,
                    low_inclusive=False, unit="N/m")
        check_range(f"interface_damping_ratio of {self.name!r}", self.interface_damping_ratio, 0.0, None,
                    low_inclusive=False, unit="-")
        for mesh, sign in self.thrust_signs:
            if sign not in (-1.0, 0.0, 1.0, -1, 0, 1):
                raise GearoptInputError(f"thrust sign of mesh {mesh!r} in joint {self.name!r} is {sign!r}; must be "
                                        f"-1, 0 or +1")

    def parameters(self) -> dict[str, float]:
        """Default values of the joint's integration parameters (names ``<joint>.<key>``)."""
        return {f"{self.name}.capacity_N": float(self.capacity_N),
                f"{self.name}.key_clearance_um": float(self.key_clearance_um or 0.0),
                f"{self.name}.slip_speed_m_s": float(self.slip_speed_m_s),
                f"{self.name}.thrust_scale": float(self.thrust_scale)}


# ----------------------------------------------------------------------------------------------------------------
# element laws (dual-typed)
# ----------------------------------------------------------------------------------------------------------------

def slip_rates_m_s(demand_tangential_N, demand_axial_N, capacity_N, slip_speed_m_s):
    """Viscoplastic Coulomb slip velocity (v_t, v_a) [m/s]: ``V <|D|/C - 1>_+`` along ``D/|D|`` (module
    docstring; ``V`` = ``slip_speed_m_s``, the slip speed at 100 % overstress). Exactly zero inside the capacity
    circle."""
    mag = nm.sqrt(demand_tangential_N ** 2 + demand_axial_N ** 2 + DEMAND_FLOOR_N ** 2)
    speed = slip_speed_m_s * nm.fmax(mag / capacity_N - 1.0, 0.0)
    return speed * demand_tangential_N / mag, speed * demand_axial_N / mag


def key_force_N(slip_m, clearance_m, stiffness_N_per_m):
    """Force of the key on the hub against its circumferential slip [N] (+ when ``slip > c``): a symmetric dead
    zone of half-width ``c``, linear beyond."""
    return stiffness_N_per_m * (nm.fmax(slip_m - clearance_m, 0.0) - nm.fmax(-slip_m - clearance_m, 0.0))


def shoulder_force_N(axial_position_m, stiffness_N_per_m):
    """Reaction of the shaft shoulder on the gear [N] (+ = off the nose): one-sided, acts only at ``u_a < 0``."""
    return stiffness_N_per_m * nm.fmax(-axial_position_m, 0.0)


def joint_rates(joint: FrictionJoint, joint_torque_Nm, thrust_N, slip_m, axial_slip_m, axial_position_m,
                axial_velocity_m_s, capacity_N, key_clearance_m, slip_speed_m_s):
    """Slip rates and forces of ``joint`` at its state (dual-typed; module docstring, "Axial inertia").

    Returns a dict: ``demand_tangential_N`` D_t = T/r - F_key, ``demand_axial_N`` the interface's elastic axial
    force k_c (u_a - z), ``key_force_N``, ``shoulder_force_N``, ``slip_rate_m_s`` du_t/dt, ``axial_slip_rate_m_s``
    dz/dt, ``axial_acceleration_m_s2`` d2u_a/dt2."""
    r = 0.5e-3 * joint.fit_diameter_mm
    if joint.key_clearance_um is None:
        f_key = 0.0 * slip_m
    else:
        f_key = key_force_N(slip_m, key_clearance_m, joint.key_stiffness_N_per_m)
    f_sh = shoulder_force_N(axial_position_m, joint.shoulder_stiffness_N_per_m)
    k_c, m = joint.interface_stiffness_N_per_m, joint.gear_mass_kg
    d_t = joint_torque_Nm / r - f_key
    d_a = k_c * (axial_position_m - axial_slip_m)
    v_t, v_z = slip_rates_m_s(d_t, d_a, capacity_N, slip_speed_m_s)
    c_c = 2.0 * joint.interface_damping_ratio * math.sqrt(k_c * m)
    # the dashpot damps the stuck layer only: it fades out (Lipschitz ramp) as the slip speed reaches
    # STICK_DAMPING_FADE_M_S, so it never adds to the force a slipping interface carries (that is its capacity)
    stick = nm.fmax(1.0 - nm.sqrt(v_t ** 2 + v_z ** 2 + 1e-18) / STICK_DAMPING_FADE_M_S, 0.0)
    f_interface = d_a + stick * c_c * (axial_velocity_m_s - v_z)
    return {"demand_tangential_N": d_t, "demand_axial_N": d_a, "key_force_N": f_key, "shoulder_force_N": f_sh,
            "slip_rate_m_s": v_t, "axial_slip_rate_m_s": v_z,
            "axial_acceleration_m_s2": (thrust_N + f_sh - f_interface) / m}


__all__ = ["DEMAND_FLOOR_N", "STICK_DAMPING_FADE_M_S", "FrictionJoint", "joint_rates", "key_force_N",
           "shoulder_force_N", "slip_rates_m_s"]
