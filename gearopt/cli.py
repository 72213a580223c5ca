"""The ``gearopt`` command line: quick geometry of a pair and the packaged default train.

    gearopt pair --teeth 38 76 --module-mm 3 --centre-distance-mm 172.24 [--profile-shift1 0.3124]
    gearopt pair --teeth 12 24 --module-mm 3 --profile-shifts 0.6 0.36
    gearopt train spur            # or helical
"""

from __future__ import annotations

import argparse
import sys

import pandas as pd

from .data import load_default_train
from .errors import GearoptError
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
    except GearoptError as err:
        print(f"check: {err}")
    return 0


def _train_command(args) -> int:
    train = load_default_train(args.kind)
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        print(train.gear_table().round(4))
        print()
        print(train.mesh_table().round(4))
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="gearopt", description="gear geometry from the command line")
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
    t = sub.add_parser("train", help="the packaged default timing train")
    t.add_argument("kind", choices=["spur", "helical"])
    t.set_defaults(run=_train_command)
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except GearoptError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
