"""One spur pair over its design-torque range: unmodified against optimised microgeometry.

Takes one mesh of the packaged spur train (default ``crank-cam``), its design torque from the data's
``[design_loads]`` and the torque range ``torque_range_fractions`` x that torque, and finds the tip relief (amounts and
starts, both gears) and profile crown that minimise the largest peak-to-peak transmission error (PPTE) over the range
(:func:`gearopt.design.optimise_microgeometry`: Ipopt on the smooth LTCA, contact-stress and loaded-contact-ratio
limits; the designs are re-scored with the exact LTCA). Writes to ``out/pair_microgeometry/<mesh>/``:

- ``comparison.csv``: exact-LTCA PPTE, peak contact stress, loaded contact ratio per design and load case;
- ``microgeometry.csv``: the optimised modification; ``starts.csv``: every Ipopt start;
- ``harris_map.csv`` and ``harris_map.png``: PPTE against torque (Harris map) of both designs on one figure;
- ``transmission_error.csv`` and ``transmission_error.png``: TE over one mesh cycle at the design torque;
- ``summary.json``: the headline numbers.

Usage: ``python problems/pair_microgeometry.py [--mesh crank-cam] [--quick] [--out DIR]``
(``--quick``: coarse NLP sampling, one start, a coarser exact check -- for tests).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from gearopt.contact.harris import harris_map
from gearopt.cli import run_script
from gearopt.errors import GearoptInputError
from gearopt.data import load_system
from gearopt.design import optimise_microgeometry
from gearopt.report import ltca_figures as figs

DEFAULT_OUT = Path("out") / "pair_microgeometry"


def run(mesh: str, quick: bool, data_path: Path | None = None) -> dict:
    """Optimise the pair's microgeometry over its torque range and compute the Harris maps (no files)."""
    system = load_system(data_path)
    pair = system.train("spur").pairs[mesh]
    t_design = system.design_torque_Nm(mesh)
    # the design torque first (optimise_microgeometry reports at the first load case), then the rest of the range
    torques = list(system.torque_range_Nm(mesh))
    min_lcr = system.requirements.min_loaded_contact_ratio
    settings = (dict(positions=20, check_positions=160, starts=1) if quick else {})
    timings = {}
    t0 = time.perf_counter()
    design = optimise_microgeometry(pair, torques, min_loaded_contact_ratio=min_lcr, **settings)
    timings["microgeometry_nlp_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    grid = np.linspace(0.25, 2.0, 8 if quick else 15) * t_design
    exact = dict(positions=160 if quick else 1280)
    maps = {"unmodified": harris_map(pair, None, grid, **exact),
            "optimised": harris_map(pair, design.microgeometry, grid, **exact)}
    timings["harris_maps_s"] = time.perf_counter() - t0
    return {"mesh": mesh, "pair": pair, "design": design, "torques": torques, "design_torque": t_design,
            "maps": maps, "timings": timings}


def write(out: Path, r: dict) -> dict:
    """Write the tables, figures and summary of :func:`run` to ``out``; returns the summary dict."""
    out.mkdir(parents=True, exist_ok=True)
    design, mesh, t = r["design"], r["mesh"], r["design_torque"]
    design.table.to_csv(out / "comparison.csv", index=False)
    pd.DataFrame([design.values]).to_csv(out / "microgeometry.csv", index=False)
    design.starts.to_csv(out / "starts.csv", index=False)
    harris = r["maps"]["unmodified"].merge(r["maps"]["optimised"], on="torque_Nm",
                                           suffixes=("_unmodified", "_optimised"))
    harris.to_csv(out / "harris_map.csv", index=False)
    figs.save(figs.plot_harris_map(r["maps"], title=f"{mesh}: PPTE against torque (exact LTCA)",
                                   design_range_Nm=(min(r["torques"]), max(r["torques"])),
                                   design_torque_Nm=r["design_torque"]), out / "harris_map.png")
    te_results = {f"unmodified, {t:g} N m": design.exact["unmodified"][t],
                  f"optimised, {t:g} N m": design.exact["optimised"][t]}
    figs.save(figs.plot_transmission_error(te_results, title=f"{mesh}: transmission error at the design torque"),
              out / "transmission_error.png")
    te = pd.DataFrame({"roll_deg": np.asarray(design.exact["unmodified"][t].position_roll_deg),
                       "te_unmodified_um": np.asarray(design.exact["unmodified"][t].transmission_error_um),
                       "te_optimised_um": np.asarray(design.exact["optimised"][t].transmission_error_um)})
    te.to_csv(out / "transmission_error.csv", index=False)
    table = design.table
    by = {name: table[table["design"] == name] for name in ("unmodified", "optimised")}
    summary = {
        "mesh": mesh, "design_torque_Nm": t, "torque_range_Nm": [float(x) for x in r["torques"]],
        "microgeometry": {k: float(v) for k, v in design.values.items()},
        "max_ppte_unmodified_um": float(by["unmodified"]["ppte_um"].max()),
        "max_ppte_optimised_um": float(by["optimised"]["ppte_um"].max()),
        "min_loaded_contact_ratio_optimised": float(by["optimised"]["loaded_contact_ratio"].min()),
        "max_contact_stress_unmodified_MPa": float(by["unmodified"]["max_contact_stress_MPa"].max()),
        "max_contact_stress_optimised_MPa": float(by["optimised"]["max_contact_stress_MPa"].max()),
        "solve_status": design.solve.status, "stage_time_s": r["timings"],
    }
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default=None, help="mesh of the spur train (default: its only mesh, else its root "
                                                      "mesh)")
    parser.add_argument("--quick", action="store_true", help="coarse settings (used by the tests)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    args = parser.parse_args(argv)
    system = load_system(args.data)
    train = system.train("spur")
    args.mesh = args.mesh or system.default_mesh("spur")
    if args.mesh not in train.pairs:
        raise GearoptInputError(f"{system.source}: --mesh {args.mesh!r} is not a mesh of the spur train "
                                f"({', '.join(train.pairs)})")
    r = run(args.mesh, args.quick, args.data)
    s = write(args.out / args.mesh, r)
    print(f"{args.mesh}: microgeometry over {', '.join(f'{t:g}' for t in s['torque_range_Nm'])} N m "
          f"({s['solve_status']})")
    print("  optimum: " + ", ".join(f"{k} {v:.3f}" for k, v in s["microgeometry"].items()))
    print(f"  largest PPTE over the range: unmodified {s['max_ppte_unmodified_um']:.2f} um -> optimised "
          f"{s['max_ppte_optimised_um']:.2f} um; peak contact stress {s['max_contact_stress_unmodified_MPa']:.0f} -> "
          f"{s['max_contact_stress_optimised_MPa']:.0f} MPa")
    print("stage times: " + ", ".join(f"{k} {v:.2f}" for k, v in s["stage_time_s"].items()))
    print(f"wrote {args.out / args.mesh}/")
    return 0


if __name__ == "__main__":
    sys.exit(run_script(main))
