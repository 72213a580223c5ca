"""The thesis scene: a diesel engine's helical timing train redesigned as a spur train in the same housing.

Runs on the packaged default data (``gearopt/data/default_train.toml``) and writes to ``out/cam_gear_walkoff/``:
CSV tables, ``report.md`` and ``result.json`` (headline numbers with units). Stages so far:

1. macro design: helical -> standard spur errors (thesis Table 3.1), sum of shifts per mesh at the fixed centre
   distances (3.2), shift per gear propagated through the train (3.3), percentage changes (3.4), contact ratios,
   backlash and geometry checks of every mesh, for the spur redesign and the helical baseline;
2. profile-shift split of the root mesh (crank-cam) optimised with Ipopt (maximum minimum tip thickness subject to
   worst-case contact ratio, undercut and ISO/TR 4467 limits), against the ISO/TR 4467 split;
3. contact: for crank-cam, cam-ac and cam-fp, the exact LTCA of the helical baseline and the unmodified spur pair at
   the design torque, the spur microgeometry minimising the largest PPTE over the design-torque range (Ipopt on the
   smooth LTCA; contact-stress and loaded-contact-ratio limits), and the comparison the thesis shows in Figs.
   4.9-4.15/4.22: TE, load intensity, contact stress, flash temperature, root stress, Harris maps, percentage change;
4. rating: ISO 6336-2/-3 method B contact and root stresses and safety factors per mesh, helical and spur;
5. joints: shaft-hub joint capacities, torque and walk-off margins (nominal and weakest fit), blanks, webs;
6. dynamics: the torsional model of the timing train, helical vs spur, with and without backlash, at rated speed
   and overspeed (thesis Figs. 4.3-4.5), and the joints' torque and axial margins over a speed sweep;
7. failure reproduction (reported first): the keyed press fits as friction elements in the torsional model over
   speed up to overspeed, damper state and fit; the walk-off probability by Monte Carlo; helical vs spur and
   helical alternatives.
8. trade-off: the front of the crank-cam tip relief's PPTE against its loaded contact ratio, the sensitivity table of
   the optimised design and its robustness under the tolerances (``gearopt.studies.scene_study``).

Usage: ``python problems/cam_gear_walkoff.py [--quick] [--out DIR] [--data FILE]`` (``--data``: your own train in
the data-file format of the packaged default, ``gearopt/data/default_train.toml``).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import logging
import os
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

import gearopt as go
from gearopt.cli import run_script
from gearopt.data import load_thesis_tables, train_from_data
from gearopt.design.shift_distribution import optimise_shift_split
from gearopt.geometry.forces import mesh_torque_Nm
from gearopt.data import values as data_values
from gearopt.report import contact_headlines as headlines
from gearopt.report import ltca_figures as figs
from gearopt.report.failure_figures import plot_failure_creep_map
from gearopt.report.figure_writer import background_figures, plot_later
from gearopt.studies.background import children_die_with_this_process, side_process
from gearopt.report import to_markdown, write_table
from gearopt.report.joint_tables import blank_table, joint_table, web_table
from gearopt.report.rating_tables import rating_table
from gearopt.cases.timing_train.recommendation import dynamic_peaks
from gearopt.cases.timing_train.summary import QUICK_BANNER, build_summary, eng, headlines_markdown, summary_markdown
from gearopt.studies import DESIGNS, mesh_contact_study
from gearopt.cases.timing_train.macro_design import (change_table, conversion_table, mesh_check_table, shift_table,
                                         sum_shift_table)

DEFAULT_OUT = Path("out") / "cam_gear_walkoff"
LOG = logging.getLogger("cam_gear_walkoff")


class StageTimings(dict):
    """``{stage: elapsed [s]}`` that logs each stage as it is recorded: start and end clock time and elapsed;
    :meth:`stage` also logs the start (a long stage is then visible while it runs)."""

    @contextlib.contextmanager
    def stage(self, stage: str):
        """Time the block as ``stage``, logging its start now and its end when the block ends."""
        LOG.info("stage %-36s started (%s)", stage, time.strftime("%H:%M:%S"))
        t0 = time.perf_counter()
        yield
        self[stage] = time.perf_counter() - t0

    def __setitem__(self, stage: str, elapsed_s: float) -> None:
        super().__setitem__(stage, elapsed_s)
        end = time.time()
        start = time.strftime("%H:%M:%S", time.localtime(end - elapsed_s))
        LOG.info("stage %-36s %7.2f s  (%s -> %s)", stage, elapsed_s, start,
                 time.strftime("%H:%M:%S", time.localtime(end)))


def macro_design(system: go.System, thesis: dict) -> dict:
    """Stage 1: the macro-design tables of the spur redesign and the helical baseline."""
    spur = train_from_data(system.data, "spur")
    helical = train_from_data(system.data, "helical")
    iso = go.GearTrain(gears=spur.gears, meshes=spur.meshes, rack=spur.rack, helix_angle_deg=0.0,
                       root_mesh=spur.root_mesh, root_gear=spur.root_gear, root_shift_split=0.5)
    limits = dict(min_contact_ratio=1.2, min_tip_thickness_ratio=0.2)
    return {
        "trains": {"spur": spur, "helical": helical},
        "tables": {
            "table_3_1_helical_to_spur": conversion_table(helical, thesis),
            "table_3_2_sum_profile_shift": sum_shift_table(spur, thesis),
            "table_3_3_profile_shift": shift_table(spur, thesis, iso_split=iso),
            "table_3_4_percentage_change": change_table(spur, thesis),
            "mesh_checks_spur": mesh_check_table(spur, **limits),
            "mesh_checks_helical": mesh_check_table(helical, **limits),
            "gears_spur": spur.gear_table(),
            "gears_helical": helical.gear_table(),
        },
        "limits": limits,
    }


TOOTH_COUNT_COLUMNS = ["rank", "teeth_crank", "teeth_cam", "teeth_ac", "teeth_fp", "teeth_lpi", "teeth_lpg",
                       "ratio_error_crank-lpi_percent", "max_abs_ratio_error_percent", "min_worst_case_contact_ratio",
                       "min_tip_thickness_mm", "limiting", "status"]


def tooth_count_stage(system: go.System, spur: go.GearTrain, lube_tolerance_percent: float = 3.0) -> dict:
    """Stage 1b: integer tooth counts at the fixed centre distances (thesis Table 3.1): every assignment within
    ``lube_tolerance_percent`` of the original helical ratios on the lube-pump branch (0 % elsewhere, the cam
    exactly 2:1), screened for sums of shifts and ISO/TR 4467 limits, each solved for the root shift split that
    maximises the smallest worst-case contact ratio (Ipopt, warm-started), ranked."""
    from gearopt.design.tooth_counts import enumerate_tooth_counts, tooth_count_study

    enumeration = enumerate_tooth_counts(spur, reference="helical_original", system=system,
                                         ratio_tolerance_percent={"crank-lpi": lube_tolerance_percent})
    study = tooth_count_study(spur, enumeration=enumeration, objective="max_min_worst_case_contact_ratio")
    return {"study": study, "lube_tolerance_percent": lube_tolerance_percent,
            "rejected_by_stage": enumeration.rejected["stage"].value_counts().to_dict()}


def shift_split_study(spur: go.GearTrain, mesh: str = "crank-cam") -> dict:
    """Stage 2: the optimised profile-shift split of one mesh at its fixed centre distance."""
    return optimise_shift_split(spur.pairs[mesh], min_contact_ratio=1.2, objective="max_min_tip_thickness")


RATED_MESHES = ("crank-cam", "cam-ac", "cam-fp", "crank-lpi", "lpi-lpg")


def rating_at_dynamic_peaks(system: go.System, trains: dict, design_torques: pd.DataFrame) -> dict:
    """ISO 6336 rating of every rated mesh at the largest dynamic mesh torque the dynamics computed (with backlash,
    over the simulated speeds and recorded cycles), at the speed where it occurs. The torque already holds the
    engine's excitation and the mesh's own dynamics, so K_A = 1 and K_v = 1 (ISO 6336-1 method A: dynamic loads from
    a comprehensive analysis); the other factors are computed. Rated for endurance at that peak (conservative: the
    peak is not reached every load cycle; a load spectrum, ISO 6336-6, would credit that)."""
    from gearopt.rating import iso6336_train_table

    grades = {g: v["accuracy_grade_iso1328"] for g, v in data_values(system.data)["gears"].items()}
    out = {}
    lash = design_torques[design_torques["backlash"]]
    for kind, rows in lash.groupby("train"):
        worst = rows.loc[rows.groupby("mesh")["peak_dynamic_torque_Nm"].idxmax()]
        tables = []
        for _, r in worst.iterrows():
            t = iso6336_train_table(trains[kind], {r["mesh"]: r["peak_dynamic_torque_Nm"]}, r["speed_rpm"],
                                    application_factor=1.0, accuracy_grades=grades, K_v=1.0)
            t.insert(1, "crank_speed_rpm", r["speed_rpm"])
            t.insert(2, "cycles", r["cycles"])
            t.insert(3, "cycle_peak_mean_Nm", r["cycle_peak_mean_Nm"])
            t.insert(4, "cycle_peak_std_Nm", r["cycle_peak_std_Nm"])
            tables.append(t)
        out[f"{kind}_dynamic_peak"] = pd.concat(tables, ignore_index=True)
    return out


def rating_stage(system: go.System, trains: dict) -> dict:
    """Stage 4: ISO 6336-2/-3 method B contact and root stresses with safety factors per mesh at the design torques,
    helical baseline and spur redesign (K_A from the data, other load factors 1)."""
    from gearopt.rating import iso6336_train_table

    loads = data_values(system.data)["design_loads"]
    design = system.design_torques_Nm()
    torques = {mesh: design[mesh] for mesh in RATED_MESHES}
    out = {kind: rating_table(trains[kind], torques, K_A=loads["application_factor_K_A"])
           for kind in ("helical", "spur")}
    grades = {g: v["accuracy_grade_iso1328"] for g, v in data_values(system.data)["gears"].items()}
    for kind in ("helical", "spur"):  # every factor computed (ISO 6336-1/-2/-3, ISO/TS 6336-20/-21), endurance
        out[f"{kind}_computed_factors"] = iso6336_train_table(trains[kind], torques, loads["speed_rpm"],
                                                              application_factor=loads["application_factor_K_A"],
                                                              accuracy_grades=grades)
    return out


def joint_stage(system: go.System) -> dict:
    """Stage 5: shaft-hub joint capacities and slip/walk-off margins at the design loads (nominal fit, and the
    weakest case: minimum interference, DIN 7190 smoothing loss, highest nut factor), blank inertias and web
    fatigue, for the helical baseline and the spur redesign."""
    out = {}
    for kind in ("helical", "spur"):
        out[kind] = {
            "joints_nominal": joint_table(system, kind, "design"),
            "joints_weakest": joint_table(system, kind, "design", interference="min", nut_factor="max",
                                          smoothing=True),
            "blanks": blank_table(system, kind),
            "webs": web_table(system, kind, "design"),
        }
    return out


def write_joints(out: Path, joints: dict) -> tuple[list[str], dict]:
    lines = ["## Shaft-hub joints, walk-off margins, blanks and webs at the design loads", "",
             "Margins are capacity / demand (inf where the demand is zero: spur gears have no axial thrust). "
             "`weakest`: minimum ISO 286 interference, DIN 7190 smoothing loss, highest nut factor.", ""]
    result: dict = {}
    for kind, tables in joints.items():
        for name, df in tables.items():
            write_table(df, out, f"{name}_{kind}")
            lines += [f"### {kind}: {name.replace('_', ' ')}", "", to_markdown(df), ""]
        for case in ("joints_nominal", "joints_weakest"):
            df = tables[case]
            for gear, row in df.set_index("gear").iterrows():
                entry = result.setdefault(str(gear), {}).setdefault(kind, {})
                entry[case.replace("joints_", "")] = {
                    "torque_Nm": float(row["torque_Nm"]), "axial_force_N": float(row["axial_force_N"]),
                    "torque_capacity_Nm": float(row["torque_capacity_Nm"]),
                    "axial_capacity_N": float(row["axial_capacity_N"]),
                    "torque_margin": _json_number(row["torque_margin"]),
                    "axial_margin": _json_number(row["axial_margin"]),
                    "hub_yield_safety": _json_number(row.get("hub_yield_safety", float("inf")))}
    return lines, result


def _json_number(v) -> float | str:
    v = float(v)
    return "inf" if v == float("inf") else v


DYNAMIC_JOINTS = ("crank", "cam", "ac", "fp")
RECORDED_CYCLES = 5
"""Engine cycles recorded per backlash run (after one run-in cycle): with backlash the response is not periodic,
so peaks are taken over these cycles and their cycle-to-cycle spread is reported (``--quick``: one cycle)."""
LASH_RTOL = 1e-3
"""CVODES tolerance of the backlash runs: the rattling response is chaotic, only its statistics converge, and at
this tolerance the per-cycle RMS and peak crank-cam force agree with a tight reference within their spread
(``benchmarks/results/dynamics_speed.json``) at under half the default's steps."""


def dynamics_stage(system: go.System, quick: bool = False) -> dict:
    """Stage 6: torsional dynamics of the timing train (helical baseline and spur redesign), with and without
    backlash, at rated speed and overspeed (thesis Figs. 4.3-4.5), and a speed sweep with the walk-off margins of
    the cam, AC and FP joints over speed."""
    from gearopt.cases.timing_train import default_timing_model
    from gearopt.dynamics import speed_sweep

    engine = data_values(system.data)["engine"]
    speeds = ((engine["overspeed_test_speed_rpm"],) if quick
              else (engine["rated_speed_rpm"], engine["overspeed_test_speed_rpm"]))
    sweep_speeds = ((engine["idle_speed_rpm"], engine["overspeed_test_speed_rpm"]) if quick
                    else (engine["idle_speed_rpm"], engine["peak_torque_speed_rpm"], engine["rated_speed_rpm"],
                          engine["overspeed_test_speed_rpm"]))
    run = dict(cycles=1, run_in_cycles=0 if quick else 1)            # without backlash the response is periodic
    lash_run = dict(run, cycles=1 if quick else RECORDED_CYCLES)
    out: dict = {"runs": {}, "sweeps": {}, "models": {}, "speeds_rpm": speeds}
    for kind in ("helical", "spur"):
        model = default_timing_model(kind, system=system)
        for speed in speeds:
            for lash in (False, True):
                out["runs"][(kind, speed, lash)] = model.simulate(speed_rpm=speed, backlash=lash,
                                                                  **(dict(lash_run, rtol=LASH_RTOL) if lash else run))
        out["sweeps"][kind] = speed_sweep(model, sweep_speeds, backlash=(True,), joints=DYNAMIC_JOINTS,
                                          rtol=LASH_RTOL, **lash_run)  # re-uses the lash runs above
        out["models"][kind] = model
    out["campbell_speeds_rpm"] = (engine["idle_speed_rpm"], engine["overspeed_test_speed_rpm"])
    return out


JOINT_TARGET_MARGIN = 1.5
"""Slip margin (capacity / dynamic peak demand) the joint-sizing stage asks of every joint over the speed sweep."""


def joint_sizing_stage(system: go.System, trains: dict, dyn: dict, target_margin: float = JOINT_TARGET_MARGIN) -> dict:
    """Stage 6b: size every timing-gear joint (crank, cam press fits; AC, FP tapers) for ``target_margin`` against
    the dynamic demands of the speed sweep (peak joint torque and axial force at every speed, with backlash), at
    the weakest tolerance / nut factor (:func:`gearopt.design.joint_sizing.size_joint`). A joint that no admissible
    design can size fails typed; the elastic solve then reports how far each limit must move."""
    from gearopt.design.joint_sizing import JointDemand, size_joint
    from gearopt.errors import SolveError

    rows, results = [], {}
    for kind, sweep in dyn["sweeps"].items():
        joints = sweep[sweep["element_type"] == "joint"]
        for joint in DYNAMIC_JOINTS:
            gear = data_values(system.data)["joints"][joint]["gear"]
            ratio = abs(float(trains[kind].speed_ratios[gear]))
            sel = joints[joints["element"] == f"joint:{joint}"]
            demands = [JointDemand(torque_Nm=float(r["peak_torque_Nm"]), axial_force_N=float(r["peak_axial_force_N"]),
                                   speed_rpm=ratio * float(r["speed_rpm"]), name=f"{r['speed_rpm']:g}rpm")
                       for _, r in sel.iterrows()]
            row = {"train": kind, "joint": joint, "target_margin": target_margin,
                   "peak_torque_Nm": max(d.torque_Nm for d in demands),
                   "peak_axial_force_N": max(d.axial_force_N for d in demands),
                   "present_min_torque_margin": float(sel["min_torque_margin"].min()),
                   "present_min_axial_margin": float(sel["min_axial_margin"].min())}
            try:
                sized = size_joint(system, joint, demands, target_margin=target_margin, elastic_on_failure=True)
            except SolveError as exc:
                relax = getattr(exc, "relaxations", None)
                worst = (f"{relax.iloc[0]['name']} by {relax.iloc[0]['relaxation']:.3g} {relax.iloc[0]['unit']}"
                         if relax is not None and len(relax) else "; ".join(v.name for v in exc.violated[:3]))
                row.update(status=exc.status, result="no admissible design", must_relax=worst)
            else:
                v = sized.values
                row.update(status=sized.solve.status, must_relax="",
                           result=(f"interference >= {v['required_min_interference_um']:.1f} um, fit "
                                   f"{sized.fit['fit'] if sized.fit else 'none in ISO 286'}"
                                   if sized.joint_type == "press_fit" else f"nut torque {v['nut_torque_Nm']:.1f} N m"),
                           min_margin=float(sized.margins.filter(like="margin").min(numeric_only=True).min()))
                results[(kind, joint)] = sized
            rows.append(row)
    return {"table": pd.DataFrame(rows), "results": results}


def dynamic_design_torques(system: go.System, dyn: dict) -> pd.DataFrame:
    """Mesh torques from the dynamics against the design torques of the data: per mesh and train, the peak
    |mesh force| x base radius of the mesh's first gear at each simulated speed, without and with backlash, and the
    ratio to the top of the design-torque range the microgeometry is optimised over (``[design_loads]``); with the
    mean and standard deviation of the per-cycle peaks over the recorded cycles (the spread of a non-periodic
    response)."""
    loads = data_values(system.data)["design_loads"]
    top = max(loads["torque_range_fractions"])
    design = system.design_torques_Nm()
    rows = []
    for (kind, speed, lash), sim in dyn["runs"].items():
        for mesh in RATED_MESHES:
            if mesh not in sim.mesh_force_N.columns:
                continue
            radius_mm = sim.mesh_base_radii_mm[mesh][0]
            force = np.abs(sim.mesh_force_N[mesh].to_numpy())
            per_cycle = mesh_torque_Nm(force[: force.size - force.size % sim.cycles].reshape(sim.cycles, -1)
                                       .max(axis=1), radius_mm)
            torque = float(mesh_torque_Nm(np.max(force), radius_mm))
            rows.append({"train": kind, "speed_rpm": speed, "backlash": lash, "mesh": mesh,
                         "design_torque_Nm": design[mesh], "range_top_Nm": top * design[mesh],
                         "peak_dynamic_torque_Nm": torque, "ratio_to_range_top": torque / (top * design[mesh]),
                         "cycles": int(sim.cycles), "cycle_peak_mean_Nm": float(per_cycle.mean()),
                         "cycle_peak_std_Nm": float(per_cycle.std(ddof=1)) if per_cycle.size > 1 else 0.0})
    return pd.DataFrame(rows)


def write_dynamics(out: Path, dyn: dict, design_torques: pd.DataFrame | None = None) -> tuple[list[str], dict]:
    from gearopt.report.dynamics_figures import campbell_data, plot_campbell_data, plot_force_traces

    lines = ["## Timing-train dynamics: contact forces, helical vs spur, without and with backlash", ""]
    speeds = dyn["speeds_rpm"]
    traces, rows = {}, []
    for speed in speeds:
        for lash in (False, True):
            panel = traces.setdefault(f"crank-cam, {speed:g} rpm, {'with' if lash else 'no'} backlash", {})
            for kind in ("helical", "spur"):
                sim = dyn["runs"][(kind, speed, lash)]
                f = sim.frame("mesh_force_N", "crank_angle_deg")["crank-cam"]
                panel[kind] = ((f.index - f.index[0]).to_numpy(), f.to_numpy() / 1000.0)
                summ = sim.summary()
                for mesh, r in summ.iterrows():
                    rows.append({"train": kind, "speed_rpm": speed, "backlash": lash, "mesh": mesh,
                                 "peak_drive_force_N": r["peak_drive_force_N"],
                                 "peak_back_force_N": r["peak_back_force_N"], "rms_force_N": r["rms_force_N"],
                                 "peak_axial_force_N": r["peak_axial_force_N"]})
    path = plot_later(plot_force_traces, out / "figures" / "dynamics_crank_cam_force.png", traces)
    table = pd.DataFrame(rows)
    write_table(table, out, "dynamics_mesh_forces")
    lines += [f"![contact forces]({path.relative_to(out)})", "", to_markdown(table), ""]
    result: dict = {"mesh_forces": table.to_dict(orient="records"), "joint_margins_over_speed": {}}
    if design_torques is not None:
        write_table(design_torques, out, "dynamic_design_torques")
        lines += ["### Dynamic mesh torques against the design-torque range", "",
                  "Peak |mesh force| x base radius of the mesh's first gear. Without backlash the dynamic peaks are "
                  "the inputs of the design torques; with backlash the impacts exceed them (the thesis' overspeed "
                  "case).", "", to_markdown(design_torques), ""]
        result["design_torques"] = design_torques.to_dict(orient="records")
    speeds_c = dyn["campbell_speeds_rpm"]
    for kind, model in dyn["models"].items():
        campbell = campbell_data(model, np.linspace(speeds_c[0], speeds_c[1], 50))
        path = plot_later(plot_campbell_data, out / "figures" / f"campbell_{kind}.png", campbell,
                          title=f"{kind} train: Campbell diagram")
        # the figure's crossings are campbell_table(model, speeds_c): every crossing in the speed range lies below
        # the figure's frequency cap (1.1 x the top order at the top speed), so computed once for both
        crossings = campbell["crossings"]
        write_table(crossings, out, f"campbell_crossings_{kind}")
        lines += [f"### Campbell diagram ({kind})", "", f"![Campbell]({path.relative_to(out)})", "",
                  f"{len(crossings)} crossings of natural frequencies with engine orders between {speeds_c[0]:g} and "
                  f"{speeds_c[1]:g} rpm (`campbell_crossings_{kind}.csv`).", ""]
    lines += ["### Walk-off and slip margins over speed (with backlash)", "",
              "With backlash the response is not periodic: each recorded engine cycle has its own worst margin. "
              "`min_torque_margin` is the worst over all recorded cycles; `torque_margin_cycle_median` and "
              "`torque_margin_cycle_best` are the median and the best of the per-cycle worst margins (equal for a "
              "periodic response).", ""]
    for kind, sweep in dyn["sweeps"].items():
        write_table(sweep, out, f"speed_sweep_{kind}")
        joints = sweep[sweep["element_type"] == "joint"]
        cols = [c for c in ("element", "speed_rpm", "peak_torque_Nm", "peak_axial_force_N", "min_torque_margin",
                            "torque_margin_cycle_median", "torque_margin_cycle_best", "min_axial_margin",
                            "max_slip_utilisation", "cycles") if c in joints.columns]
        lines += [f"#### {kind}", "", to_markdown(joints[cols]), ""]
        for _, r in joints.iterrows():
            joint = str(r["element"]).removeprefix("joint:")
            entry = result["joint_margins_over_speed"].setdefault(joint, {}).setdefault(kind, [])
            entry.append({"speed_rpm": float(r["speed_rpm"]), "torque_margin": _json_number(r["min_torque_margin"]),
                          "axial_margin": _json_number(r["min_axial_margin"]),
                          "peak_torque_Nm": float(r["peak_torque_Nm"]),
                          "peak_axial_force_N": float(r["peak_axial_force_N"]), "cycles": int(r["cycles"]),
                          **{f"{k}_cycle_{stat}": _json_number(r[f"{k}_cycle_{stat}"])
                             for k in ("torque_margin", "axial_margin") for stat in ("worst", "median", "best")}})
    return lines, result


CONTACT_MESHES = ("crank-cam", "cam-ac", "cam-fp")


def contact_stage(system: go.System, trains: dict, quick: bool = False, on_study=None) -> dict:
    """Stage 3: helical vs unmodified spur vs optimised spur for the three meshes of the thesis' chapter 4;
    ``on_study(mesh, study)`` is called as each mesh's study ends (the main job writes its section and hands its
    figures to the figure writer then, so they render while the next mesh is solved)."""
    loads = data_values(system.data)["design_loads"]
    lub = data_values(system.data)["lubrication"]
    limits = data_values(system.data)["design_limits"]
    required = system.requirements
    options = dict(crank_speed_rpm=loads["speed_rpm"], torque_fractions=loads["torque_range_fractions"],
                   bulk_temperature_C=lub["oil_temperature_C"], friction_coefficient=lub["mean_friction_coefficient"],
                   max_root_stress_MPa=limits["max_root_stress_MPa"],
                   max_flash_temperature_C=required.max_contact_temperature_C,
                   min_loaded_contact_ratio=required.min_loaded_contact_ratio,
                   stop_without_progress=True)     # evidence beside the recommended design: 94 -> 21.5 CPU-s
    if quick:
        options.update(positions=80, nlp_positions=20, harris_points=4, helical_slices=5, starts=1, max_refinements=1)
    studies = {}
    design = system.design_torques_Nm()
    for mesh in CONTACT_MESHES:
        studies[mesh] = mesh_contact_study(trains, mesh, design[mesh], **options)
        if on_study is not None:
            on_study(mesh, studies[mesh])
    return studies


def recommendation_stage(system: go.System, codesign: dict, design_torques: pd.DataFrame, dynamics: dict,
                         calibrated_inputs: dict | None = None, quick: bool = False) -> tuple[dict, object]:
    """The one answer: every design of the co-design study judged on every requirement of the data's
    ``[requirements]`` with the exact models (contact of the three contact meshes over their ranges, ISO 6336 at
    the design torques and at the dynamic peaks, joints at the design load and over speed), the best chosen
    (:func:`gearopt.cases.timing_train.recommendation.timing_recommendation`; with ``calibrated_inputs`` from the
    failure reproduction's calibration its joint and dynamic rows judged again on them), in the dynamics design loop
    (:func:`gearopt.cases.timing_train.recommendation.dynamics_design_loop`: the co-design solved again with the
    recommended design's own peaks while they differ by more than 2 % from those its NLPs carried). Returns
    ``Recommendation.as_json()`` with ``"dynamics_loop"`` (one row per round) and the co-design section: the one
    given, or (report lines, JSON) of the last re-solve."""
    from gearopt.cases.timing_train.recommendation import dynamics_design_loop

    short = all(s.cycles == 1 for (k, _, lash), s in dynamics["runs"].items() if lash)
    resolved: list = []

    def solve(peaks):
        study = codesign_stage(system, quick=quick, dynamic_peaks=peaks)
        resolved[:] = [(study.report_lines(), json.loads(json.dumps(study.to_json(), default=float)))]
        return resolved[0][1]

    rec, _, history = dynamics_design_loop(
        system, solve, codesign, contact_meshes=CONTACT_MESHES, design_torques=design_torques,
        sweep=dynamics["sweeps"]["spur"], dynamics_speeds_rpm=dynamics["speeds_rpm"],
        dynamics_run=dict(cycles=1 if short else RECORDED_CYCLES, run_in_cycles=0 if short else 1, rtol=LASH_RTOL),
        calibrated_inputs=calibrated_inputs)
    last = history[-1]
    rec.notes.append(
        f"dynamics in the design loop: {len(history)} co-design solve(s); "
        + ("the dynamic-peak requirements carried by its NLPs: " + ", ".join(last["carried"])
           if last["carried"] else "no dynamic-peak requirement could be carried (no design of the space meets "
                                   "it: see its reach), so the designs do not depend on the peaks")
        + f"; the recommended design's own peaks {'agree' if last['agrees'] else 'differ'} within "
          f"{last['max_change_percent']:.3g} %")
    out = json.loads(json.dumps({**rec.as_json(), "dynamics_loop": history}, default=_json_default))
    return out, (resolved[0] if resolved else codesign)


def _json_default(v):
    if isinstance(v, (np.floating, np.integer, np.bool_)):
        return v.item()
    raise TypeError(f"{type(v).__name__} is not JSON serialisable")


def codesign_stage(system: go.System, quick: bool = False, dynamic_peaks: dict | None = None):
    """Stage: co-design of the spur train and a low-helix alternative (profile shift, helix angle, per-flank tip
    relief, walk-off margins in one NLP) beside the sequential design (gearopt.cases.timing_train.codesign); quick: the
    spur option, one load case, no refinement. The main job caps the co-design's refinement at 1 re-solve and slices
    helical faces 11 times without raising them (run time: the low-helix co-design solve alone takes minutes; 7
    slices left the 8 deg meshes' root stress 1.2-1.6 % off the exact LTCA's, above the 1 % stress tolerance;
    whether each design verified is reported per option); the sequential design (lifted contact form, fast) gets up
    to 3 re-solves. problems/codesign.py runs the study at its defaults. ``dynamic_peaks``: {mesh: (peak torque
    [N m], crank speed [rpm])} of the spur train's dynamics with backlash: S_H and S_F there join the NLPs where a
    design of the option's space meets them (else the study reports the space's reach)."""
    from gearopt.cases.timing_train import codesign_study

    return codesign_study(system, quick=quick, options=("spur",) if quick else ("spur", "low_helix"),
                          dynamic_peaks=dynamic_peaks,
                          ltca_options=None if quick else {"max_refinements": 1, "helical_slices": 11,
                                                           "max_helical_slices": 11},
                          sequential_options=None if quick else {"max_refinements": 3})


CONTACT_HEADER = ["## Contact: helical baseline vs unmodified spur vs optimised spur", "",
                  "Evidence: each mesh's flanks optimised alone (a flank shared by two meshes gets two reliefs "
                  "here). The recommended design's flanks -- one relief per flank -- are in the design sheet at the "
                  "top.", ""]


def write_contact(out: Path, studies: dict, *, quick: bool = False) -> tuple[list[str], dict]:
    """Contact tables and figures; returns the report lines and the result.json entries. ``quick``: the flank maps
    and the per-load-case change chart of the first mesh only (the largest figures)."""
    lines, result = list(CONTACT_HEADER), {}
    for index, (mesh, st) in enumerate(studies.items()):
        mesh_lines, result[mesh] = write_contact_mesh(out, mesh, st, every_figure=not quick or index == 0)
        lines += mesh_lines
    return lines, result


def write_contact_mesh(out: Path, mesh: str, st, *, every_figure: bool = True) -> tuple[list[str], dict]:
    """One mesh's part of :func:`write_contact`: its tables, its figures (handed to the figure writer) and its report
    lines and ``result.json`` entry; ``every_figure=False``: no flank maps and no per-load-case change chart."""
    lines = []
    tag = mesh.replace("-", "_")
    write_table(st.summary, out, f"contact_{tag}")
    opt = st.optimisation
    write_table(opt.table, out, f"microgeometry_{tag}_exact_ltca")
    # built and rendered by the figure writer's worker (plot_later) while this process goes on
    fig_te = plot_later(figs.plot_transmission_error, out / "figures" / f"te_{tag}.png",
                        {d: st.ltca[d] for d in DESIGNS}, title=f"{mesh}: static TE at {st.torque_Nm:g} N m")
    fig_tt = plot_later(figs.plot_transmission_error, out / "figures" / f"te_torques_{tag}.png",
                        {f"{t:g} N m": r for t, r in sorted(opt.exact["optimised"].items())},
                        title=f"{mesh}: optimised spur, static TE at the load cases")
    fig_h = plot_later(figs.plot_harris_map, out / "figures" / f"harris_{tag}.png", st.harris,
                       title=f"{mesh}: Harris map", design_range_Nm=(min(opt.torques_Nm), max(opt.torques_Nm)),
                       design_torque_Nm=st.torque_Nm)
    fig_maps = plot_later(figs.plot_flank_grid, out / "figures" / f"flank_maps_{tag}.png",
                          {d: st.ltca[d] for d in DESIGNS},
                          title=f"{mesh}: load intensity, contact stress, contact temperature, root stress of "
                                f"gear 1 over its flank") if every_figure else None
    change = st.summary.set_index("design").drop(columns=["loaded_contact_ratio"])
    fig_c = plot_later(figs.plot_percentage_change, out / "figures" / f"change_{tag}.png", change, "helical",
                       title=f"{mesh}: change against helical")
    fig_cl = plot_later(figs.plot_percentage_change, out / "figures" / f"change_load_cases_{tag}.png",
                        opt.table.set_index("design"), "unmodified", by="torque_Nm",
                        title=f"{mesh}: change against the unmodified spur pair at every load case (exact LTCA)"
                        ) if every_figure else None
    lines += [f"### {mesh} at {st.torque_Nm:g} N m on the driving gear, {st.speed_rpm:g} rpm", "",
              to_markdown(st.summary), "",
              "Optimised microgeometry (linear tip relief blended over "
              f"{opt.microgeometry.relief_smoothing_deg:g} deg at its start): "
              + ", ".join(f"{k} {v:.3f}" for k, v in opt.values.items()), "",
              f"Ipopt: {opt.solve.status}, {opt.solve.iterations} iterations, {opt.solve.solve_time_s:.3f} s; "
              f"load cases {', '.join(f'{t:g}' for t in opt.torques_Nm)} N m. Exact-LTCA check of the designs:",
              "", to_markdown(opt.table), "",
              f"![TE]({fig_te.relative_to(out)}) ![TE over torque]({fig_tt.relative_to(out)}) "
              f"![Harris]({fig_h.relative_to(out)}) ![change]({fig_c.relative_to(out)})"
              + (f" ![change at every load case]({fig_cl.relative_to(out)})" if fig_cl else ""), ""]
    lines += [f"![flank maps]({fig_maps.relative_to(out)})", ""] if fig_maps else []
    entry = st.headline()
    entry["optimised_microgeometry"] = {k: v for k, v in opt.values.items()}
    entry["optimised_microgeometry"]["relief_shape"] = opt.microgeometry.relief_shape
    entry["optimised_microgeometry"]["relief_smoothing_deg"] = opt.microgeometry.relief_smoothing_deg
    entry["constraint_margins"] = headlines.nlp_constraint_margins(opt)
    entry["verified_margins"] = headlines.verified_margins(opt)
    entry["ppte_over_range"] = headlines.ppte_over_range(opt)
    entry["smooth_exact_gap"] = headlines.smooth_exact_gap(opt)
    entry["tip_relief_drawing"] = headlines.tip_relief_drawing(st.ltca["spur_unmodified"].layout.pair,
                                                             opt.values)
    lines += headlines_markdown(entry)
    entry["design_torque_Nm"] = st.torque_Nm
    entry["driving_gear_speed_rpm"] = st.speed_rpm
    entry["stage_time_s"] = st.times_s
    return lines, entry


def write_rating(out: Path, ratings: dict) -> tuple[list[str], dict]:
    lines = ["## Strength rating (ISO 6336-2/-3 method B) at the design torques", ""]
    result = {}
    for kind, df in ratings.items():
        write_table(df, out, f"rating_{kind}")
        cols = [c for c in ("mesh", "torque_Nm", "sigma_H_MPa", "S_H", "sigma_F_1_MPa", "sigma_F_2_MPa", "S_F_1",
                            "S_F_2") if c in df.columns]
        if kind.endswith("_dynamic_peak"):
            cols = ["mesh", "torque_Nm", "crank_speed_rpm", "cycles", "cycle_peak_mean_Nm", "cycle_peak_std_Nm",
                    "K_Hbeta", "K_Halpha", "S_H_1", "S_H_2", "S_F_1", "S_F_2", "S_B", "S_intS"]
            lines += [f"{kind}: at the largest dynamic mesh torque with backlash (peak over the simulated speeds "
                      f"and recorded cycles; per-cycle peaks mean and standard deviation beside it), K_A = K_v = 1 "
                      f"(the dynamics holds them), other factors computed, endurance.", ""]
        elif kind.endswith("_computed_factors"):
            cols = ["mesh", "torque_Nm", "speed_1_rpm", "N_L_1", "N_L_2", "K_v", "K_Hbeta", "K_Fbeta", "K_Halpha",
                    "Z_NT_1", "Z_L_1", "Z_v_1", "Z_R_1", "Y_NT_1", "Y_deltarelT_1", "Y_RrelT_1", "Y_X_1", "S_H_1",
                    "S_H_2", "S_F_1", "S_F_2", "S_B", "S_intS"]
            lines += [f"{kind}: every factor computed (`gearopt.rating.rate_iso6336`), K_A from the data, endurance "
                      f"(N_L = 1e10), lubricant {df['lubricant'].iloc[0]}.", ""]
        lines += [f"### {kind}", "", to_markdown(df[cols]), ""]
        result[kind] = {str(r["mesh"]): {c: float(r[c]) for c in cols if c != "mesh"} for _, r in df.iterrows()}
    return lines, result


FAILURE_JOINTS = ("cam", "crank")


def failure_reproduction_stage(system: go.System, quick: bool = False) -> dict:
    """Stage 0: reproduce the failure -- the shaft-hub joints as friction elements in the torsional model
    (``gearopt.dynamics.joint_friction``) over speed up to overspeed, damper state and fit, and the Monte Carlo
    walk-off probability (``gearopt.studies.failure``), for the helical train, the spur cure and helical
    alternatives."""
    from gearopt.cases.timing_train import failure_reproduction
    # the full envelope's (speed, damper) points run in two forked worker processes (the quick one serially)
    return failure_reproduction(system, quick=quick, joints=FAILURE_JOINTS, samples=5000 if quick else 20000,
                                executor="serial" if quick else "processes", workers=2)


def write_failure(out: Path, failure: dict, figures: list | None = None) -> tuple[list[str], dict]:
    """Report section and ``result.json["failure_reproduction"]`` of :func:`failure_reproduction_stage`; the creep
    map drawn by :func:`plot_failure_map`, or, given ``figures`` (a list), appended to it as ``(builder, path,
    args)`` for another process's figure writer (the side process hands it to the main one)."""
    a = failure["assumptions"]
    envelope = pd.concat(list(failure["envelopes"].values()), ignore_index=True)
    write_table(envelope, out, "failure_reproduction_envelope")
    cam_rows = envelope[(envelope["fit_case"] != "") & envelope["train"].isin(["helical", "spur"])
                        & (envelope["joint"] == "cam")]
    creep = cam_rows["axial_creep_um_per_cycle"].where(cam_rows["axial_creep_um_per_cycle"].abs() >= 1e-6, 0.0)
    cam_map = cam_rows.assign(cell=[f"{u:.2f} / {c:.3g}" for u, c in zip(cam_rows["max_rigid_utilisation"], creep)])
    cam_map = cam_map.pivot_table(index=["train", "speed_rpm", "damper_state"], columns="fit_case", values="cell",
                                  aggfunc="first")
    order = sorted([c for c in cam_map.columns if c.endswith("x_weakest")], key=lambda c: float(c.split("x")[0]))
    cam_map = cam_map[order + [c for c in ("weakest", "nominal", "strongest") if c in cam_map.columns]].reset_index()
    rows = []
    for train, joints in failure["summary"].items():
        for joint, r in joints.items():
            rows.append({"train": train, "joint": joint, "max_slip_utilisation": r["max_slip_utilisation"],
                         "max_slip_utilisation_nominal_fit": r["max_slip_utilisation_nominal_fit"],
                         "max_axial_creep_um_per_cycle": r["max_axial_creep_um_per_cycle"],
                         "max_axial_creep_um_per_cycle_nominal_fit": r["max_axial_creep_um_per_cycle_nominal_fit"],
                         "walk_off_probability": r["walk_off_probability"],
                         **{f"p_walk_off_damper_{k}": v for k, v in r["probability_by_damper_state"].items()},
                         "main_driver": next(iter(r["drivers"])) if r["walk_off_probability"] > 0 else ""})
    table = pd.DataFrame(rows)
    write_table(table, out, "failure_reproduction_summary")
    cam = failure["summary"]["helical"]["cam"]
    spur = failure["summary"]["spur"]["cam"]
    p_cam = cam.get("walk_off_probability_uncalibrated", cam["walk_off_probability"])  # on the data's estimates
    below = ", ".join(f"{k.replace('x_weakest_fit', '')} x the weakest fit: utilisation {v['max_slip_utilisation']:.2f}, "
                      f"creep {v['max_axial_creep_um_per_cycle']:.3g} um/cycle at {v['at_speed_rpm']:g} rpm, "
                      f"{a['distance_mm']:g} mm in {_minutes(v['minutes_to_walk_distance'])}"
                      for k, v in cam["below_tolerance"].items())
    if p_cam > 0:
        verdict = (f"The helical cam gear walks off in the model: it slips at the weakest fits (peak combined slip "
                   f"utilisation {cam['max_slip_utilisation']:.2f}) and ratchets off its seat up to "
                   f"{cam['max_axial_creep_um_per_cycle']:.3g} um per engine cycle; walk-off probability "
                   f"{p_cam:.3%} ({round(p_cam * a['samples'])} of "
                   f"{a['samples']} samples) in {a['period_months']:g} months on the data's estimates (field "
                   f"{a['field_rate']:.3%}; calibrated below), driven by "
                   f"{', '.join(list(cam['drivers'])[:3])}.")
    elif cam["max_axial_creep_um_per_cycle"] > 0:
        verdict = (f"Within the fit tolerances the helical cam gear only just reaches slip: at the weakest fit its "
                   f"peak combined slip utilisation is {cam['max_slip_utilisation']:.2f} and it creeps at most "
                   f"{cam['max_axial_creep_um_per_cycle']:.3g} um per cycle (at {cam['at_speed_rpm']:g} rpm; "
                   f"{a['distance_mm']:g} mm in {_minutes(cam['minutes_to_walk_distance'])}) -- too slow to walk {a['distance_mm']:g} mm in the assumed overspeed exposure "
                   f"(probability {p_cam:.3%} on the data's estimates; field {a['field_rate']:.3%}). At the nominal fit "
                   f"its utilisation is {cam['max_slip_utilisation_nominal_fit']:.2f}.")
    else:
        verdict = (f"With these data the helical cam gear does not walk off anywhere in the envelope: peak combined "
                   f"slip utilisation {cam['max_slip_utilisation']:.2f} at the weakest fit "
                   f"({cam['max_slip_utilisation_nominal_fit']:.2f} at the nominal fit), no ratchet (probability "
                   f"{p_cam:.3%} on the data's estimates; field {a['field_rate']:.3%}).")
    helical_cam = envelope[(envelope["train"] == "helical") & (envelope["joint"] == "cam")
                           & ~envelope["fit_case"].str.endswith("x_weakest")]
    worst = helical_cam.loc[helical_cam["axial_creep_um_per_cycle"].idxmax()]
    verdict += (f" (The lash model rattles at overspeed, so demand and creep vary from cycle to cycle: at the "
                f"largest creep, {worst['speed_rpm']:g} rpm, {worst['damper_state']} damper, {worst['fit_case']} "
                + (f"fit, the creep of single cycles ranged up to {worst['max_cycle_axial_creep_um']:.3g} um with a "
                   f"standard deviation of {worst['axial_creep_um_cycle_std']:.2g} um over {a['recorded_cycles']} "
                   f"cycles" if a["recorded_cycles"] > 1 else "fit, one recorded cycle (quick mode)")
                + "; so re-runs of this stage can differ at the edge of slip. A utilisation near 1 is at the edge of "
                "slip; `problems/failure_reproduction.py` runs longer statistics.)")
    verdict += (f" The mechanism is there: below the tolerance range ({below}) the gear ratchets off at overspeed. "
                "Data that would change the verdict: the real cam fit (interference after fretting wear, friction "
                "coefficient), the damper's state at overspeed, and measured overspeed exposure.")
    lines = ["## Failure reproduction: cam-gear walk-off in the helical train, and the spur cure", "",
             "The press-fitted, keyed gears as friction elements in the torsional model (regularised Coulomb slip "
             "with a combined torque/axial capacity, the key as a stop on the relative rotation, the shaft shoulder "
             "as a one-sided axial stop; one-way coupled). Assumptions: speeds "
             + "; ".join(f"{k} {v['speed_rpm']:g} rpm ({v['source']})" for k, v in a["speeds_rpm"].items())
             + " -- the governor limits fuel up to high idle, not a vehicle motoring the engine faster; damper states "
             + ", ".join(f"{k} {v['damping_Nms_per_rad']:g} N m s/rad" for k, v in a["damper_states"].items())
             + f" ({a['damper_source']}); fit cases: {a['fit_cases']}; walk-off distance {a['distance_mm']:g} mm "
             f"in {a['period_months']:g} months ({a['distance_source']}); exposure {a['exposure_source']}; damper "
             f"state probabilities {a['damper_state_probabilities']} ({a['damper_probability_source']}); "
             f"{a['recorded_cycles']} recorded cycles after {a['run_in_cycles']} run-in per point (the lash model "
             "rattles at overspeed: peaks vary from cycle to cycle); slip regularisation "
             f"V = {a['joint_data']['slip_speed_m_s']:g} m/s ({a['joint_data']['slip_speed_m_s_source']}); the gear's "
             "axial inertia is modelled (a thrust above the capacity accelerates the gear at (F - C)/m, it does not "
             "slide at a speed set by V). Slip utilisation = |(T/r, F_axial)|/C with the gear stuck and the key "
             "unloaded (> 1: the fit slips and the key carries the excess torque); creep = change of the plastic "
             "axial slip per engine cycle.", "",
             f"**Verdict.** {verdict} The spur train has no thrust: its cam joint "
             f"(peak utilisation {spur['max_slip_utilisation']:.2f}) cannot creep, walk-off probability "
             f"{spur['walk_off_probability']:.2%}. A retained helical cam gear (retainer plate and bolt, dropped in "
             f"the source study because it did not fit the cover) cannot walk beyond its retainer's clearance while "
             f"the retainer holds the peak off-nose thrust, {cam['max_off_nose_thrust_N'] * 1e-3:.2f} kN here.", "",
             "The crank gear: " + _crank_sentence(failure["summary"]), "",
             to_markdown(table), "", f"![creep map]({_creep_map(out, envelope, figures).relative_to(out)})", "",
             "### Cam joint map: peak slip utilisation / axial creep [um per cycle]", "",
             "Columns: fit cases (and 0.5, 0.75 x the weakest fit's capacity, below the tolerance range); the "
             "envelope CSV has every capacity level and the crank joint.", "", to_markdown(cam_map), ""]
    lines += calibration_lines(failure.get("calibration"), failure["summary"])
    result = {train: {joint: {k: v for k, v in r.items() if k != "drivers"} | {"drivers": r["drivers"]}
                      for joint, r in joints.items()} for train, joints in failure["summary"].items()}
    result["assumptions"] = a
    if failure.get("calibration") is not None:
        result["calibration"] = failure["calibration"]
    return lines, json.loads(json.dumps(result, default=float).replace("NaN", "null"))


def calibration_lines(cal: dict | None, summary: dict) -> list[str]:
    """Report section of the failure model's calibration against the field record
    (``gearopt.studies.calibration``): the evidence, what it rules out, each input's prior and calibrated range,
    and the walk-off probabilities on the calibrated inputs."""
    if cal is None:
        return []
    field = "; ".join(f"{e['joint']} {e['failures']} of {e['fleet_size']} in {e['period_months']:g} months "
                      f"({e['source']})" for e in cal["field"])
    rows = [{"input": k, "unit": v["unit"], "prior": f"{v['prior'][0]:.3g}..{v['prior'][1]:.3g}",
             "nominal": v["nominal"], "posterior_median": v["posterior"]["median"],
             "posterior_5_95": f"{v['posterior']['q05']:.3g}..{v['posterior']['q95']:.3g}",
             "consistent_range": f"{v['consistent_range'][0]:.3g}..{v['consistent_range'][1]:.3g}"}
            for k, v in cal["inputs"].items()]
    rows += [{"input": f"{j}.mounting: P({' / '.join(v['prior'])})", "unit": "-",
              "prior": " / ".join(f"{p:.2g}" for p in v["prior"].values()), "nominal": "as_modelled",
              "posterior_median": max(v["posterior"], key=v["posterior"].get),
              "posterior_5_95": " / ".join(f"{p:.2g}" for p in v["posterior"].values()),
              "consistent_range": ", ".join(v["consistent"])} for j, v in cal["mounting"].items()]
    probs = [{"train": t, "joint": j, "walk_off_probability_calibrated": r["walk_off_probability"],
              "interval_90": "{:.3g}..{:.3g}".format(*r["walk_off_probability_interval_90"]),
              "walk_off_probability_uncalibrated": r["walk_off_probability_uncalibrated"]}
             for t, joints in summary.items() for j, r in joints.items() if "walk_off_probability_interval_90" in r]
    rules = cal["rules_out"] or ["nothing: every input's whole prior range stays consistent"]
    return ["### Calibrated to the field record", "",
            f"Evidence: {field}. Method: {cal['method']}; {cal['prior_samples']} prior samples, effective sample size "
            f"{cal['effective_samples']:.0f}"
            + (" (quick mode: one speed and damper state, a smoke run, not a result)" if cal.get("quick") else "")
            + ". Key clearance: " + cal["not_calibrated"]["key_clearance_um"] + ". Mountings: as_modelled (the "
            "press fit, shoulder on the data's side), flipped (shoulder on the other side), retained (an axial "
            "retainer holds the gear).", "",
            "**What the field rules out:** " + "; ".join(rules) + ".", "", to_markdown(pd.DataFrame(rows)), "",
            "Walk-off probabilities on the calibrated inputs (posterior predictive; the uncalibrated Monte Carlo "
            "beside):", "", to_markdown(pd.DataFrame(probs)), ""]


CREEP_MAP = Path("figures") / "failure_reproduction_creep_map.png"


def _creep_map(out: Path, envelope: pd.DataFrame, figures: list | None) -> Path:
    if figures is None:
        return plot_failure_map(out, envelope)
    figures.append((plot_failure_creep_map, out / CREEP_MAP, (envelope,)))
    return out / CREEP_MAP


def plot_failure_map(out: Path, envelope: pd.DataFrame) -> Path:
    """The creep map (:func:`gearopt.report.failure_figures.plot_failure_creep_map`) written to
    ``out/figures`` (by the figure writer's worker inside its block, else at once)."""
    return plot_later(plot_failure_creep_map, out / CREEP_MAP, envelope)


def _minutes(v) -> str:
    return "never" if v == "inf" else f"{float(v):.3g} min"


def _crank_sentence(summary: dict) -> str:
    h, s = summary["helical"].get("crank"), summary["spur"].get("crank")
    if h is None:
        return "not modelled."
    c_weak, c_nom = h["capacity_N_weakest_fit"], h["capacity_N_nominal_fit"]
    return (f"its slip utilisation (the demand the fit would carry if the gear stuck with the key unloaded) peaks at "
            f"{h['max_slip_utilisation']:.0f} (helical) / {s['max_slip_utilisation']:.0f} (spur) at the weakest "
            f"H7/r6 fit: after DIN 7190 smoothing (0.8 sum Rz = 8 um of its 11 um minimum interference) that fit "
            f"holds only {c_weak * 1e-3:.2f} kN, {c_weak / c_nom:.0%} of the nominal fit's {c_nom * 1e-3:.1f} kN "
            f"(utilisation {h['max_slip_utilisation_nominal_fit']:.2f} / {s['max_slip_utilisation_nominal_fit']:.2f} "
            f"at the nominal fit). Beyond the capacity the key carries the torque (peak key force "
            f"{h['max_key_force_N'] * 1e-3:.0f} kN) while the interface slips round within the key's clearance and "
            f"compliance. Slip without thrust accumulates nothing: the spur crank gear's creep is "
            f"{s['max_axial_creep_um_per_cycle']:.3g} um/cycle. In the helical train the off-nose thrust (peak "
            f"{h['max_off_nose_thrust_N'] * 1e-3:.1f} kN) alone exceeds the weakest fits' capacity, so the gear slides "
            f"back and forth on its seat against its own inertia (net creep of either sign, up to "
            f"{h['max_axial_creep_um_per_cycle']:.3g} um/cycle), and at the nominal fit the torque-driven slip "
            f"ratchets it off at up to {h['max_axial_creep_um_per_cycle_nominal_fit']:.3g} um/cycle (walk-off "
            f"probability {h.get('walk_off_probability_uncalibrated', h['walk_off_probability']):.0%} on the data's "
            f"estimates) -- which the field never showed. The crank joint's data "
            f"(H7/r6 fit, friction 0.12, no axial retention) are therefore not credible: the real crank gear is most "
            f"likely held axially by the damper hub clamped on the crank nose, or has a heavier fit. Data that would "
            f"settle it: the crank gear's fit and its axial retention.")


def write_outputs(out: Path, macro: dict, split: dict, timings: dict, contact: dict | None = None,
                  ratings: dict | None = None, joints: dict | None = None, dynamics: dict | None = None,
                  design_torques: pd.DataFrame | None = None, teeth: dict | None = None,
                  sizing: dict | None = None, system: go.System | None = None,
                  failure: dict | None = None, codesign=None, sections: dict | None = None,
                  recommendation: dict | None = None, quick: bool = False) -> None:
    """report.md and result.json of the whole run (tables and figures of each section too); ``sections``: the
    sections :func:`write_sections` already wrote (their report lines and result entries); ``recommendation``:
    the recommended design (``Recommendation.as_json()``), whose verdict and design sheet open the report."""
    out.mkdir(parents=True, exist_ok=True)
    if sections is None:
        sections = write_sections(out, contact, ratings, joints, dynamics, design_torques)
    failure_lines, failure_result = (sections["failure"] if "failure" in sections
                                     else write_failure(out, failure) if failure else ([], {}))
    lines = list(failure_lines)  # the failure the redesign cures comes first, after the summary
    appendix = ["## Appendix: reproductions of the source study's tables", "",
                "Thesis columns are the thesis' own (normalised where the thesis normalised); see "
                "docs/source-study.md sec. 1.", ""]
    titles = {
        "table_3_1_helical_to_spur": "Helical -> standard spur gears (thesis Table 3.1)",
        "table_3_2_sum_profile_shift": "Sum of profile shifts at the fixed centre distances (thesis Table 3.2)",
        "table_3_3_profile_shift": "Profile shift per gear (thesis Table 3.3)",
        "table_3_4_percentage_change": "Percentage change after profile shift (thesis Table 3.4)",
        "mesh_checks_spur": "Spur redesign: contact ratios, backlash, checks",
        "mesh_checks_helical": "Helical baseline: contact ratios, backlash, checks",
        "gears_spur": "Spur redesign: gear dimensions",
        "gears_helical": "Helical baseline: gear dimensions",
    }
    for key, df in macro["tables"].items():
        write_table(df, out, key)
        (appendix if key.startswith("table_3_") else lines).extend([f"## {titles[key]}", "", to_markdown(df), ""])
    if teeth is not None:
        ranked = teeth["study"].table
        write_table(ranked, out, "tooth_count_candidates")
        write_table(teeth["study"].rejected, out, "tooth_count_rejected")
        cols = [c for c in TOOTH_COUNT_COLUMNS if c in ranked.columns]
        lines += ["## Tooth counts at the fixed centre distances (thesis Table 3.1)", "",
                  f"Candidates within {teeth['lube_tolerance_percent']:g} % of the original helical speed ratios on "
                  f"the lube-pump branch (0 % elsewhere), ranked by the smallest worst-case contact ratio after an "
                  f"Ipopt shift split per candidate. Rejected: "
                  + ", ".join(f"{n} at {stage}" for stage, n in teeth["rejected_by_stage"].items()) + ".", "",
                  to_markdown(ranked[cols]), ""]
    split_df = split["table"]
    write_table(split_df, out, "shift_split_crank_cam")
    lines += ["## Profile-shift split of crank-cam: Ipopt vs ISO/TR 4467", "", to_markdown(split_df), "",
              f"Objective: {split['objective']}; Ipopt status {split['status']} in {split['iterations']} iterations.",
              ""]
    contact_lines, contact_result = sections["contact"]
    rating_lines, rating_result = sections["rating"]
    joint_lines, joint_result = sections["joints"]
    dyn_lines, dyn_result = sections["dynamics"]
    sizing_lines = []
    if sizing is not None:
        write_table(sizing["table"], out, "joint_sizing")
        sizing_lines = ["## Joint sizing against the dynamic demands over speed", "",
                        f"Every joint sized for a slip margin of {JOINT_TARGET_MARGIN:g} against the peak joint torque "
                        "and axial force of the speed sweep (with backlash), at the weakest interference / nut "
                        "factor (`gearopt.design.joint_sizing`); `present_min_*` are the margins of the present "
                        "design over the same sweep.", "", to_markdown(sizing["table"]), ""]
    codesign_lines = (["## Co-design: profile shift, helix angle, flank reliefs and walk-off in one NLP", ""]
                      + codesign.report_lines()) if codesign is not None else []
    lines += contact_lines + rating_lines + joint_lines + dyn_lines + sizing_lines + codesign_lines + appendix
    lines += ["## Run time per stage", ""] + [f"- {k}: {v:.3f} s" for k, v in timings.items()]
    result = {
        "units": {"centre_distance": "mm", "tip_thickness": "mm", "time": "s", "ppte": "um", "stress": "MPa",
                  "temperature": "C", "torque": "N m", "microgeometry": "um and deg as in the key names"},
        "meshes": {
            kind: {name: {"centre_distance_mm": float(p.geometry()["centre_distance_mm"]),
                          "profile_shifts": [float(x) for x in p.geometry()["profile_shifts"]],
                          "transverse_contact_ratio": float(p.geometry()["transverse_contact_ratio"]),
                          "worst_case_transverse_contact_ratio":
                              float(p.geometry()["worst_case_transverse_contact_ratio"]),
                          "normal_backlash_min_mm": float(p.geometry()["normal_backlash_min_mm"]),
                          "normal_backlash_max_mm": float(p.geometry()["normal_backlash_max_mm"])}
                   for name, p in macro["trains"][kind].pairs.items()}
            for kind in ("spur", "helical")},
        "profile_shifts": {kind: {g: float(x) for g, x in macro["trains"][kind].profile_shifts.items()}
                           for kind in ("spur", "helical")},
        "shift_split_crank_cam": {k: v for k, v in split.items() if k != "table"},
        "tooth_counts": ([{c: (r[c] if isinstance(r[c], str) else float(r[c])) for c in TOOTH_COUNT_COLUMNS
                           if c in r} for r in teeth["study"].table.to_dict(orient="records")] if teeth else []),
        "pairs": contact_result,
        "rating": rating_result,
        "joints": joint_result,
        "dynamics": dyn_result,
        "joint_sizing": (sizing["table"].replace({np.inf: "inf"}).to_dict(orient="records") if sizing else []),
        "failure_reproduction": failure_result,
        "codesign": codesign.to_json() if codesign is not None else {},
        "stage_time_s": timings,
    }
    head = ([QUICK_BANNER, ""] if quick else []) + ["# Cam gear walk-off: spur redesign of the timing train", ""]
    if recommendation is not None:
        summary = build_summary(recommendation, quick=quick, **summary_inputs(system or go.load_system(), dynamics,
                                                                              out))
        result = {"summary": summary, "recommendation": recommendation, **result}
        head += [summary_markdown(summary, recommendation),
                 "Generated by `problems/cam_gear_walkoff.py`; every table below is also a CSV file in this folder. "
                 "The evidence follows: the failure the redesign cures, then each stage.", ""]
    else:
        head += ["Generated by `problems/cam_gear_walkoff.py`; no recommendation (the co-design did not run).", ""]
    (out / "report.md").write_text("\n".join(head + lines) + "\n")
    (out / "result.json").write_text(json.dumps(result, indent=2) + "\n")


def write_sections(out: Path, contact: dict | None, ratings: dict | None, joints: dict | None,
                   dynamics: dict | None, design_torques: pd.DataFrame | None, *, quick: bool = False) -> dict:
    """Tables and figures of the main process's sections (the figures go to the figure writer's worker);
    ``{section: (report lines, result.json entries)}`` for :func:`write_outputs` (which calls it when not given
    them; the main job writes each section as soon as its stage ends, so the figures render while the next stages
    run)."""
    out.mkdir(parents=True, exist_ok=True)
    return {"contact": write_contact(out, contact, quick=quick) if contact else ([], {}),
            "rating": write_rating(out, ratings) if ratings else ([], {}),
            "joints": write_joints(out, joints) if joints else ([], {}),
            "dynamics": write_dynamics(out, dynamics, design_torques) if dynamics else ([], {})}


KEY_FIGURES = ("te_crank_cam", "te_torques_crank_cam", "harris_crank_cam", "dynamics_crank_cam_force", "campbell_spur")


def summary_inputs(system: go.System, dynamics: dict | None, out: Path) -> dict:
    """Load basis and key figures of the verdict-first summary (:func:`gearopt.cases.timing_train.summary.build_summary`)
    from the data's ``[design_loads]`` and what the run drew."""
    values = data_values(system.data)
    loads = values["design_loads"]
    basis = {"rating": ("ISO 6336 method B at the static design torques ("
                        + ", ".join(f"{m} {t:g} N m" for m, t in system.design_torques_Nm().items()
                                    if m in RATED_MESHES)
                        + f"), K_A {loads['application_factor_K_A']:g}; K_v, K_Hbeta, K_Fbeta, K_Halpha, K_Falpha and the "
                          "life, lubrication, roughness and size factors computed (gearopt.rating.rate_iso6336) "
                          "for endurance, N_L = 1e10 load cycles; and again at the largest dynamic mesh torque "
                          "with backlash (K_A = K_v = 1, the dynamics holds them; per-cycle peak spread in the "
                          "rating tables)"),
             "joints at design load": "static design torques on each gear",
             "contact": (f"exact LTCA at {', '.join(f'{f:g}' for f in loads['torque_range_fractions'])} x the design "
                         f"torque, {loads['speed_rpm']:g} rpm crank")}
    if dynamics:
        sims = list(dynamics["runs"].values())
        changes = [float(s.cycle_change[-1]) for s in sims if len(s.cycle_change) and np.isfinite(s.cycle_change[-1])]
        change = max(changes) if changes else float("nan")
        lash = [s for k, s in dynamics["runs"].items() if k[2]] or sims
        basis["dynamics"] = (f"peaks over {min(s.cycles for s in lash)} recorded cycle(s) with backlash (one "
                             f"periodic cycle without) after {min(s.run_in_cycles for s in sims)} run-in cycle(s) at "
                             + ", ".join(f"{s:g}" for s in sorted({k[1] for k in dynamics["runs"]})) + " rpm; "
                             + (f"largest cycle-to-cycle change {change:.2g}"
                                + (" (not periodic: peaks may not have settled)" if change > 0.05 else "")
                                if np.isfinite(change) else "cycle-to-cycle change not measured (one cycle)"))
    figures = [f"figures/{stem}.png" for stem in KEY_FIGURES if (out / "figures" / f"{stem}.png").exists()]
    return {"load_basis": basis, "figures": figures}


def trade_off_stage(system: go.System, trains: dict, quick: bool = False):
    """Stage 7: the headline trade-off of the spur crank-cam tip relief over the design torque range -- PPTE against
    loaded contact ratio -- with the sensitivity report and the Monte Carlo robustness of the optimised design."""
    from gearopt.studies import relief_scene_from_data, scene_study

    # each position's approach an NLP variable (the mesh's macro geometry is fixed): on the default data 50.8 ->
    # 36.6 CPU-s in one process, the optimum 3.487 -> 3.478 um and every front point as good or better
    scene = relief_scene_from_data(system, trains["spur"], "crank-cam", positions=24 if quick else None,
                                   ltca_options={"approach": "lifted", **({"max_refinements": 1} if quick else {})})
    return scene_study(scene, "loaded_contact_ratio", "crank-cam", points=4 if quick else 9,
                       samples=64 if quick else 2000, starts=1 if quick else 4,
                       verify_ltca_options={"max_refinements": 0} if quick else None)


def trade_off_outputs(out: Path, study) -> tuple[str, dict]:
    """Tables and figure of the trade-off study; its report section (Markdown) and ``result.json`` entry."""
    fig = out / "figures" / "trade_off_crank_cam.png"
    fig.parent.mkdir(parents=True, exist_ok=True)
    figs.save(study.front.plot(), fig, dpi=110)
    write_table(study.front.table, out, "trade_off_front_crank_cam")
    if study.sensitivity is not None:
        write_table(study.sensitivity.table, out, "sensitivity_crank_cam")
    write_table(study.monte_carlo.summary, out, "robustness_crank_cam")
    return study.markdown(str(fig.relative_to(out))), json.loads(json.dumps(study.headline(), default=float))


def write_trade_off(out: Path, markdown: str, headline: dict) -> None:
    """Append the trade-off section to ``report.md`` and its ``trade_off`` key to ``result.json``."""
    with open(out / "report.md", "a") as f:
        f.write("\n## Trade-off, sensitivities and robustness of the crank-cam tip relief\n\n" + markdown + "\n")
    result = json.loads((out / "result.json").read_text())
    result["trade_off"] = headline
    (out / "result.json").write_text(json.dumps(result, indent=2, default=float) + "\n")


class CodesignOutputs:
    """The co-design study's report lines and ``result.json`` entry, as the side process returns them (plain
    data: a class of this script does not unpickle in the other process)."""

    def __init__(self, lines: list[str], entry: dict):
        self._lines, self._json = lines, entry

    def report_lines(self) -> list[str]:
        return self._lines

    def to_json(self) -> dict:
        return self._json


@contextlib.contextmanager
def one_thread_per_process(enabled: bool):
    """With side processes: the macro-symbolic LTCA maps its positions on one thread (``GEAROPT_THREADS=1``,
    inherited by the side processes) unless the user set it -- the main, side and figure processes already fill two
    cores, and threads on top cost CPU time without saving wall time. Measured here: ``--quick`` 9.2-11.3 s against
    9.1-9.2 s wall; the full run 284 -> 267 CPU-s in the process tree (the co-design's process 92 -> 84), 154 -> 146
    s wall, back to back on the same clone. ``--serial`` (one process) keeps the threads."""
    previous = os.environ.get("GEAROPT_THREADS")
    if enabled and previous is None:
        os.environ["GEAROPT_THREADS"] = "1"
    try:
        yield
    finally:
        if enabled and previous is None:
            os.environ.pop("GEAROPT_THREADS", None)


QUICK_DPI = 80
"""Resolution of the figures of a ``--quick`` run (120 otherwise): fewer pixels to render."""

def _side_stage(stage: str, run):
    """``run()`` timed as ``stage``, with the compile-cache counters it moved (a side process may run several)."""
    from gearopt.compile_cache import cache_stats

    LOG.info("stage %-36s started (%s)", stage, time.strftime("%H:%M:%S"))
    before, t0 = cache_stats(), time.perf_counter()
    section = run()
    after, timings = cache_stats(), StageTimings()
    timings[stage] = time.perf_counter() - t0                       # logged as it ends ("[side] stage ...")
    return {"section": section, "timings": dict(timings), "pid": os.getpid(), "process_cpu_s": time.process_time(),
            "compile_cache": {k: v - before.get(k, 0) for k, v in after.items() if isinstance(v, (int, float))}}


def side_failure(system: go.System, out: Path, quick: bool = False) -> dict:
    """Side-process stage: the failure reproduction and its report section (tables written here); the creep map is
    handed back (``plot_later``: builder, path, arguments) for the main process's figure writer to draw, off the
    side process's time (:func:`plot_side_figures`)."""
    later: list = []
    done = _side_stage("failure_reproduction",
                       lambda: write_failure(out, failure_reproduction_stage(system, quick=quick), figures=later))
    return {**done, "plot_later": later}


def plot_side_figures(side_runs: dict, plotted: set) -> None:
    """Hand the figures of the side stages finished so far (their ``plot_later`` entries) to this process's figure
    writer, once per stage (``plotted``: the stages already handed)."""
    for stage, run in side_runs.items():
        if stage not in plotted and run.done() and run.exception() is None:
            plotted.add(stage)
            for builder, path, args in run.result().get("plot_later", ()):
                plot_later(builder, path, *args)


def side_codesign(system: go.System, out: Path, quick: bool = False, dynamic_peaks: dict | None = None) -> dict:
    """Side-process stage: the co-design study (with the dynamics' peak mesh torques); its report lines and
    ``result.json`` entry (plain data)."""
    def run():
        study = codesign_stage(system, quick=quick, dynamic_peaks=dynamic_peaks)
        return study.report_lines(), json.loads(json.dumps(study.to_json(), default=float))
    return _side_stage("codesign_nlp", run)


def side_trade_off(system: go.System, out: Path, quick: bool = False) -> dict:
    """Side-process stage: the trade-off study (tables and figure written here); its report section and entry."""
    return _side_stage("trade_off_study", lambda: trade_off_outputs(
        out, trade_off_stage(system, {"spur": train_from_data(system.data, "spur")}, quick=quick)))


SIDE_STAGES = {"failure_reproduction": side_failure}
"""Stages that need only the data and start first: they run in side processes beside the others."""

DYNAMICS_SIDE_STAGES = {"codesign_nlp": side_codesign, "trade_off_study": side_trade_off}
"""Side stages submitted when the dynamics stage ends, in this order: the co-design (it needs the dynamics' peaks;
in a full run it takes the second side process, the longest chain after the failure reproduction), then the
trade-off study (it needs only the data, but queued first it held the co-design's process)."""


def side_result(stage: str, run):
    """The side stage's result; a side process that died is said in one line naming the stage (exit code 3 under
    :func:`gearopt.cli.run_script`, distinct from a failed requirement's 1)."""
    from concurrent.futures.process import BrokenProcessPool

    try:
        return run.result()
    except BrokenProcessPool as exc:
        raise RuntimeError(f"stage {stage}: its side process died ({exc}); run again, or with --serial to run the "
                           f"stage in this process") from None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="reduced settings (used by the tests)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    parser.add_argument("--serial", action="store_true",
                        help="run every stage in this process (no side process; e.g. to debug a stage)")
    args = parser.parse_args(argv)

    if not logging.getLogger().handlers:
        logging.basicConfig(level=logging.INFO, format="%(message)s")
    from gearopt.compile_cache import cache_stats

    wall0, stats0 = time.perf_counter(), cache_stats()      # counters of this run only (main() may run twice)
    cpu0 = time.process_time()                              # this process's CPU before the job (a caller's)
    timings = StageTimings()
    system, thesis = go.load_system(args.data), load_thesis_tables()
    args.out.mkdir(parents=True, exist_ok=True)
    # the stages that need only the data run in a side process beside the others; figures render in a third
    # a full run: the co-design (minutes) in a process of its own; --quick: one side process (a second one made
    # it slower here, 12 s against 9.6 s: four processes on two cores)
    workers = 1 if args.quick else 2
    # SIGTERM/SIGINT (a timeout, a scheduler, kill, Ctrl-C) end the job with every process of its tree
    with children_die_with_this_process(), one_thread_per_process(not args.serial), \
            side_process(enabled=not args.serial, workers=workers) as side, \
            background_figures(dpi=QUICK_DPI if args.quick else None):
        side_runs = {stage: side.submit(fn, system, args.out, quick=args.quick) for stage, fn in SIDE_STAGES.items()}
        plotted: set = set()                     # side stages whose figures went to the figure writer

        with timings.stage("macro_design"):
            macro = macro_design(system, thesis)

        with timings.stage("tooth_counts"):
            teeth = tooth_count_stage(system, macro["trains"]["spur"])

        with timings.stage("shift_split_nlp"):
            split = shift_split_study(macro["trains"]["spur"])

        with timings.stage("dynamics"):
            dynamics = dynamics_stage(system, quick=args.quick)
            design_torques = dynamic_design_torques(system, dynamics)
        peaks = {m: tuple(v) for m, v in dynamic_peaks(design_torques, dynamics["sweeps"]["spur"])
                 .mesh_torques_Nm.items()}
        side_runs.update({stage: side.submit(fn, system, args.out, quick=args.quick,
                                             **({"dynamic_peaks": peaks} if fn is side_codesign else {}))
                          for stage, fn in DYNAMICS_SIDE_STAGES.items()})
        with timings.stage("write_dynamics"):    # each section written as its stage ends: its figures render now
            sections = {"dynamics": write_dynamics(args.out, dynamics, design_torques)}
        plot_side_figures(side_runs, plotted)

        with timings.stage("joint_sizing_nlp"):
            sizing = joint_sizing_stage(system, macro["trains"], dynamics)

        LOG.info("stage %-36s started (%s)", "contact_ltca_and_microgeometry_nlp", time.strftime("%H:%M:%S"))
        t0, written = time.perf_counter(), {}

        def write_mesh(mesh, study):             # each mesh's section as its study ends: its figures render
            t1 = time.perf_counter()             # while the next mesh is solved
            written[mesh] = write_contact_mesh(args.out, mesh, study, every_figure=not args.quick or not written)
            written[mesh] += (time.perf_counter() - t1,)

        contact = contact_stage(system, macro["trains"], quick=args.quick, on_study=write_mesh)
        write_s = sum(w[2] for w in written.values())
        timings["contact_ltca_and_microgeometry_nlp"] = time.perf_counter() - t0 - write_s
        timings["write_contact"] = write_s
        sections["contact"] = (CONTACT_HEADER + [line for w in written.values() for line in w[0]],
                               {mesh: w[1] for mesh, w in written.items()})
        plot_side_figures(side_runs, plotted)

        with timings.stage("rating"):
            ratings = rating_stage(system, macro["trains"])
            ratings.update(rating_at_dynamic_peaks(system, macro["trains"], design_torques))

        with timings.stage("joints_blanks_webs"):
            joints = joint_stage(system)
        plot_side_figures(side_runs, plotted)

        with timings.stage("write_rating_joints"):
            sections.update(rating=write_rating(args.out, ratings), joints=write_joints(args.out, joints))

        with timings.stage("side_process_wait"):
            side_results = {stage: side_result(stage, run) for stage, run in side_runs.items()}
        plot_side_figures(side_runs, plotted)
        for r in side_results.values():
            timings.update(r["timings"])

        with timings.stage("recommendation"):
            calibration = side_results["failure_reproduction"]["section"][1].get("calibration") or {}
            recommendation, codesign_json = recommendation_stage(
                system, side_results["codesign_nlp"]["section"][1], design_torques, dynamics,
                calibration.get("calibrated_inputs"), quick=args.quick)
            if codesign_json is not side_results["codesign_nlp"]["section"][1]:     # re-solved in the loop
                side_results["codesign_nlp"]["section"] = codesign_json

        t0 = time.perf_counter()
        write_outputs(args.out, macro, split, timings, contact, ratings, joints, dynamics, design_torques, teeth,
                      sizing, system=system, codesign=CodesignOutputs(*side_results["codesign_nlp"]["section"]),
                      sections={**sections, "failure": side_results["failure_reproduction"]["section"]},
                      recommendation=recommendation, quick=args.quick)
        write_trade_off(args.out, *side_results["trade_off_study"]["section"])
        timings["write_outputs"] = time.perf_counter() - t0
        t0 = time.perf_counter()
    timings["figure_files_wait"] = time.perf_counter() - t0
    result = json.loads((args.out / "result.json").read_text())
    result["stage_time_s"] = dict(timings)                          # every stage, the ones after write_outputs too
    result["side_process_stages"] = list(SIDE_STAGES) + list(DYNAMICS_SIDE_STAGES) if side.enabled else []
    result["wall_time_s"] = time.perf_counter() - wall0            # less than the stages' sum: two chains overlap
    # CPU time of each process of the job: the main process's since main() started (an in-process caller's
    # earlier work excluded), a side process's since it started (imports included) to the end of its last stage:
    # less disturbed by other load on the machine than the wall times, it shows which chain is longer
    result["process_cpu_s"] = {"main": time.process_time() - cpu0, **{
        f"side_{pid}": max(r["process_cpu_s"] for r in side_results.values() if r["pid"] == pid)
        for pid in sorted({r["pid"] for r in side_results.values()}) if pid != os.getpid()}}
    stats = {k: v - stats0.get(k, 0) if isinstance(v, (int, float)) else v    # this run's kernels in this
             for k, v in cache_stats().items()}                               # process: compiled, loaded, interpreted
    for other in (r["compile_cache"] for r in side_results.values()) if side.enabled else ():
        stats = {k: v + other.get(k, 0) if isinstance(v, (int, float)) else v for k, v in stats.items()}
    result["compile_cache"] = stats
    (args.out / "result.json").write_text(json.dumps(result, indent=2, default=float) + "\n")

    spur = macro["tables"]["table_3_3_profile_shift"]
    print("Cam gear walk-off: spur redesign at the helical train's centre distances")
    print("profile shifts:", ", ".join(f"{g} {x:+.4f}" for g, x in spur["profile_shift"].items()))
    checks = macro["tables"]["mesh_checks_spur"]
    for mesh, row in checks.iterrows():
        print(f"  {mesh:10s} eps_alpha {row['transverse_contact_ratio']:.3f} (worst case "
              f"{row['worst_case_transverse_contact_ratio']:.3f}), backlash {row['normal_backlash_min_mm']:.3f}-"
              f"{row['normal_backlash_max_mm']:.3f} mm: {row['check']}")
    best = teeth["study"].table.iloc[0]
    rec = result.get("recommendation") or {}
    used = {g: v["teeth"] for g, v in rec.get("gears", {}).items()}
    print(f"tooth counts (evidence): {len(teeth['study'].table)} candidates; the best by worst-case contact ratio "
          f"has LPI/LPG {best['teeth_lpi']:.0f}/{best['teeth_lpg']:.0f} (crank-LPI ratio error "
          f"{best['ratio_error_crank-lpi_percent']:+.2f} %, worst-case eps_alpha {best['min_worst_case_contact_ratio']:.3f})"
          + (f"; the recommended design keeps the data's {used.get('lpi')}/{used.get('lpg')}" if used else ""))
    print(f"crank-cam split (evidence), Ipopt ({split['objective']}): x = {split['profile_shifts'][0]:.4f} / "
          f"{split['profile_shifts'][1]:.4f}; ISO/TR 4467: {split['iso_tr_4467_profile_shifts'][0]:.4f} / "
          f"{split['iso_tr_4467_profile_shifts'][1]:.4f}"
          + (f"; the recommended design's shifts: {rec['gears']['crank']['profile_shift']:.4f} / "
             f"{rec['gears']['cam']['profile_shift']:.4f}" if rec else ""))
    print("per-mesh microgeometry (evidence: each mesh optimised alone; the recommended design's flanks are in the "
          "report's design sheet):")
    for mesh, st in contact.items():
        rng = headlines.ppte_over_range(st.optimisation)
        o, u = rng["by_design"]["optimised"], rng["by_design"]["unmodified"]
        worse = rng["worse_than_unmodified_Nm"]
        print(f"  {mesh:10s} PPTE over {min(rng['torques_Nm']):g}-{max(rng['torques_Nm']):g} N m (worst, exact LTCA): "
              f"spur unmodified {eng(u['worst_ppte_um'])} um, spur optimised {eng(o['worst_ppte_um'])} um "
              f"({eng(o['design_torque_ppte_um'])} um at {st.torque_Nm:g} N m)"
              + (f"; optimised WORSE than unmodified at {', '.join(f'{t:g}' for t in worse)} N m" if worse else ""))
    for kind in ("helical", "spur"):
        j = joints[kind]["joints_nominal"].set_index("gear")
        print(f"  joints ({kind}): " + ", ".join(
            f"{g} torque x{r['torque_margin']:.2f} axial x{r['axial_margin']:.3g}" for g, r in j.iterrows()))
    for _, r in sizing["table"].iterrows():
        if r["train"] == "spur":
            print(f"  joint {r['joint']:5s} (spur) present margin x{r['present_min_torque_margin']:.2f} over speed; "
                  f"for x{r['target_margin']:g}: {r['result']}{(' -- relax ' + r['must_relax']) if r['must_relax'] else ''}")
    print("stage times:", ", ".join(f"{k} {v:.2f} s" for k, v in timings.items()),
          f"(wall {result['wall_time_s']:.1f} s; {', '.join(result['side_process_stages']) or 'no stage'} in the "
          f"side process)")
    summary = json.loads((args.out / "result.json").read_text())["summary"]
    print(f"recommended design: {summary['design']} ({summary['why']})")
    print(("QUICK RUN (reduced settings, not the full run's finding) " if args.quick else "")
          + f"verdict: {summary['verdict']}" + (f" ({len(summary['failed'])} requirements fail: "
                                                 + "; ".join(summary["failed"]) + ")" if summary["failed"] else ""))
    print(f"wrote {args.out}/report.md, result.json and CSV tables")
    return 1 if summary["verdict"] == "FAIL" else 0


if __name__ == "__main__":
    sys.exit(run_script(main))
