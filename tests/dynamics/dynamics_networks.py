"""Small torsional networks shared by the dynamics tests (not a test module)."""

import math

from gearopt import numerics as nm
from gearopt.dynamics import TorsionalNetwork

R1, R2, J1, J2, K_MESH = 0.040, 0.080, 0.01, 0.04, 4e8
M_EQ = 1.0 / (R1 ** 2 / J1 + R2 ** 2 / J2)          # 3.125 kg
W_MESH = math.sqrt(K_MESH / M_EQ)                   # mesh mode [rad/s], 1800 Hz


def forced_pair(mean_Nm=100.0, ripple_Nm=50.0, damping=True, shape=None, backlash_mm=0.1):
    """Speed-controlled drive -> shaft -> g1 = mesh = g2 -> shaft -> load with a load torque over the nominal
    angle (a state-independent excitation, as the linear forced response assumes)."""
    net = TorsionalNetwork("forced pair", cycle_deg=360.0)
    net.add_inertia("drive", 1.0).add_inertia("g1", J1).add_inertia("g2", J2).add_inertia("load", 0.02)
    net.add_shaft("drive", "g1", 2e5, 5.0 if damping else 0.0)
    net.add_shaft("g2", "load", 1e5, 5.0 if damping else 0.0)
    net.add_mesh("g1", "g2", base_radii_mm=(R1 * 1e3, R2 * 1e3), teeth=(30, 60), stiffness_N_per_m=K_MESH,
                 damping_N_s_per_m=2000.0 if damping else 0.0, backlash_mm=backlash_mm, stiffness_shape=shape,
                 contact_width_um=0.02)
    net.set_speed_boundary("drive")
    if mean_Nm or ripple_Nm:
        net.add_torque("load", lambda t, a, w, T0, T1, nominal_angle_rad: -(T0 + T1 * nm.cos(2 * nominal_angle_rad)),
                       parameters={"T0": mean_Nm, "T1": ripple_Nm}, name="load")
    return net


def free_pair(damping_ratio=0.0, backlash_mm=0.1, width_um=0.01, damping_width_um=0.5):
    net = TorsionalNetwork("free pair", cycle_deg=360.0)
    net.add_inertia("g1", J1).add_inertia("g2", J2)
    c = 2 * damping_ratio * math.sqrt(K_MESH * M_EQ)
    net.add_mesh("g1", "g2", base_radii_mm=(R1 * 1e3, R2 * 1e3), teeth=(30, 60), stiffness_N_per_m=K_MESH,
                 damping_N_s_per_m=c, backlash_mm=backlash_mm, contact_width_um=width_um,
                 damping_width_um=damping_width_um)
    return net
