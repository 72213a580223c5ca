"""Scenes shared by the studies tests: the crank-cam tip relief at the ends of the data's torque range (kept fast:
one face slice, 24 positions), with a loaded-contact-ratio limit that is active at the optimum."""

import gearopt as go
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene

MESH = "crank-cam"
RELIEF = ("tip_relief_1_um", "tip_relief_2_um", "tip_relief_1_start_roll_deg", "tip_relief_2_start_roll_deg")
TORQUES = (150.0, 450.0)      # [meshes.crank-cam] design_torque_Nm 300 N m x torque_range_fractions 0.5, 1.5


DATA_TORQUES = (150.0, 300.0, 450.0)     # the whole range: a smoother, single-branch optimum (sensitivity tests)


def relief_scene(min_lcr: float = 1.3, stress_limit: bool = True, torques=TORQUES, positions: int = 24) -> Scene:
    limits = [Limit("loaded_contact_ratio", MESH, lower=min_lcr)]
    if stress_limit:
        limits.insert(0, Limit("max_contact_stress_MPa", MESH, upper=1150.0))
    return Scene("relief", train=go.load_default_train("spur"),
                 load_cases=[LoadCase(f"T{t:g}", t) for t in torques],
                 variables=[DesignVariable(v, MESH) for v in RELIEF],
                 objectives=[Objective("ppte_um", MESH, aggregate="max")], limits=limits,
                 ltca_options={"positions": positions})
