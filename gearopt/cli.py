"""The ``gearopt`` command line: geometry of a pair, and the studies on a train data file (yours or the packaged one).

    gearopt pair --teeth 38 76 --module-mm 3 --centre-distance-mm 172.24 [--profile-shift1 0.3124]
    gearopt pair --teeth 12 24 --module-mm 3 --profile-shifts 0.6 0.36
    gearopt train spur [--data FILE]                  # or helical
    gearopt rate [--data FILE] [--train spur]         # ISO 6336 S_H / S_F of every mesh at the design loads
    gearopt microgeometry [--mesh MESH] [--data FILE] [--quick]   # robust PPTE design over the mesh's torque range
    gearopt dynamics [--data FILE] [--speeds RPM ...] # speed sweep: joint slip and walk-off margins
    gearopt scene FILE [--scene NAME] [--data FILE] [--mesh MESH]   # a scene declared in FILE (docs/scenes.md)

Exit codes: 0 every requirement met, 1 a requirement fails (a check, a safety factor, a margin), 2 bad input (the
message names the file, the key path or section, and what to add) or a failed solve, 3 an internal error.
``--data FILE``: a system data file (``docs/data-schema.md``; default: the packaged timing train).
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
from pathlib import Path

import pandas as pd

from .data import load_system, system_from_data
from .errors import GearoptError, GearoptInputError, GeometryError, InfeasibleProblemError, MissingSectionError
from .geometry.pair import GearPair


def _pair_command(args) -> int:
    common = dict(teeth=tuple(args.teeth), module_mm=args.module_mm, pressure_angle_deg=args.pressure_angle_deg,
                  helix_angle_deg=args.helix_angle_deg, face_width_mm=args.face_width_mm)
    if args.centre_distance_mm is not None:
        pair = GearPair.from_centre_distance(centre_distance_mm=args.centre_distance_mm,
                                             profile_shift1=args.profile_shift1, shift_split=args.shift_split,
                                             **common)
    elif args.profile_shifts is not None:
        pair = GearPair.from_profile_shifts(profile_shifts=tuple(args.profile_shifts), **common)
    else:
        raise GearoptError("give --centre-distance-mm or --profile-shifts")
    for key, value in pair.geometry().items():
        if isinstance(value, tuple):
            value = "  ".join(f"{v:.6g}" if isinstance(v, float) else str(v) for v in value)
        elif isinstance(value, float):
            value = f"{value:.6g}"
        print(f"{key:40s} {value}")
    try:
        pair.check(min_contact_ratio=args.min_contact_ratio)
        print("check: ok")
    except GeometryError as err:  # the pair violates a limit: exit 1; a bad limit itself is bad input (exit 2)
        print(f"check: FAIL: {err}")
        return 1
    return 0


def _system(args):
    """The typed system of ``--data`` (default: the packaged timing train)."""
    return load_system(args.data)


def _train_command(args) -> int:
    train = _system(args).train(args.kind)
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        print(train.gear_table().round(4))
        print()
        print(train.mesh_table().round(4))
    return 0


def _verdict(rows: list[tuple[str, float, float, str, str]]) -> int:
    """Print ``(requirement, value, limit, sense, unit)`` rows with PASS/FAIL; 1 if any fails, else 0."""
    from .report.tables import eng

    failed = 0
    for name, value, limit, sense, unit in rows:
        ok = value >= limit if sense == ">=" else value <= limit
        failed += not ok
        print(f"{name:48s} {eng(value):>9s} {sense} {eng(limit):<7s} {unit:4s} {'PASS' if ok else 'FAIL'}")
    print(f"verdict: {'FAIL' if failed else 'PASS'} ({failed} of {len(rows)} requirements fail)")
    return 1 if failed else 0


def _rate_command(args) -> int:
    system = _system(args)
    train = system.train(args.train)
    torques = {m: t for m, t in system.design_torques_Nm().items() if m in train.pairs}
    if not torques:
        raise MissingSectionError(f"{system.source}: no mesh states a design torque: gearopt rate needs "
                                  f"design_torque_Nm in [meshes.<name>] (meshes: {', '.join(system.meshes)})")
    loads = system.design_loads
    K_A = loads.application_factor_K_A if loads is not None else 1.0
    req = system.requirements
    min_s_h = req.min_S_H if args.min_s_h is None else args.min_s_h
    min_s_f = req.min_S_F if args.min_s_f is None else args.min_s_f
    if args.unit_factors:
        from .report.rating_tables import rating_table

        table = rating_table(train, torques, K_A=K_A)
        cols = ["mesh", "torque_Nm", "sigma_H_MPa", "S_H", "sigma_F_1_MPa", "sigma_F_2_MPa", "S_F_1", "S_F_2"]
        basis = f"ISO 6336-2/-3 method B, K_A {K_A:g}, other load factors and life factors 1 (--unit-factors)"
        table["S_H_1"] = table["S_H_2"] = table["S_H"]
    else:
        from .design.requirements import rating_table

        if loads is None or loads.speed_rpm is None:
            raise MissingSectionError(f"{system.source}: [design_loads] speed_rpm is missing: gearopt rate computes "
                                      f"K_v and the life and lubrication factors at that speed; add it, or rate with "
                                      f"--unit-factors (load factors 1)")
        table = rating_table(system, train, torques, loads.speed_rpm, application_factor=K_A)
        cols = ["mesh", "torque_Nm", "K_v", "K_Hbeta", "K_Halpha", "S_H_1", "S_H_2", "S_F_1", "S_F_2", "S_B"]
        basis = (f"ISO 6336 with every factor computed (K_v, K_Hbeta, K_Halpha, life, lubrication, size), K_A "
                 f"{K_A:g}, {loads.speed_rpm:g} rpm of the root gear, endurance; --unit-factors for load factors 1")
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        print(table[cols].round(3).to_string(index=False))
    print(f"at the meshes' design torques: {basis}")
    unrated = sorted(set(train.pairs) - set(torques))
    if unrated:
        print(f"not rated (no design_torque_Nm): {', '.join(unrated)}")
    rows = []
    for _, r in table.iterrows():
        rows.append((f"S_H {r['mesh']}", float(min(r["S_H_1"], r["S_H_2"])), min_s_h, ">=", "-"))
        rows.append((f"S_F {r['mesh']}", float(min(r["S_F_1"], r["S_F_2"])), min_s_f, ">=", "-"))
        if "S_B" in cols:
            rows.append((f"S_B {r['mesh']}", float(r["S_B"]), req.min_S_B, ">=", "-"))
    return _verdict(rows)


def _microgeometry_command(args) -> int:
    from .design.microgeometry_nlp import optimise_microgeometry
    from .design.requirements import TrainDesign, evaluate_requirements
    from .report.contact_headlines import ppte_over_range, tip_relief_drawing, verified_margins

    system = _system(args)
    train = system.train(args.train)
    mesh = args.mesh or system.default_mesh(args.train)
    if mesh not in train.pairs:
        raise GearoptInputError(f"{system.source}: --mesh {mesh!r} is not a mesh of the {args.train} train "
                                f"({', '.join(train.pairs)})")
    torques = list(system.torque_range_Nm(mesh))
    limits = system.design_limits
    max_root = limits.max_root_stress_MPa if limits is not None else None
    min_lcr = system.requirements.min_loaded_contact_ratio
    opts = dict(positions=20, check_positions=160) if args.quick else {}
    design = optimise_microgeometry(train.pairs[mesh], torques, max_root_stress_MPa=max_root,
                                    min_loaded_contact_ratio=min_lcr, **opts)
    rng = ppte_over_range(design)
    o, u = rng["by_design"]["optimised"], rng["by_design"]["unmodified"]
    print(f"{mesh}: optimised microgeometry over {', '.join(f'{t:g}' for t in rng['torques_Nm'])} N m")
    for name, value in design.values.items():
        print(f"  {name:34s} {value:.3f}")
    for key, d in tip_relief_drawing(train.pairs[mesh], design.values).items():
        gear = train.pairs[mesh].names[int(key[-1]) - 1]       # "gear_1" -> the user's name of gear 1
        print(f"  {gear}: tip relief {d.get('amount_um', 0):.1f} um from d = {d['start_diameter_mm']:.2f} mm, "
              f"length {d['relief_length_mm']:.2f} mm on the line of action")
    print(f"  PPTE worst over the range: optimised {o['worst_ppte_um']:.3g} um (at {o['worst_torque_Nm']:g} N m), "
          f"unmodified {u['worst_ppte_um']:.3g} um; at the design torque {o['design_torque_ppte_um']:.3g} um")
    if design.worse_than_unmodified_Nm:
        print("  worse than the unmodified flanks at " + ", ".join(f"{t:g}" for t in design.worse_than_unmodified_Nm)
              + " N m")
    # the data's [requirements] of this mesh's contact, judged on the exact LTCA (the same rows as every verdict),
    # beside the NLP's own stress limits
    check = evaluate_requirements(system, TrainDesign(train, {mesh: design.microgeometry}, name=mesh,
                                                      variables=("flanks",)), contact_meshes=[mesh],
                                  groups=("contact",))
    rows = [(r.name, r.value, r.limit, r.sense, r.unit) for r in check.rows]
    rows += [(f"{name} (exact LTCA, worst load case)", m["margin"], 0.0, ">=", m["unit"] or "-")
             for name, m in verified_margins(design).items() if name != "loaded_contact_ratio"]
    for r in check.failed:
        print(f"  {r.name}: what it would take: {r.what_it_would_take}")
    return _verdict(rows)


def _dynamics_model(system, kind: str):
    """The torsional model of the system (:func:`gearopt.cases.torsional_model`)."""
    from .cases import torsional_model

    if system.excitation != "engine":
        system.require("excitation", "gearopt dynamics (a driving torque: [excitation], or an [engine])")
    return torsional_model(system, kind)


def _dynamics_command(args) -> int:
    from .dynamics import speed_sweep

    system = _system(args)
    model = _dynamics_model(system, args.train)
    joints = tuple(args.joints) if args.joints is not None else tuple(system.joints)
    unknown = [j for j in joints if j not in system.joints]
    if unknown:
        raise GearoptInputError(f"{system.source}: --joints {' '.join(unknown)}: not a [joints.*] entry "
                                f"({', '.join(system.joints) or 'the data has none'})")
    speeds = args.speeds if args.speeds is not None else model.default_speeds_rpm
    sweep = speed_sweep(model, speeds, backlash=(args.backlash,), joints=joints, cycles=args.cycles,
                        run_in_cycles=args.run_in_cycles, shafts=())
    rows_j = sweep[sweep["element_type"] == "joint"]
    cols = [c for c in ("element", "speed_rpm", "peak_torque_Nm", "peak_axial_force_N", "min_torque_margin",
                        "min_axial_margin", "cycle_change") if c in rows_j.columns]
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        if len(rows_j):
            print(rows_j[cols].round(3).to_string(index=False))
        meshes = sweep[sweep["element_type"] == "mesh"]
        mcols = [c for c in ("element", "speed_rpm", "mean_force_N", "peak_drive_force_N", "rms_force_N",
                             "drive_separations_per_cycle") if c in meshes.columns]
        if len(meshes):
            print(meshes[mcols].round(3).to_string(index=False))
    rows = []
    for _, r in rows_j.iterrows():
        rows.append((f"slip margin {r['element']} at {r['speed_rpm']:g} rpm", float(r["min_torque_margin"]),
                     args.min_margin, ">=", "-"))
        rows.append((f"walk-off margin {r['element']} at {r['speed_rpm']:g} rpm", float(r["min_axial_margin"]),
                     args.min_margin, ">=", "-"))
    if not rows:
        print("no joint to check: the data has no [joints.*] entry (the table above gives the mesh loads)")
        return 0
    return _verdict(rows)


def _retarget(spec: dict, where: str, mesh: str | None, system) -> tuple[dict, str | None]:
    """The scene table with its mesh targets moved to ``mesh`` (``--mesh``), or -- when the scene names a mesh the
    data lacks and the data's train has one mesh -- to that mesh; returns the table and a notice (None: unchanged)."""
    from .design.scene_terms import quantity_kind, variable_kind

    items = [("variables", v, variable_kind(v.get("name", "")).target_kind) for v in spec.get("variables", [])]
    items += [(k, q, quantity_kind(q.get("quantity", "")).target_kind) for k in ("objectives", "limits")
              for q in spec.get(k, [])]
    targets = sorted({it.get("target") for _, it, kind in items if kind == "mesh"})
    train = system.train(spec.get("train", "spur"))
    if mesh is None:
        missing = [t for t in targets if t not in train.pairs]
        if not missing:
            return spec, None
        if len(train.pairs) != 1 or len(targets) != 1:
            raise GearoptInputError(f"{where} names mesh {missing[0]!r}, which {system.source} does not have "
                                    f"(meshes: {', '.join(train.pairs)}); give --mesh MESH")
        mesh = next(iter(train.pairs))
    elif mesh not in train.pairs:
        raise GearoptInputError(f"{system.source}: --mesh {mesh!r} is not a mesh of the data "
                                f"({', '.join(train.pairs)})")
    if len(targets) > 1:
        raise GearoptInputError(f"{where} names {len(targets)} meshes ({', '.join(targets)}): --mesh moves a scene "
                                "of one mesh")
    if targets == [mesh]:
        return spec, None
    out = {k: ([dict(it, target=mesh) if it.get("target") in targets else dict(it) for it in v]
               if k in ("variables", "objectives", "limits") else v) for k, v in spec.items()}
    return out, f"{where}: mesh {', '.join(targets)} of the scene file -> {mesh} of {system.source}"


def _scene_command(args) -> int:
    import tomllib

    from .design.scene_file import scene_from_data, scene_names

    try:
        with open(args.file, "rb") as fh:
            scenes = tomllib.load(fh)
    except OSError as exc:
        raise GearoptInputError(f"{args.file}: cannot read the scene file ({exc.strerror})") from None
    except tomllib.TOMLDecodeError as exc:
        raise GearoptInputError(f"{args.file}: not valid TOML: {exc}") from None
    names = scene_names(scenes)
    if not names:
        raise GearoptInputError(f"{args.file} declares no [scenes.<name>] table (docs/scenes.md)")
    name = args.scene or names[0]
    if name not in names:
        raise GearoptInputError(f"{args.file}: scene {name!r} is not declared ([scenes.*] holds {', '.join(names)})")
    if "trains" in scenes:
        system = system_from_data({k: v for k, v in scenes.items() if k != "scenes"}, source=str(args.file))
    else:
        system = _system(args)
    spec, notice = _retarget(dict(scenes["scenes"][name]), f"{args.file} [scenes.{name}]", args.mesh, system)
    if notice:
        print(notice)
    scene = scene_from_data({"scenes": {name: spec}}, name, train_data=system)
    if any(lc.dynamics is not None for lc in scene.load_cases):
        scene = dataclasses.replace(scene, dynamics_model=lambda kind: _dynamics_model(system, kind))
    try:
        result = scene.build().solve(starts=args.starts)
    except InfeasibleProblemError as err:  # the limits cannot all be met: a requirement fails, not bad input
        print(f"scene {name!r}: infeasible: {err}")
        print("verdict: FAIL (the scene's limits cannot all be met)")
        return 1
    print(f"scene {name!r}: {result.solve.status}")
    for key, value in result.values.items():
        print(f"  {key:44s} {value:.4g}")
    q = result.quantities
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        print(q.to_string(index=False))
    # margins of the limits; Ipopt meets an active bound to its tolerance (1e-8 scaled), so -1e-6 of the bound passes
    rows = [(f"{r['quantity']} {r['target']} @{r['load_case']}", float(r["margin"]),
             -1e-6 * max(1.0, abs(float(r["lower"] if pd.notna(r["lower"]) else r["upper"]))), ">=", str(r["unit"]))
            for _, r in q.iterrows() if r.get("role") == "limit" and pd.notna(r["margin"])]
    return _verdict(rows)


def run_script(main_function, argv: list[str] | None = None) -> int:
    """Run a script's ``main(argv)`` under the command line's exit-code rule: its own code (0 pass, 1 a requirement
    fails), 2 with a one-line ``error:`` message for bad input or a failed solve (any
    :class:`~gearopt.errors.GearoptError`), 3 for an internal error (the traceback with ``GEAROPT_TRACEBACK=1``)."""
    try:
        return int(main_function(argv) or 0)
    except GearoptError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    except Exception as err:  # noqa: BLE001 -- a bug, not bad input: one line (the traceback on request), exit 3
        if os.environ.get("GEAROPT_TRACEBACK"):
            raise
        print(f"internal error (a gearopt bug; GEAROPT_TRACEBACK=1 shows the traceback): {type(err).__name__}: {err}",
              file=sys.stderr)
        return 3


def _add_data(p) -> None:
    p.add_argument("--data", type=Path, default=None, metavar="FILE",
                   help="train data file (default: the packaged default data)")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="gearopt", description="gear geometry and design studies from the command "
                                                                 "line (exit 1 when a requirement fails)")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("pair", help="macro geometry and checks of one pair")
    p.add_argument("--teeth", type=int, nargs=2, required=True)
    p.add_argument("--module-mm", type=float, required=True)
    p.add_argument("--pressure-angle-deg", type=float, default=20.0)
    p.add_argument("--helix-angle-deg", type=float, default=0.0)
    p.add_argument("--face-width-mm", type=float, default=20.0)
    p.add_argument("--centre-distance-mm", type=float)
    p.add_argument("--profile-shifts", type=float, nargs=2)
    p.add_argument("--profile-shift1", type=float)
    p.add_argument("--shift-split", type=float, default=0.5, help="ISO/TR 4467 lambda")
    p.add_argument("--min-contact-ratio", type=float, default=1.0)
    p.set_defaults(run=_pair_command)
    t = sub.add_parser("train", help="gears and meshes of a train of the data")
    t.add_argument("kind", choices=["spur", "helical"])
    _add_data(t)
    t.set_defaults(run=_train_command)
    r = sub.add_parser("rate", help="ISO 6336 contact, root and scuffing safety of every mesh at the design loads "
                                     "(every factor computed)")
    _add_data(r)
    r.add_argument("--train", choices=["spur", "helical"], default="spur")
    r.add_argument("--min-s-h", type=float, default=None,
                   help="minimum contact safety S_H (default: the data's [requirements] min_S_H)")
    r.add_argument("--min-s-f", type=float, default=None,
                   help="minimum root safety S_F (default: the data's [requirements] min_S_F)")
    r.add_argument("--unit-factors", action="store_true",
                   help="load factors K_v, K_Hbeta, K_Halpha and life factors 1 (default: every factor computed)")
    r.set_defaults(run=_rate_command)
    m = sub.add_parser("microgeometry", help="PPTE-minimising tip relief of one spur mesh over its torque range")
    _add_data(m)
    m.add_argument("--train", choices=["spur", "helical"], default="spur")
    m.add_argument("--mesh", default=None, help="mesh name (default: the train's only mesh, else its root mesh)")
    m.add_argument("--quick", action="store_true", help="coarse NLP and check resolution")
    m.set_defaults(run=_microgeometry_command)
    d = sub.add_parser("dynamics", help="speed sweep of the timing train: joint slip and walk-off margins")
    _add_data(d)
    d.add_argument("--train", choices=["spur", "helical"], default="spur")
    d.add_argument("--speeds", type=float, nargs="+", default=None,
                   help="speeds of the driving shaft [rpm] (default: the model's, e.g. idle and overspeed of an "
                        "engine, the [excitation] speed)")
    d.add_argument("--joints", nargs="+", default=None, help="[joints.*] names (default: every joint of the data)")
    d.add_argument("--backlash", action=argparse.BooleanOptionalAction, default=True)
    d.add_argument("--cycles", type=int, default=1)
    d.add_argument("--run-in-cycles", type=int, default=1)
    d.add_argument("--min-margin", type=float, default=1.0, help="required slip and walk-off margin (default 1)")
    d.set_defaults(run=_dynamics_command)
    s = sub.add_parser("scene", help="solve a scene declared in a file ([scenes.NAME], docs/scenes.md)")
    s.add_argument("file", type=Path)
    s.add_argument("--scene", default=None, help="scene name (default: the first in the file)")
    _add_data(s)
    s.add_argument("--starts", type=int, default=1, help="multi-start count (default 1)")
    s.add_argument("--mesh", default=None, help="run the scene on this mesh of the data (a scene of one mesh)")
    s.set_defaults(run=_scene_command)
    args = parser.parse_args(argv)
    return run_script(lambda _: args.run(args))


if __name__ == "__main__":
    sys.exit(main())
