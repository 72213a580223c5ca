"""The helix-angle decision as a trade-off front: crank-cam PPTE against the walk-off demand on the cam gear's joint.

The source study's helical cam gear walked off its shaft; the spur replacement was chosen by hand. A larger helix
angle lowers the transmission error (more overlap) but raises the axial thrust on every helical gear (F_a = F_t
tan beta, summed over the gear's meshes by :func:`gearopt.joints.walk_off.walk_off`). This script traces that
trade-off with :func:`gearopt.studies.pareto_front` on a train-level co-design scene over the default data
(:func:`gearopt.load_system`, :func:`gearopt.data.train_from_data`, or ``--data FILE``):

- variables: the train's helix angle (0 to 8 deg, the low-helix bound of ``problems/codesign.py``) and root-gear
  profile shift (0 to 0.6; every mesh follows at its fixed centre distance), and the tip relief (amount, start roll
  angle) of the two loaded flanks of the crank-cam mesh (``crank:driving``, ``cam:driven``): each point of the front
  has the best relief for its helix angle;
- objective: the largest PPTE of the crank-cam mesh over the design load cases (``[design_loads]`` torques of
  crank-cam, cam-AC and cam-FP at the rated speed; ``--quick``: the design torque only, else x
  ``torque_range_fractions``);
- limits: the crank-cam geometry limits (worst-case contact ratio, tip thickness, undercut, interference, ISO/TR
  4467 shift limits). The LTCA stress, temperature and loaded-contact-ratio limits of ``problems/codesign.py`` are
  left out to keep the front to the two quantities of the decision (with the stress and contact-ratio limits added,
  a trial run's PPTE end stopped at 3.7 deg instead of 8 deg: more local optima for the same question);
- front quantity: ``axial_utilisation`` of the cam joint (|axial force| / axial capacity of the ``[joints.cam]``
  press fit at the overspeed test speed with the torques x the largest range fraction) -- the inverse of its
  walk-off (axial) margin, 0 for a spur train. Its inverse is the margin; the utilisation is the front quantity
  because the margin is infinite at a helix angle of 0 (the spur end of the front). ``slip_utilisation`` (the
  combined torque and thrust of the fit) is not used: for this fit the torque dominates it, and it changes by less
  than 0.1 % over the helix range.

Only the crank-cam mesh has LTCA quantities (one smooth LTCA model; the cam-AC and cam-FP meshes enter through
their torques and thrusts on the cam gear). The front is solved on the smooth LTCA at fixed positions and face
slices; every solved point is then re-solved by the scene's exact-LTCA refinement at its own walk-off demand
(:func:`gearopt.studies.verify_front`, ``ltca_options`` ``{"max_refinements": 1,
"helical_slices": 7}``; ``--quick``: no refinement, the exact check of the re-solve only): ``front.csv`` has the
front's smooth PPTE beside the exact LTCA's PPTE of each verified design and whether the two agree. Failed points
stay in the table with their status.

Affordability: ``--quick`` (4 points, 24 NLP positions, 7 face slices, one load case, the ends from 3 starts) runs
in about 30-35 s on one core (2026-11-29: 33.7 s, most of it the ends' six solves); the default (9 points, 40
positions, three load cases, 4 starts, one refinement per point) in about 3 minutes (measured here: 176 s serially; the front ran monotone from 2.25 um at 8 deg to 3.61 um
at 0 deg, and the exact LTCA agreed within the refinement's 2 % at 7 of the 9 points).

Writes ``<out>/front.csv``, ``<out>/front.png`` and ``<out>/summary.json``.

Usage: ``python problems/helix_front.py [--points 9] [--executor serial|processes|dask] [--quick] [--out DIR]
[--data FILE]``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import numpy as np
import pandas as pd

from gearopt.data import System, load_system, train_from_data, values
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.cases.timing_train import GEOMETRY_LIMITS, MESHES
from gearopt.studies import pareto_front, verify_front
from gearopt.cli import run_script

MESH, JOINT, QUANTITY = "crank-cam", "cam", "axial_utilisation"
FLANKS = ("crank:driving", "cam:driven")
MAX_HELIX_ANGLE_DEG = 8.0
DEFAULT_OUT = Path("out") / "helix_front"


def build_scene(system: System, quick: bool) -> tuple[Scene, dict]:
    """The train-level scene of the module docstring on ``system`` and its settings (JSON-ready)."""
    data = system.data
    v = values(data)
    loads = v["design_loads"]
    train = train_from_data(data, "spur")
    speed, overspeed = float(loads["speed_rpm"]), float(v["engine"]["overspeed_test_speed_rpm"])
    fractions = [1.0] if quick else [float(f) for f in loads["torque_range_fractions"]]
    top = max(float(f) for f in loads["torque_range_fractions"])
    design = system.design_torques_Nm()
    cases = [LoadCase(f"{f:g}x", {m: design[m] * f for m in MESHES}, speed_rpm=speed) for f in fractions]
    over = LoadCase("overspeed", {m: design[m] * top for m in MESHES}, speed_rpm=overspeed)
    names = tuple(c.name for c in cases)
    variables = [DesignVariable("helix_angle_deg", "train", lower=0.0, upper=MAX_HELIX_ANGLE_DEG),
                 DesignVariable("root_profile_shift", "train", lower=0.0, upper=0.6)]
    variables += [DesignVariable(name, flank) for flank in FLANKS
                  for name in ("tip_relief_um", "tip_relief_start_roll_deg")]
    limits = [Limit("geometry_limits", MESH, options=GEOMETRY_LIMITS)]
    ltca_options = {"positions": 24 if quick else 40, "helical_slices": 7}
    scene = Scene("helix angle front", train=train, load_cases=[*cases, over], variables=variables,
                  objectives=[Objective("ppte_um", MESH, aggregate="max", load_cases=names)], limits=limits,
                  ltca_options=ltca_options, data=system)
    settings = {"load_cases_Nm": {c.name: dict(c.torque_Nm) for c in cases}, "speed_rpm": speed,
                "overspeed_rpm": overspeed, "overspeed_torques_Nm": dict(over.torque_Nm),
                "max_helix_angle_deg": MAX_HELIX_ANGLE_DEG,
                "ltca_options": ltca_options, "quick": quick}
    return scene, settings


def run(quick: bool = False, data_file: Path | None = None, points: int | None = None, executor: str = "serial"):
    """Trace and verify the front; returns (front, verification table, merged table, settings)."""
    scene, settings = build_scene(load_system(data_file), quick)
    points = points or (4 if quick else 9)
    front = pareto_front(scene, QUANTITY, JOINT, points=points, starts=3 if quick else 4, executor=executor)
    check = verify_front(front, scene, executor,
                         ltca_options={"max_refinements": 0 if quick else 1, "helical_slices": 7})
    table = front.table.merge(check.drop(columns=["status", "error"]), on="point", how="left")
    q = front.quantity_column
    with np.errstate(divide="ignore"):
        table.insert(table.columns.get_loc(q) + 1, f"axial_margin[{JOINT}]", 1.0 / table[q].to_numpy(float))
    settings.update(points=points, executor=str(executor))
    return front, check, table, settings


def plot(front, table: pd.DataFrame):
    """PPTE against the cam joint's axial utilisation: the smooth front, the exact LTCA of each verified design,
    failed points marked; helix angles annotated."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.0, 4.6))
    q, obj = front.quantity_column, front.objective_column
    ok = table[table["status"] == "ok"]
    ax.plot(100 * ok[q], ok[obj], "o-", color="C0", label="ε-constraint front (smooth LTCA)")
    ver = table[table["verification"] == "ok"]
    if len(ver):
        ax.plot(100 * ver[f"verified:{q}"], ver["exact_objective"], "s", color="C3", mfc="none", ms=8,
                label="exact LTCA of the re-solved design")
        for _, r in ver[ver["verified"] == True].iterrows():  # noqa: E712 (a column of bools)
            ax.plot(100 * r[f"verified:{q}"], r["exact_objective"], "s", color="C3", ms=8)
    for _, r in ok.iterrows():
        ax.annotate(f"β {r['train.helix_angle_deg']:.2f}°", (100 * r[q], r[obj]), xytext=(4, 6),
                    textcoords="offset points", fontsize=7)
    for _, r in table[table["status"] != "ok"].iterrows():
        ax.axvline(100 * r["epsilon"], color="C1", ls=":", lw=0.8)
    if (table["status"] != "ok").any():
        ax.plot([], [], color="C1", ls=":", label="failed points")
    ax.set_xlabel(f"axial utilisation of the {JOINT} joint at overspeed [%] (= 100 / walk-off margin)")
    ax.set_ylabel(f"largest PPTE of {MESH} [µm]")
    ax.set_title("Helix angle: transmission error against walk-off demand (filled: exact and smooth agree)",
                 fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return fig


def write(front, table: pd.DataFrame, settings: dict, out: Path, elapsed_s: float) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    table.to_csv(out / "front.csv", index=False)
    plot(front, table).savefig(out / "front.png", dpi=110)
    q, obj = front.quantity_column, front.objective_column
    cols = ["point", "status", "verification", "verified", "train.helix_angle_deg", "train.root_profile_shift", q,
            f"axial_margin[{JOINT}]", obj, "exact_objective"]
    points = [{c: _json(r.get(c)) for c in cols} for _, r in table.iterrows()]
    summary = {"scene": front.scene, "objective": obj, "quantity": q, "sense": front.sense, "units": front.units,
               "settings": settings, "ends": front.ends, "points": points,
               "failed": int((table["status"] != "ok").sum()),
               "verification_failed": int((table["verification"] != "ok").sum()),
               "verified": int((table["verified"] == True).sum()),  # noqa: E712
               "elapsed_s": elapsed_s}
    (out / "summary.json").write_text(json.dumps(summary, indent=1, default=_json) + "\n")
    return summary


def _json(v):
    if isinstance(v, (np.bool_, bool)):
        return bool(v)
    if isinstance(v, (np.floating, float)):
        return float(v) if np.isfinite(v) else str(float(v))
    if isinstance(v, np.integer):
        return int(v)
    return v


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=None, help="points of the front (default 9; --quick 4)")
    parser.add_argument("--executor", default="serial", help="serial, processes, dask or a scheduler address")
    parser.add_argument("--quick", action="store_true",
                        help="4 points, one load case, 24 NLP positions, no refinement of the re-solves (tests)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    args = parser.parse_args(argv)
    if args.points is not None and args.points < 3:
        parser.error(f"--points {args.points} must be >= 3")
    t0 = time.perf_counter()
    front, _, table, settings = run(args.quick, args.data, args.points, args.executor)
    summary = write(front, table, settings, args.out, time.perf_counter() - t0)
    cols = ["point", "status", "train.helix_angle_deg", front.quantity_column, front.objective_column,
            "exact_objective", "verified"]
    print(table[cols].to_string(index=False))
    print(f"{summary['verified']} of {len(table)} points verified by the exact LTCA, {summary['failed']} failed; "
          f"wrote {args.out}/front.csv, front.png, summary.json in {summary['elapsed_s']:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(run_script(main))
