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

Peers (issue 29 item 8; JSON ``peers``): on the sweeps' base scene (crank-cam, 1 load case, 40 positions) the
library's ``scene.build().solve()`` (:func:`bench_optimum_quality.run_gearopt`: CPU seconds of build and solve,
``time.process_time``) against two methods on the exact model, in the same process: SciPy's SLSQP with 2-point
finite differences from the scene's declared start (:func:`bench_optimum_quality.run_slsqp`, at most
``SLSQP_MAXITER`` iterations) and SciPy's differential evolution (seed ``PEER_SEED``, ``DE_POPSIZE`` x variables
individuals, ``DE_MAXITER`` generations) with a Nelder-Mead polish of ``POLISH_PER_VARIABLE`` x variables evaluations
(:func:`bench_optimum_quality.run_global`; the limits as a penalty on the relative violation). Every design is judged
by one exact evaluator independent of the scene's models (:class:`bench_optimum_quality.ExactEvaluator`: the
microgeometry and pair rebuilt from the variable values, :func:`gearopt.ltca` at 1280 positions, every limit met
exactly); it is checked against the library's own exact check at the library's design (``evaluator_check``). Per
method: CPU seconds, the exact objective (largest PPTE, um) and feasibility of the design it returns, and the CPU
time at which it first reached a feasible design within ``REACH_TOLERANCE`` (1 %) of the best known (the best
feasible design of any method in the run): for the peers from their evaluation traces (CPU time of every exact
evaluation since their first; SLSQP's finite-difference and line-search points count, as its user could keep the
best one), for the library its total CPU time if its returned design is within it, else ``null``. Ratios are peer /
library.

Writes ``benchmarks/results/codesign.json`` and ``benchmarks/results/codesign.png`` (third panel: the peers, best
feasible exact PPTE against CPU time).
Run: ``python benchmarks/bench_codesign.py`` (a few minutes) or ``--quick`` (the test suite's smoke run, seconds:
20 and 40 positions, the 1-mesh, 1-case, 40-position point solved once and shared by the three sweeps, one uniform
grid of 80 positions, no refinements; the peers on tiny budgets, ``QUICK_PEERS``, and the library's solve with
``QUICK_LIBRARY_OPTIONS``: one start of an 8-point screen, no refinement, a 5-evaluation-per-variable polish).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import gearopt as go  # noqa: E402
from gearopt.contact.ltca import ltca  # noqa: E402
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene  # noqa: E402
from gearopt.cases.timing_train import MESHES  # noqa: E402
from gearopt.design.train_design import loaded_flanks  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
import bench_optimum_quality as boq  # noqa: E402

RESULTS = Path(__file__).resolve().parent / "results"
FRACTIONS = (1.0, 0.5, 1.5)
PEER_POSITIONS = 40                  # the peers' scene: the sweeps' base point (1 mesh, 1 load case)
PEER_SEED = 0                        # differential evolution's seed
DE_POPSIZE = 10                      # individuals per variable
DE_MAXITER = 60                      # generations (no early stop)
POLISH_PER_VARIABLE = 50             # Nelder-Mead evaluations per variable after DE
SLSQP_MAXITER = 100                  # SLSQP iterations (2-point finite-difference gradients)
REACH_TOLERANCE = 0.01               # "within 1 % of the best known"
QUICK_PEERS = {"DE_POPSIZE": 3, "DE_MAXITER": 2, "POLISH_PER_VARIABLE": 2, "SLSQP_MAXITER": 3}
QUICK_LIBRARY_OPTIONS = {"macro_starts": 1, "screen_samples": 8, "max_refinements": 0,
                         "polish_evaluations_per_variable": 5}


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


def _reach(trace, best: float) -> tuple[float | None, int | None]:
    """``(CPU s, evaluations)`` at the first entry of a ``[cpu_s, evaluations, best feasible so far]`` trace within
    ``REACH_TOLERANCE`` of ``best`` (``(None, None)``: never)."""
    for cpu, k, value in trace:
        if value <= best * (1.0 + REACH_TOLERANCE):
            return float(cpu), int(k)
    return None, None


def peers(train, loads, mesh: str, quick: bool) -> dict:
    """The library's ``solve()`` against SLSQP-FD and DE + Nelder-Mead on the exact model (module docstring)."""
    budget = dict(QUICK_PEERS) if quick else {"DE_POPSIZE": DE_POPSIZE, "DE_MAXITER": DE_MAXITER,
                                               "POLISH_PER_VARIABLE": POLISH_PER_VARIABLE,
                                               "SLSQP_MAXITER": SLSQP_MAXITER}
    options = {"positions": PEER_POSITIONS, **(QUICK_LIBRARY_OPTIONS if quick else {})}
    sc = scene(train, loads, [mesh], 1, options)
    lib = boq.run_gearopt(sc, None)
    built = lib["built"]
    ev = boq.evaluator_for(built)
    mine = boq.judged(ev, lib["values"])
    check = lib["result"].exact_check
    ours = check.loc[check["mesh"] == mesh, "ppte_um"].to_numpy(float)
    theirs = np.array([r["ppte_um"] for r in mine["load_cases"]])
    print(f"  peers: gearopt {lib['call']} {mine['objective']:.4f} um, feasible {mine['feasible']}, "
          f"{lib['cpu_s']:.1f} CPU-s", flush=True)
    slsqp = boq.run_slsqp(ev, built.initial_values(), maxiter=budget["SLSQP_MAXITER"])
    sj = slsqp["judged"]
    print(f"  peers: SLSQP-FD {sj['objective']:.4f} um, feasible {sj['feasible']}, {slsqp['evaluations']} "
          f"evaluations, {slsqp['cpu_s']:.1f} CPU-s", flush=True)
    de = boq.run_global(ev, PEER_SEED, popsize=budget["DE_POPSIZE"], maxiter=budget["DE_MAXITER"],
                        polish_per_variable=budget["POLISH_PER_VARIABLE"])
    dj = boq.judged(ev, de["values"]) if de["values"] is not None else None
    print(f"  peers: DE + Nelder-Mead {de['objective']} um, {de['evaluations']} evaluations, {de['cpu_s']:.1f} "
          f"CPU-s", flush=True)
    found = [mine["objective"] if mine["feasible"] else math.inf, sj["objective"] if sj["feasible"] else math.inf,
             *(t[2] for t in slsqp["trace"]), *(t[2] for t in de["trace"])]
    best = min(found)
    best = None if not math.isfinite(best) else best

    def row(method, call, cpu, judged_design, trace, extra):
        if best is None:
            reach = (None, None)
        elif trace is None:         # the library: its returned design only
            ok = judged_design is not None and judged_design["feasible"] and \
                judged_design["objective"] <= best * (1.0 + REACH_TOLERANCE)
            reach = (cpu, None) if ok else (None, None)
        else:
            reach = _reach(trace, best)
        return {"method": method, "call": call, "cpu_s": cpu,
                "exact_ppte_um": judged_design["objective"] if judged_design else None,
                "feasible": bool(judged_design["feasible"]) if judged_design else False,
                "violation": judged_design["violation"] if judged_design else None,
                "margins": judged_design["margins"] if judged_design else None,
                "values": judged_design["values"] if judged_design else None,
                "cpu_s_to_reach": reach[0], "evaluations_to_reach": reach[1], "trace": trace, **extra}

    evaluator_check = {"max_abs_ppte_difference_um": float(np.max(np.abs(ours - theirs)))
                       if len(ours) == len(theirs) else None,
                       "same_microgeometry": bool(lib["result"].microgeometry[mesh] == ev.microgeometry(lib["values"]))}
    rows = [row("gearopt", f"scene.build().{lib['call']}", lib["cpu_s"], mine, None, {
                    "ltca_options": options, "exact_ltca_calls": lib["ltca_calls"],
                    "ipopt_iterations": lib["ipopt_iterations"], "solves": lib["solves"],
                    "evaluator_check": evaluator_check}),
            row("slsqp_fd", f"scipy.optimize.minimize(method='SLSQP', maxiter={budget['SLSQP_MAXITER']}), 2-point "
                "finite differences, from the declared start", slsqp["cpu_s"], sj, slsqp["trace"], {
                    "evaluations": slsqp["evaluations"], "iterations": slsqp["iterations"],
                    "scipy_message": slsqp["scipy_message"],
                    "best_feasible_evaluated_um": slsqp["trace"][-1][2] if slsqp["trace"] else None}),
            row("de_nelder_mead", f"scipy.optimize.differential_evolution(seed={PEER_SEED}, "
                f"popsize={budget['DE_POPSIZE']}, maxiter={budget['DE_MAXITER']}) + Nelder-Mead "
                f"({budget['POLISH_PER_VARIABLE']} evaluations per variable)", de["cpu_s"], dj, de["trace"], {
                    "evaluations": de["evaluations"], "de_evaluations": de["de_evaluations"],
                    "de_cpu_s": de["de_cpu_s"], "failed_evaluations": de["failed_evaluations"]})]
    head = rows[0]

    def ratio(a, b):
        return None if a is None or b is None or b <= 0 else a / b

    return {"scene": {"mesh": mesh, "load_case": sc.load_cases[0].name, "torque_Nm": loads[mesh],
                      "positions": PEER_POSITIONS, "variables": ev.names, "lower": ev.low.tolist(),
                      "upper": ev.high.tolist(), "limits": [f"{lim.quantity} {'<=' if lim.upper is not None else '>='} "
                                                            f"{lim.upper if lim.upper is not None else lim.lower:g}"
                                                            for lim in sc.limits]},
            "settings": {"check_positions": boq.CHECK_POSITIONS, "penalty_um": boq.PENALTY_UM,
                         "reach_tolerance_relative": REACH_TOLERANCE, "seed": PEER_SEED,
                         **{k.lower(): v for k, v in budget.items()}},
            "best_known_ppte_um": best, "methods": rows,
            "ratio_cpu_to_reach": {r["method"]: ratio(r["cpu_s_to_reach"], head["cpu_s_to_reach"]) for r in rows[1:]},
            "ratio_cpu_total": {r["method"]: ratio(r["cpu_s"], head["cpu_s"]) for r in rows[1:]}}


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
    load_start = list(os.getloadavg())
    peer = peers(train, loads, names[0], args.quick)
    peer["load_average_1_5_15_min"] = {"start": load_start, "end": list(os.getloadavg())}
    result = {"quick": args.quick, "mode": mode, "platform": platform.platform(), "python": platform.python_version(),
              "total_s": time.perf_counter() - t_all, "sweeps": sweeps, "time_to_2_percent": to_2pct,
              "peers": peer}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "codesign.json").write_text(json.dumps(result, indent=2) + "\n")

    fig, axes = plt.subplots(1, 3, figsize=(16.5, 4))
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
    peers_panel(axes[2], peer)
    fig.tight_layout()
    fig.savefig(args.out / "codesign.png", dpi=120)
    print(json.dumps(to_2pct, indent=1))
    print(json.dumps({k: peer[k] for k in ("best_known_ppte_um", "ratio_cpu_to_reach", "ratio_cpu_total")}, indent=1))
    return result


def peers_panel(ax, peer: dict) -> None:
    """CPU time against the exact PPTE: the peers' best feasible design so far (steps), every method's returned
    design (markers), the best known + ``REACH_TOLERANCE`` (dashed)."""
    styles = {"gearopt": ("r", "*"), "slsqp_fd": ("C0", "o"), "de_nelder_mead": ("C2", "s")}
    for r in peer["methods"]:
        color, marker = styles[r["method"]]
        t = np.array(r["trace"] or [], float)
        if len(t):
            ax.step(np.append(t[:, 0], r["cpu_s"]), np.append(t[:, 2], t[-1, 2]), where="post", color=color,
                    label=f"{r['method']}: best feasible so far")
        if r["exact_ppte_um"] is not None:
            ax.plot([r["cpu_s"]], [r["exact_ppte_um"]], marker=marker, color=color, ms=12 if marker == "*" else 7,
                    mfc=color if r["feasible"] else "none", ls="none",
                    label=f"{r['method']}: returned ({'feasible' if r['feasible'] else 'infeasible'})")
    if peer["best_known_ppte_um"] is not None:
        ax.axhline(peer["best_known_ppte_um"] * (1 + REACH_TOLERANCE), color="k", lw=0.8, ls="--",
                   label=f"best known + {100 * REACH_TOLERANCE:g} %")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU time [s]")
    ax.set_ylabel("exact PPTE [um] (1280 positions)")
    ax.legend(fontsize=7)
    ax.set_title(f"peers on the exact model ({peer['scene']['mesh']}, 1 load case)")


if __name__ == "__main__":
    main()
