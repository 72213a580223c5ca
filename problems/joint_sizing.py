"""Size the shaft-hub joints of the timing train for a target slip margin: required press-fit interference and
taper nut torque against the present design, with an ISO 286 fit suggestion.

Joints (default the data's ``crank``, ``cam`` press fits and ``ac``, ``fp`` taper fits): each is sized by
:func:`gearopt.design.joint_sizing.size_joint` (an Ipopt NLP) for ``--margin`` (default 1.5) at two load cases:

- ``rated``: the data's ``[design_loads]`` mesh torques carried through the train (:func:`gearopt.joints.walk_off`:
  joint torque and, for the helical train, the axial tooth force on each gear), at the engine's rated speed;
- ``overspeed``: the same loads x ``--overspeed-torque-factor`` (default 1: no dynamic amplification is modelled
  here -- the dynamics stage of ``problems/cam_gear_walkoff.py`` gives the torques over speed), at the overspeed test
  speed, where the centrifugal loss of the press fits is largest.

Shaft speeds follow the train's speed ratios. Weakest case: minimum interference of the tolerance band with the DIN
7190 smoothing loss, largest nut factor; stresses at the largest interference / smallest nut factor (hub and shaft
von Mises safety >= 1.2; nut thread stress <= 0.9 x the 830 MPa proof strength of class 10.9, ISO 898-1, which the
data's nut-torque notes assume). Both trains are sized by default (spur: no axial thrust; helical: the walk-off
case). Writes to ``out/joint_sizing/``: ``joint_sizing.csv`` (one row per train and joint), ``margins.csv`` (the
re-evaluated margins per load case), ``fits_<train>_<joint>.csv`` (ISO 286 candidates), ``summary.json``.

Usage: ``python problems/joint_sizing.py [--margin 1.5] [--train spur|helical|both] [--joints crank cam ac fp]
[--overspeed-torque-factor 1.0] [--quick] [--out DIR]``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import pandas as pd

from gearopt.cli import run_script
from gearopt import System
from gearopt.data import load_system
from gearopt.design.joint_sizing import (JointDemand, PressFitSpec, TaperFitSpec, press_fit_margin_table, size_joint,
                                         taper_margin_table)
from gearopt.errors import GearoptInputError, SolveError
from gearopt.joints.walk_off import walk_off

DEFAULT_OUT = Path("out") / "joint_sizing"
DEFAULT_JOINTS = ("crank", "cam", "ac", "fp")
PROOF_STRENGTH_MPA = 830.0   # ISO 898-1 class 10.9 proof stress, as the data's [joints.ac/fp] nut_torque notes use


def joint_demands(system: System, kind: str, overspeed_torque_factor: float = 1.0) -> dict[str, list[JointDemand]]:
    """{gear: [rated, overspeed] JointDemand} of every gear of the ``kind`` train at the design loads."""
    train = system.train(kind)
    rated_rpm, overspeed_rpm = system.speeds_rpm("joint sizing")
    res = walk_off(train, system.design_torques_Nm())
    out = {}
    for gear in train.gears:
        T, F = float(res.joint_torque_Nm[gear]), float(res.axial_force_N[gear])
        ratio = abs(float(train.speed_ratios[gear]))
        if T == 0.0 and F == 0.0:
            continue
        out[gear] = [JointDemand(T, F, ratio * rated_rpm, "rated"),
                     JointDemand(overspeed_torque_factor * T, overspeed_torque_factor * F,
                                 ratio * overspeed_rpm, "overspeed")]
    return out


def present_margins(system: System, joint: str, demands: list[JointDemand]) -> pd.DataFrame:
    """Margins of the present design at the demands, with the same weakest-case rules as the sizing."""
    if system.joints[joint].joint_type == "press_fit":
        spec = PressFitSpec.from_data(system, joint)
        return press_fit_margin_table(spec, spec.interference_um, demands, tolerance_band_um=spec.present_band_um)
    spec = TaperFitSpec.from_data(system, joint, proof_strength_MPa=PROOF_STRENGTH_MPA)
    return taper_margin_table(spec, spec.nut_torque_Nm, demands)


def size_all(system: System, trains: list[str], joints: list[str], margin: float, factor: float) -> dict:
    """Size every joint of every train; returns rows, margin tables and fit tables."""
    rows, margin_tables, fit_tables = [], [], {}
    for kind in trains:
        demands = joint_demands(system, kind, factor)
        for joint in joints:
            j = system.joints[joint].entries
            gear = j["gear"]
            if gear not in demands:
                continue
            dem = demands[gear]
            present = present_margins(system, joint, dem)
            row = {"train": kind, "joint": joint, "gear": gear, "type": j["joint_type"],
                   "rated_torque_Nm": dem[0].torque_Nm, "rated_axial_force_N": dem[0].axial_force_N,
                   "overspeed_rpm": dem[1].speed_rpm, "target_margin": margin,
                   "present_min_combined_margin": float(present["combined_margin"].min())}
            if j["joint_type"] == "press_fit":
                row.update(present_fit=j["fit"], present_interference_min_um=j["diametral_interference_min_um"],
                           present_interference_max_um=j["diametral_interference_max_um"])
            else:
                row.update(present_nut_torque_Nm=j["nut_torque_Nm"])
            try:
                s = size_joint(system, joint, dem, target_margin=margin, proof_strength_MPa=PROOF_STRENGTH_MPA)
            except SolveError as exc:
                row.update(status=exc.status, note=str(exc).splitlines()[0])
                rows.append(row)
                continue
            row.update(status=s.solve.status, sized_min_combined_margin=float(s.margins["combined_margin"].min()),
                       active_constraints="; ".join(s.active_constraints))
            if s.joint_type == "press_fit":
                v = s.values
                row.update(sized_interference_um=v["interference_um"],
                           sized_interference_min_um=v["interference_min_um"],
                           sized_interference_max_um=v["interference_max_um"], tolerance_band_um=v["tolerance_band_um"],
                           required_min_interference_um=v["required_min_interference_um"],
                           allowed_max_interference_um=v["allowed_max_interference_um"],
                           suggested_fit=s.fit["fit"] if s.fit else "none in the ISO 286 table",
                           suggested_fit_min_um=s.fit["min_um"] if s.fit else math.nan,
                           suggested_fit_max_um=s.fit["max_um"] if s.fit else math.nan)
                fit_tables[f"{kind}_{joint}"] = s.fits
            else:
                row.update(sized_nut_torque_Nm=s.values["nut_torque_Nm"], sized_preload_min_N=s.values["preload_min_N"],
                           sized_preload_max_N=s.values["preload_max_N"])
            rows.append(row)
            for label, table in (("present", present), ("sized", s.margins)):
                t = table.reset_index()
                t.insert(0, "design", label)
                t.insert(0, "joint", joint)
                t.insert(0, "train", kind)
                margin_tables.append(t)
    return {"rows": rows, "margins": margin_tables, "fits": fit_tables}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--margin", type=float, default=1.5, help="target slip margin (default 1.5)")
    parser.add_argument("--train", choices=("spur", "helical", "both"), default="both")
    parser.add_argument("--joints", nargs="+", default=None,
                        help="joints of [joints.*] (default: the timing train's crank, cam, AC and FP joints when the "
                             "data has them, else every joint)")
    parser.add_argument("--overspeed-torque-factor", type=float, default=1.0,
                        help="torque factor of the overspeed case over the design loads (default 1)")
    parser.add_argument("--quick", action="store_true", help="accepted for uniformity (the sizing is fast)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    args = parser.parse_args(argv)
    system = load_system(args.data)
    system.require("joints", "joint sizing")
    if args.joints is None:
        args.joints = [j for j in DEFAULT_JOINTS if j in system.joints] or list(system.joints)
    unknown = [j for j in args.joints if j not in system.joints]
    if unknown:
        raise GearoptInputError(f"{system.source}: --joints {' '.join(unknown)}: not a [joints.*] entry "
                                f"({', '.join(system.joints)})")
    if not args.margin >= 1.0:
        parser.error(f"--margin {args.margin} must be >= 1")
    if not args.overspeed_torque_factor > 0.0:
        parser.error(f"--overspeed-torque-factor {args.overspeed_torque_factor} must be > 0")
    trains = ["spur", "helical"] if args.train == "both" else [args.train]
    t0 = time.perf_counter()
    r = size_all(system, trains, args.joints, args.margin, args.overspeed_torque_factor)
    elapsed = time.perf_counter() - t0
    args.out.mkdir(parents=True, exist_ok=True)
    table = pd.DataFrame(r["rows"])
    table.to_csv(args.out / "joint_sizing.csv", index=False)
    pd.concat(r["margins"], ignore_index=True).to_csv(args.out / "margins.csv", index=False)
    for key, fits in r["fits"].items():
        fits.to_csv(args.out / f"fits_{key}.csv", index=False)
    summary = {"target_margin": args.margin, "overspeed_torque_factor": args.overspeed_torque_factor,
               "time_s": elapsed,
               "joints": [{k: (v if not isinstance(v, float) or math.isfinite(v) else str(v)) for k, v in row.items()}
                          for row in r["rows"]]}
    (args.out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    print(f"Joint sizing for slip margin {args.margin:g} at the design loads (rated and overspeed)")
    for row in r["rows"]:
        head = f"  {row['train']:7s} {row['joint']:5s} present margin {row['present_min_combined_margin']:.2f}"
        if "sized_min_combined_margin" not in row:
            print(f"{head}: {row['status']} ({row.get('note', '')})")
        elif row["type"] == "press_fit":
            print(f"{head} ({row['present_fit']}); needs interference >= {row['required_min_interference_um']:.1f} um "
                  f"(allowed <= {row['allowed_max_interference_um']:.0f} um): fit {row['suggested_fit']}")
        else:
            print(f"{head} (nut {row['present_nut_torque_Nm']:g} N m); needs nut torque "
                  f"{row['sized_nut_torque_Nm']:.1f} N m")
    print(f"time {elapsed:.2f} s; wrote {args.out}/")
    return 0


if __name__ == "__main__":
    sys.exit(run_script(main))
