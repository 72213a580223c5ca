"""Joint capacity / walk-off margin, gear blank and web fatigue tables of a timing train (thesis sec. 3.10-3.11).

:func:`joint_table` evaluates every ``[joints.*]`` entry of the data for a train (helical baseline or spur redesign)
under given per-mesh torques -- a single load case or a torque history -- :func:`blank_table` gives mass and
inertia of every gear blank and :func:`web_table` the web stress and Goodman/EFR margins of the webbed gears. Columns carry their units; margins are capacity/demand (``inf`` where the demand is
exactly zero, explained in the ``note`` column -- never a large finite stand-in).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from ..blank.blank import rim_thickness_factor
from ..blank.catalogue import blank_from_data
from ..blank.web import web_fatigue, web_stress
from ..data import System, material_record, system_of, train_from_data
from ..errors import GearoptInputError
from ..geometry.train import GearTrain
from ..joints.catalogue import joint_capacity
from ..joints.walk_off import joint_margins, walk_off


def design_load_torques_Nm(system: System) -> dict[str, float]:
    """Per-mesh design torques [N m] of ``system`` (a :class:`~gearopt.data.System`; ``[meshes.<name>]
    design_torque_Nm``, torque on the driving gear): the static design case."""
    torques = system_of(system, "design_load_torques_Nm").design_torques_Nm()
    if not torques:
        raise GearoptInputError("the data state no design torque ([meshes.<name>] design_torque_Nm)")
    return torques


def _train(system: System, train) -> GearTrain:
    if isinstance(train, GearTrain):
        return train
    return train_from_data(system.data, train)


def _worst(x) -> tuple[float, float]:
    """(largest magnitude, signed value there) of a scalar or a history."""
    a = np.atleast_1d(np.asarray(x, dtype=float))
    i = int(np.argmax(np.abs(a)))
    return float(abs(a[i])), float(a[i])


def _min(x) -> float:
    return float(np.min(np.atleast_1d(np.asarray(x, dtype=float))))


def joint_table(system: System, train: str | GearTrain = "spur",
                torques_Nm: Mapping[str, Any] | str | tuple[Mapping[str, Any], str] | None = None, *,
                root_rotation: str = "cw",
                inertia_torques_Nm: Mapping[str, Any] | None = None, interference: str = "nominal",
                nut_factor: str = "nominal", smoothing: bool = False, speed_rpm: float = 0.0) -> pd.DataFrame:
    """One row per joint of the data (``system.joints``): capacity, demand and margins.

    ``system``: the :class:`~gearopt.data.System` of the data file (required; its ``[joints]``, else
    :class:`~gearopt.errors.MissingSectionError`).
    ``train``: ``"spur"``/``"helical"`` (built from ``system``) or a :class:`GearTrain`. ``torques_Nm`` (the load
    case, required): {mesh: torque on the mesh's first gear [N m], + when it drives}, floats or arrays of one
    torque history (meshes left out carry none); ``"design"`` the data's design torques
    (:func:`design_load_torques_Nm`); or a ``(torques, description)`` pair, e.g. a case's load case such as the
    timing train's quasi-static accessory peaks
    (:func:`gearopt.cases.timing_train.quasi_static_load_case`: the library knows no gear by name). ``inertia_torques_Nm``: {gear: J alpha} in each
    gear's sense of rotation. ``interference``/``nut_factor``/``smoothing``/``speed_rpm``: capacity options of
    :func:`~gearopt.joints.catalogue.joint_capacity` (e.g. ``interference="min"``, ``nut_factor="max"`` for the
    weakest joints of the tolerance and nut-factor ranges).

    Columns: ``gear``, ``type``, ``fit``, ``pressure_MPa``, ``torque_capacity_Nm``, ``axial_capacity_N``,
    ``torque_Nm`` and ``axial_force_N`` (largest magnitude over the history, signed: + torque = gear drives its
    shaft, + axial = off the shaft nose), ``torque_margin``, ``axial_margin``, ``combined_margin`` (minimum over the
    history of the slip margin under torque and axial load together), ``hub_von_mises_MPa``, ``hub_yield_safety``,
    ``note``. ``df.attrs`` holds the load case and conventions.
    """
    system = system_of(system, "joint_table")
    system.require("joints", "joint_table")
    tr = _train(system, train)
    torques_Nm, case = _load_case(tr, torques_Nm, system)
    result = walk_off(tr, torques_Nm, root_rotation=root_rotation, inertia_torques_Nm=inertia_torques_Nm)
    helical = float(tr.helix_angle_deg) != 0.0
    rows = []
    for name in system.joints:
        cap = joint_capacity(system, name, interference=interference, nut_factor=nut_factor, smoothing=smoothing,
                             speed_rpm=speed_rpm)
        gear = cap.gear
        if gear not in tr.gears:
            raise GearoptInputError(f"[joints.{name}] gear={gear!r} is not a gear of the train")
        T, F = result.joint_torque_Nm[gear], result.axial_force_N[gear]
        m = joint_margins(cap.type, T, F, cap.torque_capacity_Nm, cap.axial_capacity_N)
        t_abs, t_signed = _worst(T)
        f_abs, f_signed = _worst(F)
        notes = []
        if not helical:
            notes.append("spur: no axial tooth force, axial margin inf")
        elif f_abs == 0.0:
            notes.append("no net axial force in this load case, axial margin inf")
        if t_abs == 0.0:
            notes.append("no net torque through the joint in this load case (an idler passes its torque through), "
                         "torque margin inf")
        if cap.type == "taper_nut":
            notes.append(f"thesis Eq. 3.48 (upper bound; hub stress at its pressure); with engagement friction "
                         f"{cap.torque_capacity_engagement_friction_Nm:.0f} N m; axial load taken as pulling off "
                         f"the taper")
        rows.append({
            "joint": name, "gear": gear, "type": cap.type, "fit": cap.fit,
            "pressure_MPa": cap.pressure_MPa, "torque_capacity_Nm": cap.torque_capacity_Nm,
            "axial_capacity_N": cap.axial_capacity_N, "torque_Nm": t_signed, "axial_force_N": f_signed,
            "torque_margin": _min(m["torque_margin"]), "axial_margin": _min(m["axial_margin"]),
            "combined_margin": _min(m["combined_margin"]), "hub_von_mises_MPa": cap.hub_von_mises_MPa,
            "hub_yield_safety": cap.hub_yield_safety, "note": "; ".join(notes)})
    df = pd.DataFrame(rows).set_index("joint")
    df.attrs.update(train=tr.name, helix_angle_deg=float(tr.helix_angle_deg), load_case=case,
                    root_rotation=root_rotation, interference=interference, nut_factor=nut_factor,
                    conventions="torque + = gear drives its shaft; axial + = off the shaft nose (towards the front)")
    return df


def blank_table(system: System, train: str | GearTrain = "spur") -> pd.DataFrame:
    """One row per gear: blank kind, ``mass_kg``, ``inertia_kgm2``, ``solid_inertia_kgm2`` (same teeth and bore,
    no web), ``inertia_reduction_percent``, ``data_inertia_kgm2`` (the data file's value, for comparison),
    ``backup_ratio``, ``rim_thickness_factor`` (AGMA K_B) and ``assumed`` inputs. ``system``: the
    :class:`~gearopt.data.System` of the data file (required)."""
    system = system_of(system, "blank_table")
    tr = _train(system, train)
    rows = []
    for gear in tr.gears:
        blank, assumed = blank_from_data(system, tr, gear)
        j = float(blank.inertia_kgm2())
        j_solid = float(blank.solid_equivalent().inertia_kgm2())
        m_b = float(blank.backup_ratio)
        g = system.gears[gear].entries if gear in system.gears else {}
        rows.append({"gear": gear, "blank": blank.kind, "mass_kg": float(blank.mass_kg()), "inertia_kgm2": j,
                     "solid_inertia_kgm2": j_solid, "inertia_reduction_percent": 100.0 * (1.0 - j / j_solid),
                     "data_inertia_kgm2": g.get("inertia_kgm2", g.get("solid_disc_inertia_kgm2", float("nan"))),
                     "backup_ratio": m_b,
                     "rim_thickness_factor": float(rim_thickness_factor(m_b)) if m_b >= 0.5 else float("nan"),
                     "assumed": ", ".join(assumed)})
    return pd.DataFrame(rows).set_index("gear")


_LOAD_CASES = ("give a dict of per-mesh torques, 'design' (the data's design torques) or a (torques, description) "
               "load case, e.g. gearopt.cases.timing_train.quasi_static_load_case(system, train) for the timing "
               "train's quasi-static accessory peaks")


def _load_case(tr: GearTrain, torques_Nm, system: System):
    """(per-mesh torques, description) of a table's ``torques_Nm`` argument."""
    if isinstance(torques_Nm, str):
        if torques_Nm != "design":
            raise GearoptInputError(f"torques_Nm={torques_Nm!r}: {_LOAD_CASES}")
        return design_load_torques_Nm(system), "[design_loads] of the data (static design torques on the driving gears)"
    if torques_Nm is None:
        raise GearoptInputError(f"torques_Nm is required (the load case): {_LOAD_CASES}")
    if isinstance(torques_Nm, tuple):
        if len(torques_Nm) != 2 or not isinstance(torques_Nm[0], Mapping) or not isinstance(torques_Nm[1], str):
            raise GearoptInputError(f"torques_Nm: a load case pair must be (torques, description): {_LOAD_CASES}")
        return dict(torques_Nm[0]), torques_Nm[1]
    return torques_Nm, "given per-mesh torques"


def web_table(system: System, train: str | GearTrain = "spur",
              torques_Nm: Mapping[str, Any] | str | tuple[Mapping[str, Any], str] | None = None, *,
              root_rotation: str = "cw",
              inertia_torques_Nm: Mapping[str, Any] | None = None, stress_concentration: float = 1.0) -> pd.DataFrame:
    """Web stress and Goodman/EFR fatigue margins of every webbed gear (thesis sec. 3.10 / 4.6, closed-form model of
    :mod:`gearopt.blank.web`).

    Loads per instant: the joint torque through the web (rim to hub), the in-plane tooth-force resultant bounded by
    the sum of the transverse mesh-force magnitudes F_t/cos(alpha_wt) (the mesh layout is not in the train), and the
    net axial force. The equivalent stress carries the sign of the joint torque; the forward stress is its largest
    positive value, the reverse stress the largest negative magnitude. A single load case is also applied reversed
    (thesis: every tooth force forward, then reverse), so its forward-reverse case is fully reversed. Material: the
    gear's ``[materials.*]`` endurance, ultimate and yield strengths. ``stress_concentration`` K_t at the pockets.
    ``system``: the :class:`~gearopt.data.System` of the data file (required). ``torques_Nm``: the load case, as
    :func:`joint_table` takes it (required).
    Columns: loads, ``forward_stress_MPa``, ``reverse_stress_MPa`` and per case ``<case>_efr_MPa``,
    ``<case>_fatigue_margin`` (S_e/EFR), and ``yield_margin``.
    """
    system = system_of(system, "web_table")
    tr = _train(system, train)
    torques, case = _load_case(tr, torques_Nm, system)
    result = walk_off(tr, torques, root_rotation=root_rotation, inertia_torques_Nm=inertia_torques_Nm)
    rows = []
    for gear in tr.gears:
        blank, assumed = blank_from_data(system, tr, gear)
        if blank.web_thickness_mm is None:
            continue
        force = 0.0
        for row in result.contributions:
            if row["gear"] == gear:
                alpha = tr.pairs[row["mesh"]].geometry()["working_pressure_angle_deg"]
                force = force + np.abs(row["tangential_force_N"]) / math.cos(math.radians(alpha))
        T = result.joint_torque_Nm[gear]
        f_pocket = float(blank.pocket_area_fraction) if not blank.hole_count else 0.0
        s = web_stress(T, hub_outer_diameter_mm=blank.hub_outer_diameter_mm,
                       rim_inner_diameter_mm=blank.rim_inner_diameter_mm, web_thickness_mm=blank.web_thickness_mm,
                       in_plane_force_N=force, axial_force_N=result.axial_force_N[gear], pocket_area_fraction=f_pocket,
                       stress_concentration=stress_concentration)
        signed = np.atleast_1d(np.where(np.asarray(T) >= 0.0, 1.0, -1.0) * np.asarray(s["von_mises_MPa"]))
        single = signed.size == 1
        fwd = float(np.max(np.abs(signed))) if single else float(max(np.max(signed), 0.0))
        rev = fwd if single else float(max(-np.min(signed), 0.0))
        mat = material_record(system, system.gear(gear).material, "web_table", f"gears.{gear}.material")
        fat = web_fatigue(fwd, rev, endurance_limit_MPa=mat["endurance_limit_MPa"],
                          ultimate_strength_MPa=mat["tensile_strength_MPa"],
                          yield_strength_MPa=mat["yield_strength_MPa"])
        row = {"gear": gear, "blank": blank.kind, "web_thickness_mm": float(blank.web_thickness_mm),
               "torque_Nm": _worst(T)[1], "in_plane_force_N": _worst(force)[0],
               "axial_force_N": _worst(result.axial_force_N[gear])[1], "forward_stress_MPa": fwd,
               "reverse_stress_MPa": rev}
        for name, r in fat.items():
            row[f"{name}_efr_MPa"] = float(r["efr_MPa"])
            row[f"{name}_fatigue_margin"] = float(r["fatigue_margin"])
        row["yield_margin"] = float(fat["forward_reverse"]["yield_margin"])
        row["assumed"] = ", ".join(assumed)
        rows.append(row)
    df = pd.DataFrame(rows).set_index("gear")
    df.attrs.update(load_case=case, model="gearopt.blank.web: web shear (torque + in-plane force bound), annular "
                                          "plate bending under the net axial force, von Mises, modified Goodman")
    return df


__all__ = ["joint_table", "blank_table", "web_table", "design_load_torques_Nm"]
