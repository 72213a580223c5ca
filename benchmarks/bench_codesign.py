"""Co-design NLP (train root shift + per-flank tip reliefs, macro-symbolic smooth LTCA): build and solve time against
the number of meshes, load cases and positions, the smooth model's error against the exact LTCA at each optimum, and
the time to a verified 2 % PPTE error by the semi-infinite refinement against uniform dense sampling.

Scene (default data, spur train): variables ``root_profile_shift`` of the train (0..0.6) and the tip relief amount
and start of every flank the meshes load (``"gear:flank"`` targets); objective the largest PPTE of the meshes
(crank-cam, cam-AC, cam-FP: the first 1, 2 or 3) over the load cases (design torques x 1.0, 0.5, 1.5); limits the
LTCA contact stress (the unmodified spur mesh's maximum) and loaded contact ratio >= 1.2. Every optimum is
re-evaluated by the exact LTCA (1280 positions, :meth:`BuiltScene.solve_once` with ``check=True``): ``ppte_error`` is
the largest relative difference between the NLP's PPTE and the exact one over meshes and load cases.

Sweeps (each point one fresh build + one Ipopt solve, no refinement): meshes 1..3 at 1 load case and 40 positions;
load cases 1..3 at 1 mesh and 40 positions; positions 20..320 at 1 mesh, 1 load case. Then time-to-2 %: the
library's refinement (``solve()``) from a cold start on 40 and 80 positions and warm-started from the sequential
answer (micro-only at the data's root shift, itself refined: its time is ``sequential_s``), against one solve on
uniform grids of 160, 320, 640 positions.
Ratios are to the 40-position, 1-mesh, 1-case point measured in the same run.

Writes ``benchmarks/results/codesign.json`` and ``benchmarks/results/codesign.png``.
Run: ``python benchmarks/bench_codesign.py`` (a few minutes) or ``--quick`` (the test suite's smoke run, seconds:
20 and 40 positions, the 1-mesh, 1-case, 40-position point solved once and shared by the three sweeps, one uniform
grid of 80 positions, no refinements).
"""

from __future__ import annotations

import argparse
import json
import platform
import time
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import gearopt as go  # noqa: E402
from gearopt.contact.ltca import ltca  # noqa: E402
from gearopt.data import values  # noqa: E402
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene  # noqa: E402
from gearopt.cases.timing_train import MESHES  # noqa: E402
from gearopt.design.train_design import loaded_flanks  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
FRACTIONS = (1.0, 0.5, 1.5)


def scene(train, data_loads, meshes, cases, options):
    load_cases = [LoadCase(f"{f:g}x", {m: data_loads[m] * f for m in meshes}) for f in FRACTIONS[:cases]]
    flanks = sorted({f for fl in loaded_flanks(train, meshes).values() for f in fl})
    variables = [DesignVariable("root_profile_shift", "train", lower=0.0, upper=0.6)] + [
        DesignVariable(n, f) for f in flanks for n in ("tip_relief_um", "tip_relief_start_roll_deg")]
    limits = []
    for m in meshes:
        stress = max(ltca(train.pairs[m], lc.mesh_torque_Nm(m)).max_contact_stress_MPa for lc in load_cases)
        limits += [Limit("max_contact_stress_MPa", m, upper=stress), Limit("loaded_contact_ratio", m, lower=1.2)]
    return Scene("bench", train=train, load_cases=load_cases, variables=variables,
                 objectives=[Objective("ppte_um", m) for m in meshes], limits=limits, ltca_options=options)


def point(train, loads, meshes, cases, positions, refine=False, warm=None):
    t0 = time.perf_counter()
    sc = scene(train, loads, meshes, cases, {"positions": positions})
    built = sc.build() if warm is None else sc.build(positions=warm.positions, initial=warm.values)
    t_build = time.perf_counter() - t0
    t0 = time.perf_counter()
    try:
        result = built.solve() if refine else built.solve_once()
    except go.SolveError as exc:
        return {"meshes": len(meshes), "load_cases": cases, "positions": positions, "failed": type(exc).__name__}
    t_solve = time.perf_counter() - t0
    ex = result.exact_check
    out = {"meshes": len(meshes), "load_cases": cases, "positions": positions, "build_s": t_build,
           "solve_s": t_solve, "ipopt_s": float(result.solve.solve_time_s or 0.0),
           "ipopt_iterations": int(result.solve.iterations), "ppte_error": float(ex["ppte_um_error"].max()),
           "stress_error": float(ex["max_contact_stress_MPa_error"].max()),
           "exact_max_ppte_um": float(ex["ppte_um"].max()),
           "root_profile_shift": result.values["train.root_profile_shift"]}
    if refine:
        out.update(refinements=result.refinements, final_positions=int(result.refinement["positions"].iloc[-1]),
                   status=result.refinement.attrs["status"])
    return out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="seconds: the test suite's smoke run, no refinements")
    parser.add_argument("--full", action="store_true", help="three meshes and load cases, up to 640 positions")
    parser.add_argument("--out", type=Path, default=RESULTS, help="results directory (default benchmarks/results)")
    args = parser.parse_args(argv)
    mode = "quick" if args.quick else ("full" if args.full else "default")
    warnings.simplefilter("ignore")
    loads = go.load_system().design_torques_Nm()
    train = go.load_default_train("spur")
    names = list(MESHES)
    t_all = time.perf_counter()
    counts = {"quick": (1,), "default": (1, 2), "full": (1, 2, 3)}[mode]
    if mode == "quick":       # the one configuration of the three quick sweeps (1 mesh, 1 load case, 40 positions)
        base = point(train, loads, names[:1], 1, 40)                           # solved once, its row in each
        sweeps = {"meshes": [base], "load_cases": [dict(base)],
                  "positions": [point(train, loads, names[:1], 1, 20), dict(base)]}
    else:
        sweeps = {"meshes": [point(train, loads, names[:n], 1, 40) for n in counts],
                  "load_cases": [point(train, loads, names[:1], c, 40) for c in counts],
                  "positions": [point(train, loads, names[:1], 1, p)
                                for p in {"default": (20, 40, 80), "full": (20, 40, 80, 160, 320)}[mode]]}
    dense = {"quick": (80,), "default": (160, 320), "full": (160, 320, 640)}[mode]
    to_2pct = {f"uniform_{p}": point(train, loads, names[:1], 1, p) for p in dense}
    if mode != "quick":
        t0 = time.perf_counter()
        micro = Scene("micro", train=train, load_cases=[LoadCase("1x", {"crank-cam": loads["crank-cam"]})],
                      variables=[DesignVariable(n, f) for f in ("crank:driving", "cam:driven")
                                 for n in ("tip_relief_um", "tip_relief_start_roll_deg")],
                      objectives=[Objective("ppte_um", "crank-cam")],
                      limits=scene(train, loads, names[:1], 1, {}).limits).build().solve()
        t_micro = time.perf_counter() - t0
        warm = point(train, loads, names[:1], 1, 40, refine=True, warm=micro)
        warm.update(sequential_s=t_micro, sequential_exact_ppte_um=float(micro.exact_check["ppte_um"].max()),
                    sequential_refinements=micro.refinements)
        to_2pct = {"refinement_from_40": point(train, loads, names[:1], 1, 40, refine=True),
                   "refinement_from_80": point(train, loads, names[:1], 1, 80, refine=True),
                   "refinement_warm_from_sequential": warm, **to_2pct}
    base = sweeps["positions"][1]
    for rows in (*sweeps.values(), to_2pct.values()):
        for r in rows:
            if "solve_s" in r:
                r["time_ratio_to_base"] = (r["build_s"] + r["solve_s"]) / (base["build_s"] + base["solve_s"])
    result = {"quick": args.quick, "mode": mode, "platform": platform.platform(), "python": platform.python_version(),
              "total_s": time.perf_counter() - t_all, "sweeps": sweeps, "time_to_2_percent": to_2pct}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "codesign.json").write_text(json.dumps(result, indent=2) + "\n")

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for key, marker in (("meshes", "o"), ("load_cases", "s"), ("positions", "^")):
        rows = [r for r in sweeps[key] if "solve_s" in r]
        axes[0].plot([r[key] for r in rows], [r["build_s"] + r["solve_s"] for r in rows], marker=marker, label=key)
    axes[0].set_xscale("log")
    axes[0].set_xlabel("meshes / load cases / positions")
    axes[0].set_ylabel("build + solve + exact check [s]")
    axes[0].legend()
    axes[0].set_title("co-design NLP cost")
    for name, r in to_2pct.items():
        if "solve_s" in r:
            axes[1].scatter(r["build_s"] + r["solve_s"], 100 * r["ppte_error"], label=name)
    for r in sweeps["positions"]:
        if "solve_s" in r:
            axes[1].scatter(r["build_s"] + r["solve_s"], 100 * r["ppte_error"], marker="x", color="grey")
    axes[1].axhline(2.0, color="k", lw=0.8, ls="--")
    axes[1].set_xscale("log")
    axes[1].set_yscale("log")
    axes[1].set_xlabel("time [s]")
    axes[1].set_ylabel("smooth vs exact PPTE at the optimum [%]")
    axes[1].legend(fontsize=8)
    axes[1].set_title("time against verified error (x: position sweep)")
    fig.tight_layout()
    fig.savefig(args.out / "codesign.png", dpi=120)
    print(json.dumps(to_2pct, indent=1))
    return result


if __name__ == "__main__":
    main()
