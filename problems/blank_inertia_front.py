"""Minimum blank inertia against rim backing: the trade-off front of a gear blank's web and rim thickness.

Scene: the blank of one gear of the spur train (default the cam gear: bore, hub and face width from the data's
``[gears]`` and ``[joints.*]`` entries, :func:`gearopt.blank.blank_from_data`) with free web and rim thicknesses;
the polar inertia is minimised (a lighter cam gear lowers the torsional load of the timing train) and the rim
backup ratio ``m_B = s_R / h_t`` (ISO 6336-3:2019, 7.7: the rim thickness factor ``Y_B`` is 1 from ``m_B >= 1.2``) is
the second quantity of the front. The front runs from the lightest blank (thinnest rim) to the thickest rim the
bounds allow; the sensitivity report of the optimum at ``m_B >= 1.2`` gives the inertia one more unit of backing
costs (the limit's multiplier).

Writes to ``out/blank_inertia_front/``: ``front.csv``, ``front.png``, ``sensitivity.csv``, ``summary.json``.

Usage: ``python problems/blank_inertia_front.py [--gear cam] [--points 11] [--quick] [--out DIR]``.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

from gearopt.cli import run_script
from gearopt.data import System, load_system, train_from_data
from gearopt.errors import GearoptInputError
from gearopt.design.scene import DesignVariable, Limit, Objective, Scene
from gearopt.studies import pareto_front, sensitivity_report

DEFAULT_OUT = Path("out") / "blank_inertia_front"
THICKNESS_BOUNDS_MM = (4.0, 20.0)
MIN_BACKUP_RATIO = 1.2


def build_scene(gear: str, system: System) -> Scene:
    """The blank scene of ``gear`` in the spur train of ``system``."""
    lo, hi = THICKNESS_BOUNDS_MM
    return Scene(f"{gear} blank", train=train_from_data(system.data, "spur"), data=system,
                 variables=[DesignVariable("web_thickness_mm", gear, lo, hi),
                            DesignVariable("rim_thickness_mm", gear, lo, hi)],
                 objectives=[Objective("inertia_kgm2", gear)],
                 limits=[Limit("rim_backup_ratio", gear, lower=MIN_BACKUP_RATIO)])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--gear", default=None,
                        help="gear of the spur train whose blank is designed (default: the largest gear with a joint)")
    parser.add_argument("--points", type=int, default=11, help="points of the front (default 11)")
    parser.add_argument("--quick", action="store_true", help="5 points")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    args = parser.parse_args(argv)
    points = 5 if args.quick else args.points
    if points < 3:
        parser.error(f"--points {points} must be >= 3")
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    system = load_system(args.data)
    system.require("joints", "the blank design (a gear's bore and hub come from its joint)")
    if args.gear is None:
        held = [j.gear for j in system.joints.values()]
        args.gear = max(held, key=lambda g: (system.gears[g].teeth, -held.index(g)))
    if system.joint_of(args.gear) is None:
        raise GearoptInputError(f"{system.source}: --gear {args.gear!r} has no [joints.*] entry: its bore and hub "
                                f"are unknown (gears with joints: {', '.join(j.gear for j in system.joints.values())})")
    scene = build_scene(args.gear, system)
    front = pareto_front(scene, "rim_backup_ratio", args.gear, points=points)
    front.table.to_csv(args.out / "front.csv", index=False)
    front.plot().savefig(args.out / "front.png", dpi=110)
    optimum = scene.build().solve()
    report = sensitivity_report(optimum)
    report.to_csv(args.out / "sensitivity.csv")
    limit = report.table[report.table["name"].str.startswith("rim_backup_ratio")].iloc[0]
    summary = {"gear": args.gear, "points": len(front.table), "failed": int((front.table["status"] != "ok").sum()),
               "ends": front.ends, "optimum": optimum.values,
               "optimum_inertia_kgm2": float(optimum.quantities.query("quantity == 'inertia_kgm2'")["value"].item()),
               "inertia_per_backup_ratio_kgm2": float(limit["sensitivity"]),
               "log_sensitivity_backup_ratio": float(limit["log_sensitivity"]),
               "elapsed_s": time.perf_counter() - t0}
    (args.out / "summary.json").write_text(json.dumps(summary, indent=1))
    print(f"{args.gear} blank: inertia {front.ends['objective']['objective']:.5g}-"
          f"{front.ends['quantity']['objective']:.5g} kg m^2 over backup ratio "
          f"{front.ends['objective']['quantity']:.3g}-{front.ends['quantity']['quantity']:.3g}; {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_script(main))
