"""Walk-off: axial thrust of helical meshes on each gear of a train, torque per shaft-hub joint, and slip margins.

Conventions (one set for the whole train, all shafts parallel):

* axis +z points out of the gear-train face towards the viewer standing in front of the engine, i.e. *off* the
  shaft noses: a positive axial force pulls a gear off its shaft nose (the walk-off direction of the thesis' cam
  gear). Rotation senses are viewed from +z (from the front): ``"ccw"`` / ``"cw"``. The crankshaft of an engine of
  standard rotation turns counter-clockwise seen from the flywheel end, i.e. clockwise from the front (SAE J824
  convention, [M] not re-read here) -- hence ``root_rotation="cw"`` by default.
* ``mesh_torques_Nm[mesh]`` is the torque *on the mesh's first-named gear* (its nominal driver) transmitted
  through that mesh [N m], positive when that gear drives the other (power flows gear 1 -> gear 2). The torque on
  gear 2 is then T z2/z1 and the transmitted tangential force F_t = 2000 T / d_w1 [N] at the working pitch circle.
* Joint torque of a gear [N m], positive when the gear drives its shaft (cam gear -> camshaft) and negative when the
  shaft drives the gear (crankshaft -> crank gear): the net mesh torque on the gear in its sense of rotation minus
  its inertia torque J alpha (``inertia_torques_Nm``, same sense), from the gear's rotational equilibrium.

Axial force of one mesh on a gear (derivation, no source needed beyond geometry): the tooth contact force is normal
to the flank, and the flank contains the helix tangent t = sin(beta) e_theta + h cos(beta) e_z (h = +1 right hand,
-1 left hand, on the pitch cylinder). Hence F . t = 0 gives ``F_z = -h tan(beta) F_theta`` with F_theta the
tangential force on the gear in +theta (counter-clockwise from the front) direction. Evaluated at the working pitch
circle (F_t,w = 2000 T/d_w, tan(beta_w) = tan(beta) d_w/d) or the reference circle (2000 T/d, tan(beta)) the product
is the same, ``2000 T tan(beta)/d`` (tested; :func:`gearopt.geometry.forces.axial_force_N`, the package's one
thrust function, and ``mesh_axial_force_N`` of a torque, re-exported here). Newton's third law holds mesh by mesh
(opposite hands, equal F_theta). A gear meshing with several others (an idler, or a cam gear driving accessories) sums
its meshes with their signs; as all its meshes share its hand and helix, the net thrust is
``2000 tan(beta) (T_joint + J alpha) / d`` -- the quasi-static thrust of the cam gear follows the camshaft's own
torque, while the accessory loads cancel through the gear (a property the tests check).

Margins: ``torque_margin = torque_capacity / |joint torque|``, ``axial_margin = axial_capacity / |axial force|``,
and a combined margin from the joint's slip utilisation (press fit: friction-force resultant
``sqrt((T/T_cap)^2 + (F_a/F_cap)^2)``; taper: ``|T|/T_cap + F_a/W``, worst direction assumed). A zero demand
(spur gears: no axial force; an idler's joint: no net torque) gives margin ``inf`` in numeric evaluation -- never a
large finite stand-in; in NLPs use the utilisations (finite everywhere, constraint ``utilisation <= 1/S``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from ._checks import check_range_any
from ..geometry import forces
from ..geometry.forces import mesh_axial_force_N, tangential_force_N
from ..geometry.involute import helix_angle_at
from ..geometry.train import GearTrain
from ..units import RAD_PER_DEG

ROTATIONS = {"ccw": 1.0, "cw": -1.0}
HANDS = {"right": 1.0, "left": -1.0}


def working_helix_angle_deg(helix_angle_deg, reference_diameter_mm, working_diameter_mm):
    """Helix angle on the working pitch cylinder [deg]: ``tan(beta_w) = tan(beta) d_w / d`` (ISO 21771 eq. 14,
    :func:`gearopt.geometry.involute.helix_angle_at`)."""
    return helix_angle_at(working_diameter_mm, reference_diameter_mm, helix_angle_deg * RAD_PER_DEG) / RAD_PER_DEG


@dataclass(frozen=True)
class WalkOffResult:
    """Per-gear axial force [N] (+z = off the shaft nose) and joint torque [N m] (+ = gear drives its shaft), with
    the per-mesh contributions. Values are floats, arrays (torque histories) or CasADi expressions."""

    axial_force_N: dict[str, Any]
    joint_torque_Nm: dict[str, Any]
    rotation_sign: dict[str, float]
    contributions: list[dict] = field(default_factory=list)

    def table(self) -> pd.DataFrame:
        """Per-mesh, per-gear contributions as a DataFrame (numeric scalars)."""
        return pd.DataFrame(self.contributions).set_index(["mesh", "gear"])


def gear_rotation_signs(train: GearTrain, root_rotation: str = "cw") -> dict[str, float]:
    """+1 (counter-clockwise seen from the front, +z) or -1 per gear, from the root gear's rotation and the train's
    speed ratios (external meshes reverse the sense)."""
    if root_rotation not in ROTATIONS:
        raise GearoptInputError(f"root_rotation={root_rotation!r} must be 'cw' or 'ccw' (seen from the front, +z)")
    s0 = ROTATIONS[root_rotation]
    return {g: s0 * math.copysign(1.0, float(r)) for g, r in train.speed_ratios.items()}


def _check_mesh_torques(train: GearTrain, mesh_torques_Nm: Mapping[str, Any]) -> None:
    unknown = set(mesh_torques_Nm) - set(train.meshes)
    if unknown:
        raise GearoptInputError(f"mesh_torques_Nm names unknown meshes {sorted(unknown)}; train meshes: "
                                f"{list(train.meshes)}")
    for name, torque in mesh_torques_Nm.items():
        check_range_any(f"mesh_torques_Nm[{name!r}]", torque, unit="N m")


def walk_off(train: GearTrain, mesh_torques_Nm: Mapping[str, Any], *, root_rotation: str = "cw",
             inertia_torques_Nm: Mapping[str, Any] | None = None) -> WalkOffResult:
    """Axial force on every gear and torque through every gear's joint from per-mesh torques (module docstring).

    ``mesh_torques_Nm``: {mesh name: torque on the mesh's first gear [N m], + when it drives}; meshes left out carry
    no torque. Values may be floats, numpy arrays of equal shape (a torque history over time or speed) or CasADi
    expressions. ``inertia_torques_Nm``: {gear: J alpha [N m] in the gear's sense of rotation} (default 0).
    Helix data come from the train (one helix angle, alternating hands); a spur train gives zero axial forces.
    """
    _check_mesh_torques(train, mesh_torques_Nm)
    signs = gear_rotation_signs(train, root_rotation)
    beta_deg = train.helix_angle_deg
    helical = nm.is_symbolic(beta_deg) or nm.to_float(beta_deg) != 0.0
    axial: dict[str, Any] = {g: 0.0 for g in train.gears}
    net: dict[str, Any] = {g: 0.0 for g in train.gears}
    rows = []
    for name, pair in train.pairs.items():
        if name not in mesh_torques_Nm:
            continue
        T1 = mesh_torques_Nm[name]
        geo = pair.geometry()
        d_w = geo["working_pitch_diameter_mm"]
        d_ref = geo["pitch_diameter_mm"]
        F_t = tangential_force_N(T1, d_w[0])  # transmitted force at the working pitch circle [N], + = 1 drives 2
        for i, gear in enumerate(pair.names):
            s = signs[gear]
            # torque on this gear from the mesh in its own sense of rotation: the driver is braked, the driven pushed
            torque_rot = -T1 if i == 0 else T1 * pair.teeth[1] / pair.teeth[0]
            net[gear] = net[gear] + torque_rot
            f_theta = s * (-F_t if i == 0 else F_t)  # tangential force on the gear in +theta (ccw from the front)
            if helical:
                h = HANDS[train.helix_hands[gear]]
                beta_w = working_helix_angle_deg(beta_deg, d_ref[i], d_w[i])
                f_z = -h * forces.axial_force_N(f_theta, beta_w)
            else:
                beta_w, f_z = 0.0, 0.0 * f_theta
            axial[gear] = axial[gear] + f_z
            rows.append({"mesh": name, "gear": gear, "role": "driving" if i == 0 else "driven",
                         "rotation": "ccw" if s > 0 else "cw",
                         "hand": train.helix_hands[gear] if helical else "",
                         "working_pitch_diameter_mm": d_w[i], "working_helix_angle_deg": beta_w,
                         "tangential_force_N": F_t, "mesh_torque_on_gear_Nm": torque_rot, "axial_force_N": f_z})
    inertia = dict(inertia_torques_Nm or {})
    unknown = set(inertia) - set(train.gears)
    if unknown:
        raise GearoptInputError(f"inertia_torques_Nm names unknown gears {sorted(unknown)}")
    joint = {g: net[g] - inertia.get(g, 0.0) for g in train.gears}
    return WalkOffResult(axial_force_N=axial, joint_torque_Nm=joint, rotation_sign=signs, contributions=rows)


def quasi_static_mesh_torques_Nm(train: GearTrain, load_torques_Nm: Mapping[str, Any]) -> dict[str, Any]:
    """Per-mesh torques (on each mesh's first gear, + = it drives) that carry given shaft loads from the root gear.

    ``load_torques_Nm``: {gear: torque its shaft absorbs [N m], + = the gear drives its load} (the root gear's
    entry is ignored: it supplies the rest). No mesh losses, rigid quasi-static train (no inertia torques). The
    loads are summed as if they peaked together -- a conservative design case, not a dynamic one.
    """
    unknown = set(load_torques_Nm) - set(train.gears)
    if unknown:
        raise GearoptInputError(f"load_torques_Nm names unknown gears {sorted(unknown)}")
    children: dict[str, list[tuple[str, str]]] = {g: [] for g in train.gears}
    order, seen = [train.root_gear], {train.root_gear}
    i = 0
    while i < len(order):
        g = order[i]
        for name, mesh in train.meshes.items():
            if g in mesh.gears:
                other = mesh.gears[1] if mesh.gears[0] == g else mesh.gears[0]
                if other not in seen:
                    seen.add(other)
                    children[g].append((name, other))
                    order.append(other)
        i += 1
    required: dict[str, Any] = {}
    for g in reversed(order):  # leaves first: torque each gear must receive = own load + what it passes on
        total = load_torques_Nm.get(g, 0.0) if g != train.root_gear else 0.0
        for mesh_name, child in children[g]:
            total = total + required[child] * train.gears[g].teeth / train.gears[child].teeth
        required[g] = total
    torques = {}
    for g in order:
        for mesh_name, child in children[g]:
            t_parent = required[child] * train.gears[g].teeth / train.gears[child].teeth
            first = train.meshes[mesh_name].gears[0]
            # on the first gear: + when it drives; if the child is listed first it is driven by gear 2
            torques[mesh_name] = t_parent if first == g else -required[child]
    return torques


# ----------------------------------------------------------------------------------------------------------------
# margins
# ----------------------------------------------------------------------------------------------------------------

def _safe_ratio(capacity, demand):
    """capacity/|demand| with inf where the demand is exactly zero (numeric); a CasADi expression otherwise."""
    if nm.is_symbolic(capacity, demand):
        return capacity / nm.fabs(demand)
    cap = np.asarray(nm.value(capacity), dtype=float)
    dem = np.abs(np.asarray(nm.value(demand), dtype=float))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):  # denormal demands: margin inf
        r = np.where(dem > 0.0, cap / np.where(dem > 0.0, dem, 1.0), np.inf)
    return float(r) if r.ndim == 0 else r


def _load_ratio(demand, capacity):
    """|demand|/capacity (numeric): ``inf`` for a load on a zero capacity, 0 without load."""
    dem = np.abs(np.asarray(nm.value(demand), dtype=float))
    cap = np.asarray(nm.value(capacity), dtype=float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return np.where(dem > 0.0, np.where(cap > 0.0, dem / np.where(cap > 0.0, cap, 1.0), np.inf), 0.0)


def press_fit_slip_utilisation(torque_Nm, axial_force_N, torque_capacity_Nm, axial_capacity_N):
    """Slip utilisation of a press fit [-]: the friction-force resultant of circumferential and axial load over the
    friction capacity, ``sqrt((T/T_cap)^2 + (F_a/F_cap)^2)`` (T_cap = F_cap d/2). Slip when > 1. Smooth except at
    zero load; its square is smooth everywhere (use that in NLPs)."""
    return nm.sqrt((torque_Nm / torque_capacity_Nm) ** 2 + (axial_force_N / axial_capacity_N) ** 2)


def joint_margins(joint_type: str, torque_Nm, axial_force_N, torque_capacity_Nm, axial_capacity_N) -> dict:
    """Margins of one joint: ``torque_margin``, ``axial_margin`` (capacity/demand, inf at zero demand),
    ``slip_utilisation`` (combined, see module docstring) and ``combined_margin`` = 1/utilisation.

    ``joint_type``: ``"press_fit"`` or ``"taper_nut"`` (for a taper the axial force is taken as pulling the hub off
    the taper -- the worst case when the taper's orientation is not known).
    """
    if joint_type not in ("press_fit", "taper_nut"):
        raise GearoptInputError(f"joint_type={joint_type!r} must be 'press_fit' or 'taper_nut'")
    check_range_any("torque_Nm", torque_Nm, unit="N m")
    check_range_any("axial_force_N", axial_force_N, unit="N")
    check_range_any("torque_capacity_Nm", torque_capacity_Nm, 0.0, None, unit="N m")  # 0: a lost fit
    check_range_any("axial_capacity_N", axial_capacity_N, 0.0, None, unit="N")
    if not nm.is_symbolic(torque_Nm, axial_force_N, torque_capacity_Nm, axial_capacity_N):
        # numeric: a zero capacity (a lost fit) gives an infinite utilisation under load, never 0/0
        t = _load_ratio(torque_Nm, torque_capacity_Nm)
        a = _load_ratio(axial_force_N, axial_capacity_N)
        u = np.sqrt(t * t + a * a) if joint_type == "press_fit" else t + a
        u = float(u) if np.ndim(u) == 0 else u
    elif joint_type == "press_fit":
        u = press_fit_slip_utilisation(torque_Nm, axial_force_N, torque_capacity_Nm, axial_capacity_N)
    elif joint_type == "taper_nut":
        u = nm.fabs(torque_Nm) / torque_capacity_Nm + nm.fabs(axial_force_N) / axial_capacity_N
    else:
        raise GearoptInputError(f"joint_type={joint_type!r} must be 'press_fit' or 'taper_nut'")
    return {"torque_margin": _safe_ratio(torque_capacity_Nm, torque_Nm),
            "axial_margin": _safe_ratio(axial_capacity_N, axial_force_N),
            "slip_utilisation": u, "combined_margin": _safe_ratio(1.0, u)}


def margin_history(joint_type: str, torque_Nm, axial_force_N, torque_capacity_Nm, axial_capacity_N) -> dict:
    """Margins over a torque history (arrays over time or speed): the margin arrays of :func:`joint_margins` and
    their minima with the index where each occurs (``min_torque_margin``, ``argmin_torque_margin``, ...)."""
    m = joint_margins(joint_type, np.asarray(torque_Nm, dtype=float), np.asarray(axial_force_N, dtype=float),
                      torque_capacity_Nm, axial_capacity_N)
    out = dict(m)
    for key in ("torque_margin", "axial_margin", "combined_margin"):
        arr = np.atleast_1d(m[key])
        out[f"min_{key}"] = float(np.min(arr))
        out[f"argmin_{key}"] = int(np.argmin(arr))
    out["max_slip_utilisation"] = float(np.max(np.atleast_1d(m["slip_utilisation"])))
    return out


__all__ = ["walk_off", "WalkOffResult", "gear_rotation_signs", "mesh_axial_force_N", "working_helix_angle_deg",
           "quasi_static_mesh_torques_Nm", "press_fit_slip_utilisation", "joint_margins", "margin_history",
           "ROTATIONS", "HANDS"]
