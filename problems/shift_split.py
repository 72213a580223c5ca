"""Profile-shift split at fixed centre distance for the meshes of the spur timing train.

At a fixed centre distance the sum x1 + x2 of a mesh is fixed; only its split is free. For every mesh of the packaged
spur train (or one, ``--mesh``) this runs both objectives of :func:`gearopt.design.shift_distribution.
optimise_shift_split` -- the largest smallest tip thickness, and balanced (minimax) root specific sliding -- subject
to the worst-case contact ratio >= 1.2, undercut, pointed tip (0.2 m_n), interference and the ISO/TR 4467 shift
limits, against the ISO/TR 4467 split (lambda = 0.5). It also sweeps x1 over [-1, 2] to show where the split is
feasible. Writes to ``out/shift_split/``:

- ``shift_split.csv``: one row per mesh and design (ISO/TR 4467, each optimum): shifts, tip thicknesses, root
  specific sliding, contact ratios, solver status and active constraints;
- ``sweep_<mesh>.csv`` and ``shift_split_<mesh>.png``: tip thickness and root specific sliding of both gears against
  x1, the feasible range shaded and the optima marked;
- ``summary.json``.

Usage: ``python problems/shift_split.py [--mesh crank-cam] [--quick] [--out DIR]`` (``--quick``: coarser sweep).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from gearopt.data import load_default_data, train_from_data  # noqa: E402
from gearopt.design.shift_distribution import OBJECTIVES, optimise_shift_split  # noqa: E402
from gearopt.errors import GearoptInputError  # noqa: E402
from gearopt.report import ltca_figures as figs  # noqa: E402
from gearopt.cli import run_script

DEFAULT_OUT = Path("out") / "shift_split"
LIMITS = dict(min_contact_ratio=1.2, min_tip_thickness_ratio=0.2)
X1_RANGE = (-1.0, 2.0)   # the NLP's bounds on x1


def sweep(pair, points: int) -> pd.DataFrame:
    """Tip thickness, root specific sliding, contact ratios and feasibility against x1 at the pair's fixed sum."""
    total = float(pair.profile_shifts[0] + pair.profile_shifts[1])
    rows = []
    for x1 in np.linspace(*X1_RANGE, points):
        row = {"profile_shift_1": x1, "profile_shift_2": total - x1}
        try:
            trial = replace(pair, profile_shifts=(float(x1), total - float(x1)), tip_diameters_mm=None)
            g = trial.geometry()
            margins = trial.constraints(worst_case=True, iso_tr_4467_limits=True, min_backlash_mm=None, **LIMITS)
            row.update(tip_thickness_1_mm=float(g["tip_thickness_mm"][0]),
                       tip_thickness_2_mm=float(g["tip_thickness_mm"][1]),
                       specific_sliding_root_1=float(g["specific_sliding_root"][0]),
                       specific_sliding_root_2=float(g["specific_sliding_root"][1]),
                       worst_case_transverse_contact_ratio=float(g["worst_case_transverse_contact_ratio"]),
                       feasible=bool(min(float(v) for v in margins.values()) >= 0.0),
                       limiting=min(margins, key=lambda k: float(margins[k])))
        except GearoptInputError as exc:      # geometry that cannot exist at this split
            row.update(feasible=False, limiting=str(exc).splitlines()[0][:80])
        rows.append(row)
    return pd.DataFrame(rows)


def study(pair) -> dict:
    """Both optima of one mesh (and the ISO/TR 4467 split) as table rows."""
    rows, results = [], {}
    for objective in OBJECTIVES:
        res = optimise_shift_split(pair, objective=objective, **LIMITS)
        results[objective] = res
        if not rows:
            rows.append(_row(res["table"]["iso_tr_4467"], "iso_tr_4467", "", 0, ""))
        rows.append(_row(res["table"]["ipopt"], objective, res["status"], res["iterations"],
                         ", ".join(res["active_constraints"])))
    return {"rows": rows, "results": results}


def _row(col: pd.Series, design: str, status: str, iterations: int, active: str) -> dict:
    return {"design": design, **{k: float(v) for k, v in col.items()}, "status": status, "iterations": iterations,
            "active_constraints": active}


def plot(mesh: str, sw: pd.DataFrame, rows: list[dict]):
    """Tip thickness and root specific sliding against x1, feasible range shaded, optima marked."""
    fig, axes = plt.subplots(2, 1, figsize=(6.4, 6.0), sharex=True)
    quantities = (("tip_thickness_{}_mm", "normal tip thickness [mm]"),
                  ("specific_sliding_root_{}", "specific sliding at the root [-]"))
    feasible = sw[sw["feasible"]]
    for ax, (key, label) in zip(axes, quantities):
        for i in (1, 2):
            ax.plot(sw["profile_shift_1"], sw[key.format(i)], label=f"gear {i}")
        if not feasible.empty:
            ax.axvspan(feasible["profile_shift_1"].min(), feasible["profile_shift_1"].max(), color="g", alpha=0.1,
                       label="feasible split")
        for r, marker in zip(rows, ("s", "o", "^")):
            ax.axvline(r["profile_shift_1"], color="k", lw=0.6, ls=":")
            ax.plot([r["profile_shift_1"]] * 2, [r[key.format(1)], r[key.format(2)]], marker, color="k", ms=5,
                    label=r["design"])
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[1].set_xlabel("profile shift of gear 1, x1 (x2 = sum - x1)")
    axes[0].set_title(f"{mesh}: profile-shift split at fixed centre distance")
    fig.tight_layout()
    return fig


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default=None, help="one mesh of the spur train (default: all)")
    parser.add_argument("--quick", action="store_true", help="coarser sweep (used by the tests)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    args = parser.parse_args(argv)
    train = train_from_data(load_default_data(args.data), "spur")
    meshes = list(train.pairs) if args.mesh is None else [args.mesh]
    unknown = [m for m in meshes if m not in train.pairs]
    if unknown:
        parser.error(f"--mesh {unknown[0]!r} is not a mesh of the spur train: {list(train.pairs)}")
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    table, summary = [], {}
    for mesh in meshes:
        pair = train.pairs[mesh]
        st = study(pair)
        sw = sweep(pair, 61 if args.quick else 301)
        sw.to_csv(args.out / f"sweep_{mesh}.csv", index=False)
        figs.save(plot(mesh, sw, st["rows"]), args.out / f"shift_split_{mesh}.png")
        feasible = sw[sw["feasible"]]["profile_shift_1"]
        summary[mesh] = {"sum_of_shifts": float(pair.profile_shifts[0] + pair.profile_shifts[1]),
                         "feasible_x1_range_sweep": ([float(feasible.min()), float(feasible.max())]
                                                     if len(feasible) else None),
                         **{r["design"]: {"profile_shifts": [r["profile_shift_1"], r["profile_shift_2"]],
                                          "worst_case_transverse_contact_ratio":
                                              r["worst_case_transverse_contact_ratio"],
                                          "status": r["status"]} for r in st["rows"]}}
        table += [{"mesh": mesh, **r} for r in st["rows"]]
    df = pd.DataFrame(table)
    df.to_csv(args.out / "shift_split.csv", index=False)
    elapsed = time.perf_counter() - t0
    (args.out / "summary.json").write_text(json.dumps({"meshes": summary, "limits": LIMITS, "time_s": elapsed},
                                                      indent=2) + "\n")
    print("Profile-shift split at fixed centre distance (worst-case contact ratio >= 1.2, tip >= 0.2 m_n, ISO/TR 4467)")
    for mesh in meshes:
        s = summary[mesh]
        parts = [f"{d} x1 {s[d]['profile_shifts'][0]:+.4f}" for d in ("iso_tr_4467", *OBJECTIVES)]
        print(f"  {mesh:10s} sum {s['sum_of_shifts']:.4f}: " + ", ".join(parts))
    print(f"time {elapsed:.2f} s; wrote {args.out}/")
    return 0


if __name__ == "__main__":
    sys.exit(run_script(main))
