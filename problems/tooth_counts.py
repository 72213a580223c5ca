"""Tooth counts of a spur train at its centre distances (for the packaged timing train: thesis section 3.4.1,
Table 3.1).

Enumerates integer tooth counts around the data's spur train, keeps those whose speed ratios stay within tolerance
of the reference -- the original helical train's where the data state each mesh's ``speed_ratio_error_percent``
(the timing train: the camshaft exactly 2:1, the lube-pump branch off by up to 3 % as the thesis accepted 2.7027 %;
``--ratio-tolerance MESH=PERCENT`` overrides), else the data's own tooth counts -- and whose centre distances profile
shift can close
within the ISO/TR 4467 and undercut limits; then optimises each candidate's shift split with Ipopt (largest
smallest worst-case contact ratio, and largest smallest tip thickness) and ranks them. With Bonmin in CasADi, a
relaxed mixed-integer model cross-checks the enumeration.

Writes to ``out/tooth_counts/`` (or ``--out``): ``candidates_contact_ratio.csv``, ``candidates_tip_thickness.csv``
(ranked), ``rejected.csv`` (every rejected assignment with its stage and reason), ``summary.json``.

Run: ``python problems/tooth_counts.py`` (``--quick``: +-1 tooth instead of +-4, used by the tests).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import casadi as ca

from gearopt.cli import run_script
from gearopt.data import load_system, values
from gearopt.errors import GearoptInputError
from gearopt.design.tooth_counts import bonmin_cross_check, enumerate_tooth_counts, tooth_count_study

DEFAULT_OUT = Path("out") / "tooth_counts"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="+-1 tooth per gear (used by the tests)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    parser.add_argument("--span", type=int, default=None, help="teeth +- span per gear (default 4, quick 1)")
    parser.add_argument("--ratio-tolerance", nargs="*", default=None, metavar="MESH=PERCENT",
                        help="allowed speed-ratio error of a mesh, percent (default: each mesh whose data state a "
                             "speed_ratio_error_percent is allowed that error rounded up to a whole percent, e.g. "
                             "the source study's accepted 2.7027 %% -> 3 %%)")
    parser.add_argument("--tolerance", type=float, default=0.0,
                        help="allowed speed-ratio error of every other mesh, percent (default 0)")
    args = parser.parse_args(argv)
    span = args.span if args.span is not None else (1 if args.quick else 4)
    out = args.out
    out.mkdir(parents=True, exist_ok=True)

    system = load_system(args.data)
    data = system.data
    train = system.train("spur")
    meshes = values(data)["meshes"]
    stated = {m: float(v["speed_ratio_error_percent"]) for m, v in meshes.items() if "speed_ratio_error_percent" in v}
    if args.ratio_tolerance is None:
        tolerances = {m: float(math.ceil(abs(e))) for m, e in stated.items() if e != 0.0}
    else:
        tolerances = {}
        for item in args.ratio_tolerance:
            mesh, sep, pct = item.partition("=")
            if not sep or mesh not in train.pairs:
                raise GearoptInputError(f"--ratio-tolerance {item!r}: give MESH=PERCENT with MESH one of "
                                        f"{', '.join(train.pairs)}")
            tolerances[mesh] = float(pct)
    # the original helical train's ratios where the data state the spur counts' error against it, else the teeth
    reference = "helical_original" if len(stated) == len(meshes) else "teeth"
    t0 = time.perf_counter()
    enumeration = enumerate_tooth_counts(train, reference=reference, system=system, span=span,
                                         default_tolerance_percent=args.tolerance,
                                         ratio_tolerance_percent=tolerances)
    t_enum = time.perf_counter() - t0
    studies = {}
    for key, objective in (("contact_ratio", "max_min_worst_case_contact_ratio"),
                           ("tip_thickness", "max_min_tip_thickness")):
        studies[key] = tooth_count_study(train, enumeration=enumeration, objective=objective)
        studies[key].table.to_csv(out / f"candidates_{key}.csv", index=False)
    enumeration.rejected.to_csv(out / "rejected.csv", index=False)

    bonmin = None
    if ca.has_nlpsol("bonmin"):
        b = bonmin_cross_check(enumeration)
        bonmin = {k: v for k, v in b.items()}
    summary = {
        "reference": ("original helical train (data: meshes.*.speed_ratio_error_percent, thesis Table 3.1)"
                      if reference == "helical_original" else "the train's own tooth counts"),
        "span": span, "tolerance_percent": enumeration.mesh_tolerance_percent,
        "gear_tolerance_percent": enumeration.gear_tolerance_percent,
        "enumeration_time_s": t_enum, "admissible": int(len(enumeration.admissible)),
        "rejected_by_stage": {str(k): int(v) for k, v in enumeration.rejected["stage"].value_counts().items()},
        "study_time_s": {k: s.elapsed_s for k, s in studies.items()},
        "ipopt_iterations": {k: [int(x["iterations"]) for x in s.solves] for k, s in studies.items()},
        "best": {}, "bonmin": bonmin,
    }
    for key, s in studies.items():
        if s.best is None:
            summary["best"][key] = None
            continue
        row = s.table.iloc[0]
        summary["best"][key] = {
            "teeth": {g: int(row[f"teeth_{g}"]) for g in train.gears},
            "objective_value": float(row["objective_value"]),
            "profile_shifts": {g: float(row[f"profile_shift_{g}"]) for g in train.gears},
            "max_abs_ratio_error_percent": float(row["max_abs_ratio_error_percent"]),
            "limiting": row["limiting"],
        }
    (out / "summary.json").write_text(json.dumps(summary, indent=2, default=str))

    print(f"tooth counts: {len(enumeration.admissible)} admissible, {len(enumeration.rejected)} rejected "
          f"(enumeration {t_enum:.2f} s); outputs in {out}")
    cols = ["rank"] + [f"teeth_{g}" for g in train.gears] + ["max_abs_ratio_error_percent", "objective_value",
                                                             "status"]
    for key, s in studies.items():
        print(f"\nranked by {s.objective}:")
        print(s.table[cols].to_string(index=False))
    if bonmin is not None:
        print(f"\nBonmin cross-check (widest shift margin): teeth {bonmin['teeth']}, margin "
              f"{bonmin['shift_margin']:.4f}; enumeration {bonmin['enumeration_shift_margin']:.4f}; "
              f"agrees: {bonmin['agrees']}")
    return 0


if __name__ == "__main__":
    sys.exit(run_script(main))
