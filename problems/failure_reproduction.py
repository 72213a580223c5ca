"""Cam-gear walk-off at overspeed: long-run creep statistics of the shaft-hub friction joints, helical vs spur.

The main job (``cam_gear_walkoff.py``) maps the whole envelope with a few cycles per point; at overspeed the lash
model rattles and the joints' peak demands vary from cycle to cycle, so the creep of a marginal fit needs more
cycles. This script runs one speed (default the 3300 rpm motoring overspeed) for every damper state with
``--cycles`` recorded cycles (default 10) and reports, per train, damper state and fit case, the peak slip
utilisation, the mean axial creep per engine cycle with its cycle-to-cycle standard deviation and largest single
cycle, and the minutes to walk the stated distance at the mean creep (``gearopt.dynamics.joint_friction``,
``gearopt.dynamics.walk_off_envelope``).

Usage: ``python problems/failure_reproduction.py [--quick] [--out DIR] [--speed RPM] [--cycles N]``.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from gearopt.data import System, load_system
from gearopt.cases.timing_train import default_timing_model
from gearopt.dynamics.walk_off_envelope import (
    DAMPER_STATES,
    ENVELOPE_EXTRA_SPEED_RPM,
    joint_envelope,
)
from gearopt.report import to_markdown, write_table
from gearopt.studies.failure import CREEP_NOISE_UM, WALK_OFF_DISTANCE_MM
from gearopt.cli import run_script

DEFAULT_OUT = Path("out") / "failure_reproduction"


def creep_statistics(system: System, speed_rpm: float, cycles: int, damper_states, levels: int = 4,
                     joints=("cam", "crank")) -> pd.DataFrame:
    """Envelope rows of both trains at one speed with ``cycles`` recorded cycles after one run-in cycle, plus the
    minutes to walk :data:`WALK_OFF_DISTANCE_MM` at the mean creep (inf when it does not creep off the nose)."""
    frames = []
    for kind in ("helical", "spur"):
        frames.append(joint_envelope(default_timing_model(kind, system=system), joints, speeds_rpm=[speed_rpm],
                                     damper_states=damper_states, levels=levels, cycles=cycles, run_in_cycles=1))
    df = pd.concat(frames, ignore_index=True)
    for col in ("axial_creep_um_per_cycle", "axial_creep_um_cycle_std", "max_cycle_axial_creep_um"):
        df[col] = df[col].where(df[col].abs() >= CREEP_NOISE_UM, 0.0)  # integration noise of a joint that stuck
    creep = df["axial_creep_um_per_cycle"]
    with np.errstate(divide="ignore"):
        df["minutes_to_walk_distance"] = np.where(creep > 0, WALK_OFF_DISTANCE_MM * 1e3 / creep / (speed_rpm / 2.0),
                                                  np.inf)
    return df


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true",
                        help="cam joint, degraded damper, nominal and sub-tolerance fits, 2 cycles (the tests)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--speed", type=float, default=ENVELOPE_EXTRA_SPEED_RPM, help="engine speed [rpm]")
    parser.add_argument("--cycles", type=int, default=10, help="recorded engine cycles per point")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="your own engine and train data file (TOML; default: the packaged data)")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    system = load_system(args.data)
    cycles = 2 if args.quick else args.cycles
    states = ("degraded",) if args.quick else tuple(DAMPER_STATES)
    df = creep_statistics(system, args.speed, cycles, states, levels=1 if args.quick else 4,
                          joints=("cam",) if args.quick else ("cam", "crank"))
    args.out.mkdir(parents=True, exist_ok=True)
    write_table(df, args.out, "creep_statistics")
    cols = ["train", "joint", "damper_state", "fit_case", "capacity_N", "max_rigid_utilisation", "slip_um_per_cycle",
            "axial_creep_um_per_cycle", "axial_creep_um_cycle_std", "max_cycle_axial_creep_um",
            "minutes_to_walk_distance"]
    shown = df[df["fit_case"] != ""][cols]
    lines = [f"# Friction-joint creep at {args.speed:g} rpm over {cycles} engine cycles", "",
             (f"Helical vs spur timing train, damper states {', '.join(states)}; creep + off the shaft nose; "
             f"minutes to walk {WALK_OFF_DISTANCE_MM:g} mm at the mean creep. Run time "
             f"{time.perf_counter() - t0:.1f} s."), "", to_markdown(shown.replace({np.inf: "inf"})), ""]
    (args.out / "report.md").write_text("\n".join(lines) + "\n")
    summary = {}
    # headline: the toleranced fits (weakest..strongest); the sub-tolerance fits beside it
    for (train, joint), g_all in shown.groupby(["train", "joint"]):
        below = g_all["fit_case"].str.endswith("x_weakest")
        g = g_all[~below] if (~below).any() else g_all
        i = g["axial_creep_um_per_cycle"].idxmax()
        summary.setdefault(train, {})[joint] = {
            "max_slip_utilisation": float(g["max_rigid_utilisation"].max()),
            "max_mean_axial_creep_um_per_cycle": float(g.loc[i, "axial_creep_um_per_cycle"]),
            "its_cycle_std_um": float(g.loc[i, "axial_creep_um_cycle_std"]),
            "at": {"damper_state": str(g.loc[i, "damper_state"]), "fit_case": str(g.loc[i, "fit_case"])},
            "below_tolerance_max_mean_axial_creep_um_per_cycle":
                float(g_all.loc[below, "axial_creep_um_per_cycle"].max()) if below.any() else None}
    (args.out / "result.json").write_text(json.dumps({"speed_rpm": args.speed, "cycles": cycles,
                                                      "summary": summary}, indent=2) + "\n")
    for train, joints in summary.items():
        for joint, r in joints.items():
            print(f"{train:8s} {joint:6s} peak utilisation {r['max_slip_utilisation']:.2f}, largest mean creep "
                  f"{r['max_mean_axial_creep_um_per_cycle']:.3g} +- {r['its_cycle_std_um']:.2g} um/cycle "
                  f"({r['at']['damper_state']}, {r['at']['fit_case']})")
    print(f"wrote {args.out}/report.md, result.json and creep_statistics.csv")
    return 0


if __name__ == "__main__":
    sys.exit(run_script(main))
