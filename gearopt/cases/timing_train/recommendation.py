"""The timing train's one answer: the co-design study's designs judged on every requirement, the best chosen.

The candidates are the designs of :func:`~gearopt.cases.timing_train.codesign_study` (per train option the
sequential design and the co-design) as its ``to_json()`` holds them: each becomes a
:class:`~gearopt.design.requirements.TrainDesign` (the packaged spur train at the design's root profile shift and
helix angle, its per-mesh flank modifications) and :func:`~gearopt.design.recommendation.recommend` judges them on
the exact models and picks one. The PPTE requirement compares each design with the unmodified flanks of its
option's baseline (the packaged spur train at the option's helix angle: the train the study's NLP compared with).

The dynamic requirements take the main job's dynamics of the spur train with backlash: the largest dynamic mesh
torque per mesh (rated at K_A = K_v = 1) and the joint margins of the speed sweep. A candidate with a helix angle
gets walk-off margins over speed from its own thrust: at each sweep speed the spur train's peak mesh torques of that
speed act together on the candidate's helical train (:func:`gearopt.joints.walk_off`, quasi-static; conservative,
the peaks of different meshes need not coincide), against the joint's axial capacity at that speed.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from ...contact.microgeometry import Microgeometry
from ...data import System
from ...design.recommendation import Recommendation, recommend
from ...design.requirements import DynamicPeaks, TrainDesign, with_capacities
from ...joints.catalogue import joint_capacity
from ...geometry.forces import mesh_torque_Nm
from ...joints.walk_off import joint_margins, walk_off


def codesign_candidates(system: System, codesign: Mapping[str, Any]) -> tuple[list[TrainDesign], dict[str, str]]:
    """The designs of a co-design study's JSON (``CodesignStudy.to_json()``) as candidates, and {candidate: option}.
    A design whose solve failed is not a candidate."""
    base = system.train("spur")
    designs, options = [], {}
    for option, entry in codesign["options"].items():
        for kind in ("sequential", "codesign"):
            e = entry.get(kind) or {}
            if "failed" in e or "microgeometry" not in e:
                continue
            macro = e["macro"]
            train = dataclasses.replace(base, root_profile_shift=float(macro["root_profile_shift"]),
                                        helix_angle_deg=float(macro["helix_angle_deg"]))
            mods = {mesh: Microgeometry(**{k: tuple(v) if isinstance(v, list) else v for k, v in mg.items()})
                    for mesh, mg in e["microgeometry"].items()}
            name = f"{option} {kind}"
            reference = dataclasses.replace(base, helix_angle_deg=float(macro["helix_angle_deg"]))
            designs.append(TrainDesign(train, mods, name=name, variables=("macro", "flanks"),
                                       reference_train=reference))
            options[name] = option
    return designs, options


def dynamic_peaks(design_torques: pd.DataFrame, sweep: pd.DataFrame, train: str = "spur") -> DynamicPeaks:
    """The dynamics' results the requirements judge (:class:`DynamicPeaks`), from the main job's dynamic design
    torques (one row per train, speed, backlash and mesh) and the speed sweep of ``train`` (with backlash)."""
    lash = design_torques[design_torques["backlash"] & (design_torques["train"] == train)]
    worst = lash.loc[lash.groupby("mesh")["peak_dynamic_torque_Nm"].idxmax()]
    peaks = {str(r["mesh"]): (float(r["peak_dynamic_torque_Nm"]), float(r["speed_rpm"])) for _, r in worst.iterrows()}
    joints = sweep[sweep["element_type"] == "joint"]
    rows = [{"joint": str(r["element"]).removeprefix("joint:"), "speed_rpm": float(r["speed_rpm"]),
             "torque_margin": float(r["min_torque_margin"]), "axial_margin": float(r["min_axial_margin"]),
             "peak_torque_Nm": float(r["peak_torque_Nm"]), "peak_axial_force_N": float(r["peak_axial_force_N"]),
             **({"cycles": int(r["cycles"])} if "cycles" in r else {}),
             **{c: float(r[c]) for c in r.index if "_margin_cycle_" in c}}
            for _, r in joints.iterrows()]
    return DynamicPeaks(mesh_torques_Nm=peaks, joint_margins=rows,
                        basis=f"the {train} train's dynamics with backlash (largest peak over the simulated speeds "
                              f"and recorded cycles)")


def helical_dynamic_peaks(system: System, design: TrainDesign, spur: DynamicPeaks, sweep: pd.DataFrame
                          ) -> DynamicPeaks:
    """``spur``'s dynamic results for a candidate with a helix angle: the same mesh torques and joint torque margins;
    the walk-off margin over speed from the candidate's own thrust (module docstring) as the combined slip margin
    of torque and thrust at the weakest fit (minimum interference, DIN 7190 smoothing, highest nut factor): a fit
    that slips under torque walks under any thrust."""
    tr = design.train
    if float(tr.helix_angle_deg) == 0.0:
        return spur
    base = system.train("spur")
    meshes = sweep[sweep["element_type"] == "mesh"]
    rows = []
    for e in spur.joint_margins:
        at = meshes[meshes["speed_rpm"] == e["speed_rpm"]]
        torques = {str(r["element"]): float(mesh_torque_Nm(
            max(abs(float(r["peak_drive_force_N"])), abs(float(r["peak_back_force_N"]))),
            0.5 * float(base.pairs[str(r["element"])].geometry()["base_diameter_mm"][0])))
            for _, r in at.iterrows() if str(r["element"]) in tr.pairs}
        gear = system.joints[e["joint"]].gear
        thrust = abs(float(walk_off(tr, torques).axial_force_N[gear])) if torques else 0.0
        cap = joint_capacity(system, e["joint"], interference="min", nut_factor="max", smoothing=True,
                             speed_rpm=e["speed_rpm"])
        combined = float(np.min(joint_margins(cap.type, e["peak_torque_Nm"], thrust, cap.torque_capacity_Nm,
                                              cap.axial_capacity_N)["combined_margin"])) if thrust > 0 else np.inf
        rows.append({k: v for k, v in e.items() if not k.startswith("axial_margin_cycle_")}
                    | {"axial_margin": combined, "peak_axial_force_N": thrust})
    return DynamicPeaks(mesh_torques_Nm=spur.mesh_torques_Nm, joint_margins=rows,
                        basis=spur.basis + "; walk-off: the helical thrust of the spur train's peak mesh torques at "
                              "each speed (quasi-static, all peaks together) with the peak joint torque, combined "
                              "slip margin at the weakest fit")


def timing_recommendation(system: System, codesign: Mapping[str, Any], *, contact_meshes: Sequence[str],
                          design_torques: pd.DataFrame | None = None, sweep: pd.DataFrame | None = None,
                          ltca_options: Mapping[str, Any] | None = None) -> Recommendation:
    """The recommended design of the timing train among the co-design study's designs (module docstring)."""
    designs, options = codesign_candidates(system, codesign)
    spur = None
    if design_torques is not None and sweep is not None:
        spur = dynamic_peaks(design_torques, sweep)

    def dynamic(design: TrainDesign, sized: System):
        if spur is None:
            return None
        own = spur if sized is system else with_capacities(spur, sized, [n for n, j in sized.joints.items() if j.free])
        return helical_dynamic_peaks(sized, design, own, sweep)

    return recommend(system, designs, contact_meshes=contact_meshes, dynamic=dynamic, options=options,
                     ltca_options=ltca_options)


__all__ = ["codesign_candidates", "dynamic_peaks", "helical_dynamic_peaks", "timing_recommendation"]
