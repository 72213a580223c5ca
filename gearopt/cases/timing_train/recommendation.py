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

A safety the recommended design fails gets the reach of the study's macro design space
(:func:`~gearopt.cases.timing_train.codesign.codesign_design_space`: root shift and, where the study solved the
low-helix option, helix angle within the study's bounds, held to its geometry limits, safeties at the design torques and walk-off margins) in its "what it would
take": the elastic mode on the exact rating says whether any design of the space meets it, the best value reached
and which bounds or limits stop it (:func:`gearopt.design.recommendation.add_reach`).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from ...contact.microgeometry import Microgeometry
from ...data import System, system_from_data
from ...errors import GearoptInputError
from ...design.recommendation import Recommendation, add_reach, recommend
from ...design.requirement_reach import RequirementReach
from ...design.requirements import DynamicPeaks, TrainDesign, evaluate_requirements, with_capacities
from ...joints.catalogue import joint_capacity
from ...geometry.forces import mesh_torque_Nm
from ...joints.walk_off import joint_margins, walk_off
from .codesign import codesign_design_space


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
                          ltca_options: Mapping[str, Any] | None = None, dynamics_speeds_rpm=None,
                          dynamics_run: Mapping[str, Any] | None = None,
                          calibrated_inputs: Mapping[str, Any] | None = None) -> Recommendation:
    """The recommended design of the timing train among the co-design study's designs (module docstring). With
    ``dynamics_speeds_rpm`` the recommended design's dynamic peaks are checked to be its own
    (:func:`dynamics_check`, ``dynamics_run`` the simulation settings) and, when its train differs from the one
    simulated by more than :data:`DYNAMICS_AGREEMENT`, it is judged again with its own peaks. With
    ``calibrated_inputs`` (the failure model's calibration to the field record,
    :func:`gearopt.studies.calibration.calibrate_walk_off`) its joint and dynamic rows are judged again on them
    (``rec.calibrated``, :func:`gearopt.studies.calibration.recheck_on_calibrated_inputs`)."""
    designs, options = codesign_candidates(system, codesign)
    spur = None
    if design_torques is not None and sweep is not None:
        spur = dynamic_peaks(design_torques, sweep)

    def dynamic(design: TrainDesign, sized: System):
        if spur is None:
            return None
        own = spur if sized is system else with_capacities(spur, sized, [n for n, j in sized.joints.items() if j.free])
        return helical_dynamic_peaks(sized, design, own, sweep)

    # the space the study explored: the helix angle only where it solved the low-helix option
    space = codesign_design_space(system, codesign["settings"], helix="low_helix" in codesign.get("options", {})) \
        if "settings" in codesign else None
    known = [RequirementReach.from_json(n["reach"])             # the co-design's reaches: not solved twice
             for notes in codesign.get("settings", {}).get("dynamic_peaks", {}).get("options", {}).values()
             for n in notes.values()]
    rec = recommend(system, designs, contact_meshes=contact_meshes, dynamic=dynamic, options=options,
                    ltca_options=ltca_options, design_space=space, known_reaches=known)
    judged_with = dynamic
    if dynamics_speeds_rpm is not None and spur is not None:
        judged = dynamic(rec.design, rec.system)
        check = dynamics_check(system, rec.design, judged, dynamics_speeds_rpm, **dict(dynamics_run or {}))
        own = check.pop("own", None)
        if own is not None:
            check["own_peaks"] = {m: [float(t), float(v)] for m, (t, v) in own.items()}
        if not check["agrees"]:
            again = dataclasses.replace(judged, mesh_torques_Nm=own, basis=judged.basis.replace(
                "the spur train's dynamics", "the design's own train's dynamics"))
            rec.check = rec.checks[rec.design.name] = evaluate_requirements(
                rec.system, rec.design, contact_meshes=contact_meshes, dynamic=again, ltca_options=ltca_options)
            if space is not None and rec.check.verdict == "FAIL":
                add_reach(rec.system or system, rec.design, rec.check, space, known)
            check["note"] += "; judged again with its own peaks"
            judged_with = _own_peaks(again)
        rec.dynamics_check = check
        rec.notes.append(f"dynamics: {check['note']}")
    if calibrated_inputs:
        from ...studies.calibration import recheck_on_calibrated_inputs
        rec.calibrated = recheck_on_calibrated_inputs(rec.system or system, rec.design, rec.check,
                                                      dict(calibrated_inputs), dynamic=judged_with,
                                                      contact_meshes=contact_meshes)
    return rec


DESIGN_LOOP_ROUNDS = 3
"""Largest number of co-design solves of :func:`dynamics_design_loop`."""


def carried_dynamic_requirements(codesign: Mapping[str, Any]) -> list[str]:
    """``"option: key"`` of every dynamic-peak requirement a co-design study's NLPs carried (its JSON's
    ``settings["dynamic_peaks"]``): where none was, the study's designs do not depend on the peak torques."""
    notes = codesign.get("settings", {}).get("dynamic_peaks", {}).get("options", {})
    return [f"{option}: {key}" for option, keys in notes.items() for key, n in keys.items() if n.get("carried")]


def dynamics_design_loop(system: System, solve, codesign: Mapping[str, Any], *, contact_meshes: Sequence[str],
                         design_torques: pd.DataFrame, sweep: pd.DataFrame, dynamics_speeds_rpm,
                         dynamics_run: Mapping[str, Any] | None = None,
                         calibrated_inputs: Mapping[str, Any] | None = None,
                         max_rounds: int = DESIGN_LOOP_ROUNDS) -> tuple[Recommendation, Mapping[str, Any], list[dict]]:
    """Dynamics in the design loop. ``codesign``: the co-design study's JSON solved with the spur train's dynamic
    peaks (``codesign_study(dynamic_peaks=...)``); ``solve(peaks)``: the same study solved again with other peaks
    ({mesh: (torque [N m], crank speed [rpm])}), as JSON. Each round recommends a design
    (:func:`timing_recommendation`) and simulates its own train (:func:`dynamics_check`); when its peak mesh
    torques differ from those the study's NLPs carried by more than :data:`DYNAMICS_AGREEMENT` and a dynamic-peak
    requirement was carried (:func:`carried_dynamic_requirements`: else the designs do not depend on the peaks and a
    re-solve would return them unchanged), the study is solved again with the design's own peaks. Stops when they
    agree, when nothing was carried or after ``max_rounds`` solves. Returns the recommendation, the last study's
    JSON and one row per round (peaks, largest change [%], agreement, the requirements carried)."""
    if max_rounds < 1:
        raise GearoptInputError(f"max_rounds={max_rounds} must be >= 1")
    spur = {m: [float(t), float(v)] for m, (t, v) in dynamic_peaks(design_torques, sweep).mesh_torques_Nm.items()}
    peaks = dict(codesign.get("settings", {}).get("dynamic_peaks", {}).get("torques", {})) or spur
    history: list[dict] = []
    for round_ in range(max_rounds):
        rec = timing_recommendation(system, codesign, contact_meshes=contact_meshes, design_torques=design_torques,
                                    sweep=sweep, dynamics_speeds_rpm=dynamics_speeds_rpm, dynamics_run=dynamics_run,
                                    calibrated_inputs=calibrated_inputs)
        carried = carried_dynamic_requirements(codesign)
        # the design's own peaks (simulated where its train differs from the packaged spur train's) against the
        # peaks its study's NLPs carried
        own = rec.dynamics_check.get("own_peaks") or spur
        change = max((abs(own[m][0] / float(t) - 1.0) for m, (t, _) in peaks.items() if m in own and float(t) > 0),
                     default=0.0)
        history.append({"round": round_ + 1, "design": rec.design.name,
                        "peaks_Nm": {m: float(v[0]) for m, v in peaks.items()},
                        "own_peaks_Nm": {m: float(v[0]) for m, v in own.items()},
                        "max_change_percent": 100.0 * change, "agrees": change <= DYNAMICS_AGREEMENT,
                        "carried": carried})
        if change <= DYNAMICS_AGREEMENT or not carried or round_ + 1 == max_rounds:
            break
        peaks = {m: list(v) for m, v in own.items()}
        codesign = solve({m: (float(t), float(v)) for m, (t, v) in peaks.items()})
    return rec, codesign, history


def _own_peaks(peaks):
    """The dynamic peaks of a design judged with its own peaks, as a function of (design, system): the joint
    margins recomputed for the system's capacities."""
    def of(design: TrainDesign, sized: System):
        return with_capacities(peaks, sized, list(sized.joints))
    return of


DYNAMICS_AGREEMENT = 0.02
"""Relative change of the peak mesh torques below which the dynamics the requirements judged are the recommended
design's own (else it is judged again with its own peaks)."""


def design_peak_torques_Nm(system: System, design: TrainDesign, speeds_rpm, *, cycles: int = 5,
                           run_in_cycles: int = 1, rtol: float = 1e-3) -> dict[str, tuple[float, float]]:
    """{mesh: (largest dynamic mesh torque [N m], crank speed [rpm] where it occurs)} of ``design``'s own train (its
    root profile shift and helix angle in the timing model; backlash on) over ``speeds_rpm``: |mesh force| x base
    radius of the mesh's first gear, the peak over the recorded cycles."""
    from .model import default_timing_model

    tr = design.train
    kind = "spur" if float(tr.helix_angle_deg) == 0.0 else "helical"
    data = system.data
    data["trains"][kind].update(root_profile_shift=float(tr.profile_shifts[tr.root_gear]),
                                helix_angle_deg=float(tr.helix_angle_deg))
    data["trains"][kind].pop("root_shift_split", None)
    model = default_timing_model(kind, system=system_from_data(data, source=f"{system.source} (the design's train)"))
    peaks: dict[str, tuple[float, float]] = {}
    for speed in speeds_rpm:
        sim = model.simulate(speed_rpm=float(speed), backlash=True, cycles=cycles, run_in_cycles=run_in_cycles,
                             rtol=rtol)
        for mesh in sim.mesh_force_N.columns:
            torque = float(mesh_torque_Nm(np.max(np.abs(sim.mesh_force_N[mesh].to_numpy())),
                                          sim.mesh_base_radii_mm[mesh][0]))
            if torque > peaks.get(mesh, (-1.0, 0.0))[0]:
                peaks[mesh] = (torque, float(speed))
    return peaks


def dynamics_check(system: System, design: TrainDesign, judged: DynamicPeaks, speeds_rpm, **run) -> dict:
    """Whether the dynamic peaks the requirements judged are ``design``'s own: the design's train simulated again
    (:func:`design_peak_torques_Nm`) when its macro geometry differs from the packaged spur train's, the largest
    relative change of a peak mesh torque against :data:`DYNAMICS_AGREEMENT`. The flank reliefs and the joint fits
    do not enter the torsional model, so for the packaged spur macro the judged peaks are the design's own."""
    base = system.train("spur")
    tr = design.train
    same = (float(tr.helix_angle_deg) == 0.0
            and abs(float(tr.profile_shifts[tr.root_gear]) - float(base.profile_shifts[base.root_gear])) < 1e-9)
    if same:
        return {"simulated": False, "max_change_percent": 0.0, "agrees": True,
                "note": "the design's train is the simulated spur train (reliefs and joint fits are not in the "
                        "torsional model): the judged dynamic peaks are its own"}
    own = design_peak_torques_Nm(system, design, speeds_rpm, **run)
    change = {m: abs(own[m][0] / t - 1.0) for m, (t, _) in judged.mesh_torques_Nm.items() if m in own and t > 0}
    worst = max(change.values(), default=0.0)
    return {"simulated": True, "peaks_Nm": {m: v[0] for m, v in own.items()},
            "change_percent": {m: 100 * v for m, v in change.items()}, "max_change_percent": 100 * worst,
            "agrees": worst <= DYNAMICS_AGREEMENT, "own": own,
            "note": f"the design's own train simulated again: peak mesh torques within {100 * worst:.3g} % of those "
                    f"judged (limit {100 * DYNAMICS_AGREEMENT:g} %)"}


__all__ = ["DESIGN_LOOP_ROUNDS", "carried_dynamic_requirements", "dynamics_design_loop", "DYNAMICS_AGREEMENT", "design_peak_torques_Nm", "dynamics_check", "codesign_candidates", "dynamic_peaks", "helical_dynamic_peaks", "timing_recommendation"]
