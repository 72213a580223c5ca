"""Solver stability study: success rates of gearopt's NLPs over random and extreme scenes, typed-failure rates, and
the generic multi-start and elastic-mode tools on the shift split.

Families (defined once in ``tests/stability/stability_cases.py``; the tests run small samples of the same
families): around the default spur crank-cam pair,

- ``shift_split_random``: optimise_shift_split, centre distance uniform over its brute-force feasible range, face
  widths x U(0.9, 1.1), random initial split, both objectives;
- ``shift_split_extreme``: limits at the brute-force maximum -/+ U(0.0005, 0.02) (contact ratio, tip thickness
  ratio), centre distances just inside / 0.05 mm outside the feasible range (each case knows whether a feasible
  point exists);
- ``microgeometry_random``: optimise_microgeometry (20-30 positions, exact check on 160 positions), torque x
  U(0.5, 1.5) of 300 N m, face widths x U(0.9, 1.1), half of the cases from a random initial microgeometry;
- ``microgeometry_load``: torque log-uniform in [5, 900] N m;
- ``microgeometry_smoothing``: contact smoothing log-uniform in [0.005, 0.05] um.

Outcome of a case: ``solved`` (converged and the exact re-check meets the limits within the stated tolerances),
``check_failed``, ``typed_failure`` (SolveError/GearoptInputError naming a constraint or parameter),
``unnamed_failure`` or ``untyped_failure`` (must not happen). Times are single wall-clock runs of the whole call
(model build, NLP build, solve, exact check) per case, summarised by their median; the nominal case of each family
is also timed with ``_timing.median_time``.

Also: the generic Latin-hypercube multi-start (:func:`gearopt.nlp.multistart.multistart`) on the shift-split
Problem (50 starts), and elastic mode on just-infeasible contact-ratio limits against the brute-force gap.

Writes ``benchmarks/results/stability.json`` and ``benchmarks/results/stability.png``.
Run: ``python benchmarks/bench_stability.py [--quick] [--out DIR]`` (about a minute here).
"""

from __future__ import annotations

import json
import platform
import statistics
import sys
import time
import warnings
from collections import Counter
from pathlib import Path

import casadi as ca
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from _timing import bench_args, median_time  # benchmarks/_timing.py

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests" / "stability"))

import stability_cases as sc

import gearopt as go

OUT = Path(__file__).resolve().parent / "results"
N_PER_FAMILY = 50
ELASTIC_CASES = 10
NOMINAL_REPEATS = 5
QUICK = {"N_PER_FAMILY": 2, "ELASTIC_CASES": 2, "NOMINAL_REPEATS": 1}
SEED = 20240611
NOMINAL = {"shift_split_random": {"centre_distance_mm": None}, "shift_split_extreme": {"centre_distance_mm": None},
           "microgeometry_random": {}, "microgeometry_load": {}, "microgeometry_smoothing": {}}


def family_cases(name: str) -> list[dict]:
    if name == "shift_split_extreme":
        return sc.shift_split_extreme_cases(N_PER_FAMILY, SEED, delta=None)
    return sc.FAMILIES[name](N_PER_FAMILY, SEED)


def summarise(outcomes: list[sc.Outcome]) -> dict:
    n = len(outcomes)
    kinds = Counter(o.kind for o in outcomes)
    times = [o.time_s for o in outcomes]
    solved_times = [o.time_s for o in outcomes if o.kind == "solved"]
    iterations = [o.iterations for o in outcomes if o.iterations is not None]
    out = {
        "cases": n,
        "success_rate": kinds["solved"] / n,
        "typed_failure_rate": kinds["typed_failure"] / n,
        "check_failed": kinds["check_failed"], "unnamed_failures": kinds["unnamed_failure"],
        "untyped_failures": kinds["untyped_failure"],
        "median_time_s": statistics.median(times), "max_time_s": max(times),
        "median_time_solved_s": statistics.median(solved_times) if solved_times else None,
        "median_iterations": statistics.median(iterations) if iterations else None,
        "errors": dict(Counter(o.error for o in outcomes if o.error)),
        "statuses": dict(Counter(_status(o) for o in outcomes if o.kind != "solved")),
    }
    # each failure classified (issue 28): "infeasible data" where the case is built without a feasible point (the
    # extreme family's brute-force check), else "solver failure" (every other family's scenes are feasible: the
    # library's default start solves them)
    failed = [o for o in outcomes if o.kind != "solved"]
    out["failures_classified"] = dict(Counter("infeasible data" if o.case.get("expected") == "infeasible"
                                              else "solver failure" for o in failed))
    feasible = [o for o in outcomes if o.case.get("expected", "feasible") == "feasible"]
    out["success_rate_feasible"] = sum(o.kind == "solved" for o in feasible) / max(len(feasible), 1)
    expected = [o for o in outcomes if "expected" in o.case]
    if expected:
        feas = [o for o in expected if o.case["expected"] == "feasible"]
        infeas = [o for o in expected if o.case["expected"] == "infeasible"]
        out["success_rate_expected_feasible"] = sum(o.kind == "solved" for o in feas) / max(len(feas), 1)
        out["typed_failure_rate_expected_infeasible"] = (sum(o.kind == "typed_failure" for o in infeas)
                                                         / max(len(infeas), 1))
        out["solved_although_infeasible"] = sum(o.kind == "solved" for o in infeas)
    seeded = [o for o in outcomes if "initial_seed" in o.case]
    if seeded:
        default = [o for o in seeded if o.case["initial_seed"] is None]
        random_ = [o for o in seeded if o.case["initial_seed"] is not None]
        out["success_rate_default_start"] = sum(o.kind == "solved" for o in default) / max(len(default), 1)
        out["success_rate_random_start"] = sum(o.kind == "solved" for o in random_) / max(len(random_), 1)
    if outcomes and all("torque_Nm" in o.case for o in outcomes):
        out["failed_torques_Nm"] = sorted(o.case["torque_Nm"] for o in outcomes if o.kind != "solved")
        out["lowest_solved_torque_Nm"] = min((o.case["torque_Nm"] for o in outcomes if o.kind == "solved"),
                                             default=None)
    if outcomes and "ppte_um" in next((o.details for o in outcomes if o.kind == "solved"), {}):
        ratios = [o.details["stress_ratio"] for o in outcomes if o.kind == "solved"]
        lcr = [o.details["loaded_contact_ratio"] for o in outcomes if o.kind == "solved"]
        out["exact_check_stress_ratio_max"] = max(ratios)
        out["exact_check_loaded_contact_ratio_min"] = min(lcr)
    if outcomes and "worst_margin" in next((o.details for o in outcomes if o.kind == "solved"), {}):
        out["exact_check_worst_margin_min"] = min(o.details["worst_margin"] for o in outcomes if o.kind == "solved")
    return out


def _status(o: sc.Outcome) -> str:
    for line in o.message.splitlines():
        if line.startswith("Ipopt status:"):
            return line.split(":", 1)[1].strip()
    return o.error or o.kind


def row(o: sc.Outcome) -> dict:
    return {"case": {k: v for k, v in o.case.items()}, "kind": o.kind, "error": o.error, "status": _status(o)
            if o.kind != "solved" else "", "time_s": o.time_s, "iterations": o.iterations, "details": o.details,
            "message": o.message.splitlines()[0] if o.message else "",
            "worst_violated": [line.strip() for line in o.message.splitlines() if line.startswith("  - ")][:3]}


def bench_multistart() -> dict:
    """The generic multi-start on the shift-split Problem: 50 Latin-hypercube starts over x1 in [-1, 2] and the
    epigraph variable in [0, 6] mm."""
    p = sc.shift_split_problem(sc.default_pair())
    t0 = time.perf_counter()
    ms = p.multistart(N_PER_FAMILY, seed=SEED)
    wall = time.perf_counter() - t0
    x1 = np.array([r.values["profile_shift_1"] for r in ms.results if r is not None])
    return {"starts": ms.n_starts, "success_rate": ms.success_rate, "statuses": ms.status_counts(),
            "best_profile_shift_1": float(ms.best.values["profile_shift_1"]),
            "spread_profile_shift_1": float(np.ptp(x1)) if x1.size else None,
            "median_iterations": float(ms.table["iterations"].median()),
            "median_solve_time_s": float(ms.table["solve_time_s"].median()), "total_time_s": wall,
            "solver_builds": p.solver_builds}


def bench_elastic(n: int | None = None) -> dict:
    """Elastic mode on contact-ratio limits above the achievable maximum (gap U(0.001, 0.3)), against the gap from
    the brute-force scan (grid 1e-4 in x1)."""
    n = ELASTIC_CASES if n is None else n
    rng = np.random.default_rng(SEED)
    best = sc.split_limits(sc.default_pair())["max_contact_ratio"]
    rows = []
    for gap in rng.uniform(0.001, 0.3, n):
        p = sc.shift_split_problem(sc.default_pair(), min_contact_ratio=best + gap)
        t0 = time.perf_counter()
        res = p.solve_elastic()
        rows.append({"gap": float(gap), "relaxation": res.relaxation("contact_ratio_margin"),
                     "top": str(res.table.iloc[0]["name"]), "time_s": time.perf_counter() - t0,
                     "phase2_error": type(res.phase2_error).__name__ if res.phase2_error else ""})
    errors = [abs(r["relaxation"] - r["gap"]) for r in rows]
    return {"cases": n, "brute_force_max_contact_ratio": best, "max_abs_error": max(errors),
            "all_name_contact_ratio": all(r["top"] == "contact_ratio_margin" for r in rows),
            "median_time_s": statistics.median(r["time_s"] for r in rows), "runs": rows}


def plot(result: dict, path: Path) -> None:
    fams = list(result["families"])
    summ = [result["families"][f]["summary"] for f in fams]
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(13, 5.2), gridspec_kw={"width_ratios": [1.3, 1]})
    x = np.arange(len(fams))
    solved = np.array([s["success_rate"] for s in summ])
    typed = np.array([s["typed_failure_rate"] for s in summ])
    other = 1.0 - solved - typed
    ax.bar(x, solved, color="tab:green", label="solved + exact check")
    ax.bar(x, typed, bottom=solved, color="tab:orange", label="typed failure (names the limit)")
    ax.bar(x, other, bottom=solved + typed, color="tab:red", label="check failed / unnamed / untyped")
    for i, s in enumerate(summ):
        ax.text(i, 1.01, f"{s['success_rate']:.0%}\n{s['median_time_s'] * 1e3:.0f} ms", ha="center",
                va="bottom", fontsize=8)
    ms = result["multistart"]
    ax.bar(len(fams), ms["success_rate"], color="tab:green")
    ax.text(len(fams), 1.01, f"{ms['success_rate']:.0%}", ha="center", va="bottom", fontsize=8)
    ax.set_xticks(list(x) + [len(fams)])
    ax.set_xticklabels([f.replace("_", "\n", 1) for f in fams] + ["multistart\n(shift split)"], fontsize=8)
    ax.set_ylim(0, 1.22)
    ax.set_ylabel(f"fraction of cases ({N_PER_FAMILY} per family)")
    ax.set_title("Outcome per scene family (label: success rate, median time)")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=3)
    ext = result["families"].get("shift_split_extreme", {}).get("summary", {})
    if "success_rate_expected_feasible" in ext:
        i = fams.index("shift_split_extreme")
        ax.text(i, 0.5, f"feasible:\n{ext['success_rate_expected_feasible']:.0%} solved\ninfeasible:\n"
                f"{ext['typed_failure_rate_expected_infeasible']:.0%} typed", ha="center", va="center", fontsize=7)
    colours = {"solved": "tab:green", "typed_failure": "tab:orange", "check_failed": "tab:red",
               "unnamed_failure": "tab:red", "untyped_failure": "black"}
    for fam, key, marker, label in (("microgeometry_load", "torque_Nm", "o", "load family"),
                                    ("microgeometry_random", "torque_Nm", "s", "random family")):
        for r in result["families"][fam]["runs"]:
            ax2.scatter(r["case"][key], r["time_s"], c=colours[r["kind"]], marker=marker, s=22)
    ax2.set_xscale("log")
    ax2.set_xlabel("torque [N m] (o: load family, s: random family incl. random starts)")
    ax2.set_ylabel("wall time per case [s]")
    ax2.set_title("Microgeometry NLP: outcome (colour) against torque")
    ax2.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None) -> int:
    args = bench_args(__doc__, argv, globals(), QUICK)
    t_start = time.perf_counter()
    warnings.simplefilter("ignore")       # Ipopt-start warnings of random starts; outcomes are recorded per case
    families = {}
    for name in sc.FAMILIES:
        cases = family_cases(name)
        outcomes = [sc.run_case(name, c) for c in cases]
        summary = summarise(outcomes)
        summary["nominal_case_median_time_s"] = median_time(lambda name=name: sc.run_case(name, NOMINAL[name]),
                                                                 repeats=NOMINAL_REPEATS)
        families[name] = {"summary": summary, "runs": [row(o) for o in outcomes]}
        print(f"{name}: success {summary['success_rate']:.0%}, typed {summary['typed_failure_rate']:.0%}, "
              f"check_failed {summary['check_failed']}, unnamed {summary['unnamed_failures']}, "
              f"untyped {summary['untyped_failures']}, median {summary['median_time_s'] * 1e3:.0f} ms, "
              f"statuses {summary['statuses']}", flush=True)
        for o in outcomes:
            if o.kind not in ("solved", "typed_failure"):
                print("   ", o.describe(), flush=True)
    multi = bench_multistart()
    print("multistart:", {k: v for k, v in multi.items()}, flush=True)
    elastic = bench_elastic()
    print("elastic:", {k: v for k, v in elastic.items() if k != "runs"}, flush=True)
    lo, hi = sc.feasible_centre_distance_range()
    result = {
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "python": platform.python_version()},
        "versions": {"casadi": ca.__version__, "numpy": np.__version__, "gearopt": go.__version__},
        "statistic": "single wall-clock run per case (median over the family); nominal case: median of 5",
        "seed": SEED, "cases_per_family": N_PER_FAMILY,
        "tolerances": {"shift_split_margin": sc.MARGIN_TOL, "microgeometry_stress_relative": sc.STRESS_REL_TOL,
                       "microgeometry_loaded_contact_ratio": sc.LCR_TOL, "check_positions": sc.CHECK_POSITIONS},
        "references": {"feasible_centre_distance_range_mm": [lo, hi],
                       **sc.split_limits(sc.default_pair())},
        "families": families, "multistart": multi, "elastic": elastic, "run_time_s": None, "quick": args.quick,
    }
    result["untyped_failures_total"] = sum(f["summary"]["untyped_failures"] + f["summary"]["unnamed_failures"]
                                           for f in families.values())
    result["run_time_s"] = time.perf_counter() - t_start
    (OUT / "stability.json").write_text(json.dumps(result, indent=2, default=float) + "\n")
    plot(result, OUT / "stability.png")
    print(f"untyped/unnamed failures: {result['untyped_failures_total']}; total {result['run_time_s']:.1f} s")
    return 1 if result["untyped_failures_total"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
