"""The main job's crank-cam microgeometry problem over three torques with stress and temperature limits: Ipopt (the
library path, semi-infinite refinement and exact check) against scipy SLSQP with finite differences on the exact
LTCA and coarse-to-fine grids; time to a verified PPTE within 2 % of the best known (issue 16).

Problem (as ``problems/cam_gear_walkoff.py`` ``contact_stage`` -> ``gearopt.studies.contact_study.mesh_contact_study``
sets it up for the crank-cam mesh, with the variables of the brief of issue 16: ``groups=("tip_relief",)``, linear
tip relief amount and start roll angle of both gears, 4 variables): the default spur crank-cam pair, torques on the
crank gear = the mesh's ``design_torque_Nm`` x ``torque_range_fractions`` of the default data (design torque first:
300, 150, 450 N m), crank speed ``speed_rpm``; minimise the largest PPTE over the three torques subject to, at every
torque: LTCA contact stress <= the unmodified pair's exact maximum at the largest torque (the library default), root
stress of both gears <= ``max_root_stress_MPa``, contact (bulk + flash) temperature <= ``max_contact_temperature_C``
(bulk = ``oil_temperature_C``, friction ``mean_friction_coefficient``), loaded contact ratio >= ``min_loaded_contact_ratio``
(data ``[design_limits]``, ``[lubrication]``). Relief starts are blended over 0.1 deg (the library default) in every
method, so all methods search the same design space.

Yardstick ("verified"): the exact numeric LTCA (``gearopt.contact.ltca.ltca``) at 1280 positions (the library's
``check_positions``; benchmarks/results/ltca.json: PPTE within 1 % of the converged value for the plain spur pair),
at each torque: PPTE = the largest of the three, limits = the extreme over the three. A point is feasible when every
limit holds to ``FEASIBILITY_TOL`` (relative). "Best known" = the lowest feasible exact max-PPTE any method found in
this run (Ipopt's optimum, an SLSQP iterate or a grid point); a method "reaches" at the first of its points (in its
own order) that is feasible with max-PPTE <= 1.02 x best known.

Methods (all timed in this run, wall time from each method's start):

- Ipopt: ``optimise_microgeometry(..., refine=True)`` with the main job's options (40 NLP positions, 1280 check
  positions, 3 starts, up to 6 re-solves): wall time of the whole call (model build, starts, refinement, exact
  check; median of ``REPEATS`` calls), scored on the yardstick above (the library's own exact check, compared).
- SLSQP (scipy) with 2-point finite differences on the exact LTCA: variables scaled to [0, 1] by the library's
  bounds, objective max PPTE, the four limits as inequality constraints from the exact LTCA, from the library's
  default start (the thesis minimum tip relief at the design torque, ``min_tip_relief_design``); at most
  ``SLSQP_MAXITER`` iterations or ``SLSQP_BUDGET_S`` of wall time. Iterates (callback) timed; each scored.
- grid over the two relief amounts with the starts at Ipopt's optimum (it needs Ipopt's answer first; its time does
  not include Ipopt's), and a 4-D grid over amounts and starts. Both coarse to fine: levels of 2^k + 1 points per
  axis over the bounds (3, 5, 9, ...), each level evaluating only its new points, in lexicographic order (amount 1,
  amount 2, start 1, start 2) within a level; one exact LTCA per torque per point.

Writes ``benchmarks/results/microgeometry_three_torques.json`` and ``.png``.
Run: ``python benchmarks/bench_microgeometry_three_torques.py [--quick] [--out DIR]`` (about 2 minutes here).
"""

from __future__ import annotations

import json
import os
import platform
import statistics
import time
from itertools import product

import casadi as ca
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402
import scipy.stats  # noqa: E402,F401  (the library's exact screen imports it on first use: loaded before any timing,
from scipy.optimize import minimize  # noqa: E402  as the peers' optimisers are, so no method pays an import)

from _timing import bench_args  # noqa: E402  (benchmarks/_timing.py)

import gearopt as go  # noqa: E402
import gearopt.data  # noqa: E402
from gearopt.contact.ltca import ltca  # noqa: E402
from gearopt.contact.microgeometry import Microgeometry  # noqa: E402
from gearopt.design.microgeometry_nlp import min_tip_relief_design, optimise_microgeometry  # noqa: E402

from pathlib import Path  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
MESH = "crank-cam"
GROUPS = ("tip_relief",)
NAMES = ("tip_relief_1_um", "tip_relief_2_um", "tip_relief_1_start_roll_deg", "tip_relief_2_start_roll_deg")
REPEATS = 3
CHECK_POSITIONS = 1280          # optimise_microgeometry / mesh_contact_study default
NLP_POSITIONS = 40              # mesh_contact_study default
IPOPT_OPTIONS: dict = {}        # the main job's: library defaults (starts="load_cases", max_refinements=6)
RELIEF_SMOOTHING_DEG = 0.1      # optimise_microgeometry default
MAX_TIP_RELIEF_UM, START_MARGIN_DEG = 40.0, 0.25   # optimise_microgeometry defaults
GRID_2D_LEVELS = (3, 5, 9, 17, 33, 65)
GRID_4D_LEVELS = (3, 5, 9)
SLSQP_MAXITER = 200
SLSQP_BUDGET_S = 120.0
REACH = 0.02
FEASIBILITY_TOL = 1e-3          # relative, on every limit
QUICK = {"REPEATS": 1, "CHECK_POSITIONS": 80, "NLP_POSITIONS": 20,
         "IPOPT_OPTIONS": {"starts": 1, "max_refinements": 1}, "GRID_2D_LEVELS": (3, 5), "GRID_4D_LEVELS": (3,),
         "SLSQP_MAXITER": 5, "SLSQP_BUDGET_S": 10.0}


def problem_of_data():
    """The crank-cam pair, torques [N m] (design first), crank-gear speed [rpm] and limits from the default data."""
    v = gearopt.data.values(go.load_default_data())
    loads, lub, lim = v["design_loads"], v["lubrication"], v["design_limits"]
    train = go.load_default_train("spur")
    pair = train.pairs[MESH]
    design = go.load_system().design_torque_Nm(MESH)
    torques = [design * f for f in loads["torque_range_fractions"]]
    torques = [design] + [t for t in torques if t != design]        # as mesh_contact_study orders them
    speed = float(train.gear_speed_rpm(pair.names[0], loads["speed_rpm"]))
    return pair, tuple(torques), speed, {
        "bulk_temperature_C": float(lub["oil_temperature_C"]),
        "friction_coefficient": float(lub["mean_friction_coefficient"]),
        "max_root_stress_MPa": float(lim["max_root_stress_MPa"]),
        "max_flash_temperature_C": float(lim["max_contact_temperature_C"]),
        "min_loaded_contact_ratio": float(lim["min_loaded_contact_ratio"])}


def bounds(pair):
    """Bounds of optimise_microgeometry's tip-relief variables in NAMES order (amounts; starts between the working
    pitch point and 0.25 deg below the tip)."""
    g = pair.geometry()
    starts = [(float(g["pitch_point_roll_deg"][i]), float(g["eap_roll_deg"][i]) - START_MARGIN_DEG) for i in (0, 1)]
    return np.array([(0.0, MAX_TIP_RELIEF_UM)] * 2 + starts)


def mods_of(x) -> Microgeometry:
    x = [float(v) for v in x]
    return Microgeometry(tip_relief_um=(x[0], x[1]), tip_relief_start_roll_deg=(x[2], x[3]), relief_shape="linear",
                         relief_smoothing_deg=RELIEF_SMOOTHING_DEG)


class Scorer:
    """The yardstick: exact LTCA at every torque (CHECK_POSITIONS), max PPTE and the extreme of each limit; counts
    distinct evaluations (one per design point; each is one LTCA per torque)."""

    def __init__(self, pair, torques, speed_rpm, lub, limits):
        self.pair, self.torques, self.speed, self.lub, self.limits = pair, torques, speed_rpm, lub, limits
        self.cache, self.calls = {}, 0

    def fresh(self) -> "Scorer":
        """The same yardstick with an empty cache (each timed method pays for all its own evaluations)."""
        return Scorer(self.pair, self.torques, self.speed, self.lub, self.limits)

    def results(self, x):
        return [ltca(self.pair, t, microgeometry=mods_of(x), positions=CHECK_POSITIONS, speed_rpm=self.speed,
                     **self.lub) for t in self.torques]

    def __call__(self, x) -> dict:
        key = tuple(np.round(np.asarray(x, dtype=float), 12))
        if key not in self.cache:
            self.calls += 1
            rs = self.results(x)
            s = {"ppte_um": max(r.ppte_um for r in rs),
                 "ppte_by_torque_um": [r.ppte_um for r in rs],
                 "max_contact_stress_MPa": max(r.max_contact_stress_MPa for r in rs),
                 "max_root_stress_MPa": max(max(r.max_root_stress_MPa) for r in rs),
                 "max_contact_temperature_C": max(r.max_flash_temperature_C for r in rs),
                 "min_loaded_contact_ratio": min(r.loaded_contact_ratio for r in rs)}
            s["margins"] = self.margins(s)
            s["feasible"] = bool(min(s["margins"].values()) >= -FEASIBILITY_TOL)
            self.cache[key] = s
        return self.cache[key]

    def margins(self, s) -> dict:
        """Relative margin of each limit (>= 0: holds)."""
        L = self.limits
        return {"contact_stress": 1 - s["max_contact_stress_MPa"] / L["max_contact_stress_MPa"],
                "root_stress": 1 - s["max_root_stress_MPa"] / L["max_root_stress_MPa"],
                "contact_temperature": 1 - s["max_contact_temperature_C"] / L["max_contact_temperature_C"],
                "loaded_contact_ratio": s["min_loaded_contact_ratio"] / L["min_loaded_contact_ratio"] - 1}


def load():
    return [round(v, 2) for v in os.getloadavg()]


# ---------------------------------------------------------------- Ipopt
def bench_ipopt(pair, torques, speed, lub, lim):
    runs, design = [], None
    for _ in range(REPEATS):
        before = load()
        t0 = time.perf_counter()
        design = optimise_microgeometry(pair, list(torques), groups=GROUPS, positions=NLP_POSITIONS,
                                        check_positions=CHECK_POSITIONS, speed_rpm=speed,
                                        max_root_stress_MPa=lim["max_root_stress_MPa"],
                                        max_flash_temperature_C=lim["max_flash_temperature_C"],
                                        min_loaded_contact_ratio=lim["min_loaded_contact_ratio"],
                                        relief_smoothing_deg=RELIEF_SMOOTHING_DEG, **lub, **IPOPT_OPTIONS)
        runs.append({"time_s": time.perf_counter() - t0, "load_before": before, "load_after": load()})
    iterations = int(np.nansum(design.starts["iterations"]))
    if design.refinement is not None and len(design.refinement) > 1:
        iterations += int(design.refinement["ipopt_iterations"].iloc[1:].sum())   # row 0 is the best start's solve
    return design, {"time_s": statistics.median(r["time_s"] for r in runs), "runs": runs,
                    "starts": len(design.starts), "ipopt_iterations": iterations,
                    "refinements": 0 if design.refinement is None else len(design.refinement) - 1,
                    "status": design.solve.status}


# ---------------------------------------------------------------- SLSQP
class Budget(Exception):
    pass


def bench_slsqp(base, lo_hi, x0):
    """SLSQP with 2-point finite differences on the exact LTCA (variables scaled to [0, 1]); ``REPEATS`` runs (the
    path is deterministic), each with an empty evaluation cache; the row of the last run with its timed iterates
    (the start is iterate 0, time 0), iterate times and total time replaced by the medians over the runs."""
    runs = [_slsqp_once(base.fresh(), lo_hi, x0) for _ in range(REPEATS)]
    row = runs[-1]
    assert all(len(r["trace"]) == len(row["trace"]) for r in runs)
    row["runs_time_s"] = [r["time_s"] for r in runs]
    row["time_s"] = statistics.median(row["runs_time_s"])
    for i, p in enumerate(row["trace"]):
        p["time_s"] = statistics.median(r["trace"][i]["time_s"] for r in runs)
    return row


def _slsqp_once(score, lo_hi, x0):
    span = lo_hi[:, 1] - lo_hi[:, 0]
    lim = score.limits
    evaluations = {"n": 0}
    t0 = time.perf_counter()

    def x_of(u):
        return lo_hi[:, 0] + span * np.clip(u, 0.0, 1.0)

    def s(u):
        if time.perf_counter() - t0 > SLSQP_BUDGET_S:
            raise Budget
        key = tuple(np.round(np.asarray(x_of(u), dtype=float), 12))
        if key not in score.cache:
            evaluations["n"] += 1
        return score(x_of(u))

    cons = [{"type": "ineq", "fun": lambda u: 100.0 * (1 - s(u)["max_contact_stress_MPa"] / lim["max_contact_stress_MPa"])},
            {"type": "ineq", "fun": lambda u: 100.0 * (1 - s(u)["max_root_stress_MPa"] / lim["max_root_stress_MPa"])},
            {"type": "ineq", "fun": lambda u: 100.0 * (1 - s(u)["max_contact_temperature_C"]
                                                       / lim["max_contact_temperature_C"])},
            {"type": "ineq", "fun": lambda u: (s(u)["min_loaded_contact_ratio"] - lim["min_loaded_contact_ratio"]) / 0.1}]
    u0 = (x0 - lo_hi[:, 0]) / span
    iterates = [(0.0, x_of(u0))]
    last = {"u": u0}

    def callback(u, *args):
        iterates.append((time.perf_counter() - t0, x_of(u)))
        last["u"] = np.array(u, dtype=float)

    status, message, nit = None, "", None
    try:
        r = minimize(lambda u: s(u)["ppte_um"], u0, method="SLSQP", bounds=[(0.0, 1.0)] * 4, constraints=cons,
                     callback=callback, options={"maxiter": SLSQP_MAXITER, "ftol": 1e-8})
        status, message, nit, x_final = int(r.status), str(r.message), int(r.nit), x_of(r.x)
        if not np.allclose(iterates[-1][1], x_final):
            iterates.append((time.perf_counter() - t0, x_final))
    except Budget:
        status, message, nit, x_final = -1, f"wall budget {SLSQP_BUDGET_S:g} s reached", len(iterates) - 1, x_of(last["u"])
    total = time.perf_counter() - t0
    trace = [{"time_s": t, **point(score, x)} for t, x in iterates]
    return {"method": "slsqp_fd_exact_ltca", "time_s": total, "iterations": nit, "evaluations": evaluations["n"],
            "ltca_calls": evaluations["n"] * len(score.torques), "scipy_status": status, "scipy_message": message,
            "final": {**score(x_final), "design": dict(zip(NAMES, map(float, x_final)))}, "trace": trace}


def point(score, x):
    s = score(x)
    return {"ppte_um": s["ppte_um"], "feasible": s["feasible"]}


# ---------------------------------------------------------------- grids
def level_points(lo_hi, levels, free):
    """Coarse-to-fine grid points: for each level n (points per axis over the bounds) the points not in an earlier
    level, lexicographic within the level; axes not in ``free`` are fixed at ``lo_hi`` (a value)."""
    seen, out = set(), []
    for n in levels:
        axes = [np.linspace(lo_hi[i][0], lo_hi[i][1], n) if i in free else [lo_hi[i]] for i in range(len(lo_hi))]
        for x in product(*axes):
            key = tuple(np.round(np.asarray(x, dtype=float), 9))
            if key not in seen:
                seen.add(key)
                out.append((n, np.array(x, dtype=float)))
    return out


def bench_grid(base, name, points):
    score = base.fresh()
    t0, trace = time.perf_counter(), []
    for n, x in points:
        trace.append({"level": n, **point(score, x), "time_s": time.perf_counter() - t0})   # when it is known
    total = time.perf_counter() - t0
    feas = [i for i, p in enumerate(trace) if p["feasible"]]
    best = min(feas, key=lambda i: trace[i]["ppte_um"]) if feas else None
    return {"method": name, "time_s": total, "evaluations": len(points), "ltca_calls": len(points) * len(score.torques),
            "final": ({**score(points[best][1]), "time_s": trace[best]["time_s"], "design": dict(zip(NAMES, map(float, points[best][1])))} if best is not None
                      else {"ppte_um": None, "feasible": False, "margins": {}}), "trace": trace}


# ---------------------------------------------------------------- reach
def reach(row, best_known):
    """First point (in the method's order) feasible with PPTE <= (1 + REACH) x best known: its time, index."""
    for i, p in enumerate(row["trace"]):
        if p["feasible"] and p["ppte_um"] <= (1 + REACH) * best_known:
            return p["time_s"], i
    return None, None


def plot(result, path):
    fig, ax = plt.subplots(figsize=(8, 5))
    best = result["best_known_ppte_um"]
    colours = {"ipopt_library_refined": "tab:red", "slsqp_fd_exact_ltca": "tab:green",
               "grid_2d_amounts_at_ipopt_starts": "tab:grey", "grid_4d": "tab:blue"}
    for row in result["methods"]:
        name = row["method"]
        if name.startswith("ipopt"):
            err = row["final"]["ppte_um"] / best - 1
            ok = row["final"]["feasible"]
            bad = ", ".join(k.replace("_", " ") for k, v in row["final"]["margins"].items() if v < -FEASIBILITY_TOL)
            ax.plot(row["time_s"], max(abs(err), 1e-4), "*", ms=14, color=colours[name],
                    mfc=colours[name] if ok else "none",
                    label=f"Ipopt, library call (refine=True), median of {result['repeats']}"
                    + ("" if ok else f": NOT verified ({bad} violated), |error| {100 * abs(err):.2g} %"))
            continue
        ts, errs, run = [], [], np.inf                       # best feasible so far, against the method's time
        for p in row["trace"]:
            if p["feasible"] and p["ppte_um"] < run:
                run = p["ppte_um"]
                ts.append(max(p["time_s"], 1e-4))
                errs.append(max(run / best - 1, 1e-4))
        if ts:
            ts.append(max(row["time_s"], ts[-1]))
            errs.append(errs[-1])
            ax.step(ts, errs, where="post", color=colours[name], label=name.replace("_", " ") + " (best feasible so far)")
        ax.plot(row["time_s"], errs[-1] if ts else 1.0, "D", color=colours[name])
    ax.axhline(REACH, color="k", ls="--", lw=0.8, label=f"{100 * REACH:g} % of best known")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("run time [s]")
    ax.set_ylabel(f"verified max PPTE / best known - 1 (floored at 1e-4); best {best:.4g} um")
    ax.set_title(f"crank-cam tip relief, {', '.join(f'{t:g}' for t in result['problem']['torques_Nm'])} N m, "
                 "stress + temperature limits")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    args = bench_args(__doc__, argv, globals(), QUICK)
    t_start = time.perf_counter()
    load_start = load()
    pair, torques, speed, data = problem_of_data()
    lub = {k: data[k] for k in ("bulk_temperature_C", "friction_coefficient")}
    lim = {k: data[k] for k in ("max_root_stress_MPa", "max_flash_temperature_C", "min_loaded_contact_ratio")}
    lo_hi = bounds(pair)
    design, ip_timing = bench_ipopt(pair, torques, speed, lub, lim)
    # the library's default stress limit: the unmodified pair's exact maximum at the largest torque (check grid)
    limits = {"max_contact_stress_MPa": ltca(pair, max(torques), positions=CHECK_POSITIONS).max_contact_stress_MPa,
              "max_root_stress_MPa": lim["max_root_stress_MPa"],
              "max_contact_temperature_C": lim["max_flash_temperature_C"],
              "min_loaded_contact_ratio": lim["min_loaded_contact_ratio"]}
    score = Scorer(pair, torques, speed, lub, limits)
    x_ip = np.array([design.values[n] for n in NAMES])
    s_ip = score(x_ip)
    library = max(design.exact["optimised"][t].ppte_um for t in torques)
    assert abs(library - s_ip["ppte_um"]) <= 1e-9 * library, (library, s_ip["ppte_um"])   # same yardstick
    ipopt = {"method": "ipopt_library_refined", **ip_timing, "evaluations": None,
             "final": {**{k: v for k, v in s_ip.items()}, "design": dict(zip(NAMES, map(float, x_ip)))},
             "trace": [{"time_s": ip_timing["time_s"], "ppte_um": s_ip["ppte_um"], "feasible": s_ip["feasible"]}]}
    print(f"ipopt: {ip_timing['time_s']:.2f} s, max PPTE {s_ip['ppte_um']:.4f} um, feasible {s_ip['feasible']}, "
          f"margins { {k: round(v, 4) for k, v in s_ip['margins'].items()} }", flush=True)

    m0 = min_tip_relief_design(pair, torques[0])
    x0 = np.clip(np.array([*m0.tip_relief_um, *m0.tip_relief_start_roll_deg]), lo_hi[:, 0], lo_hi[:, 1])
    start = score(x0)
    slsqp = bench_slsqp(score, lo_hi, x0)
    print(f"slsqp: {slsqp['time_s']:.2f} s, {slsqp['iterations']} it, {slsqp['evaluations']} evaluations, "
          f"PPTE {slsqp['final']['ppte_um']:.4f}, feasible {slsqp['final']['feasible']}", flush=True)
    fixed = [tuple(lo_hi[0]), tuple(lo_hi[1]), x_ip[2], x_ip[3]]
    grid2 = bench_grid(score, "grid_2d_amounts_at_ipopt_starts", level_points(fixed, GRID_2D_LEVELS, {0, 1}))
    grid4 = bench_grid(score, "grid_4d", level_points([tuple(b) for b in lo_hi], GRID_4D_LEVELS, {0, 1, 2, 3}))
    methods = [ipopt, slsqp, grid2, grid4]
    for g in (grid2, grid4):
        print(f"{g['method']}: {g['time_s']:.2f} s, {g['evaluations']} points, best {g['final']['ppte_um']}", flush=True)

    best_known = min(p["ppte_um"] for m in methods for p in m["trace"] if p["feasible"])
    base = ip_timing["time_s"]
    for m in methods:
        t, i = reach(m, best_known)
        m["time_to_reach_s"], m["reach_index"] = t, i
        m["time_to_reach_ratio_to_ipopt"] = None if t is None else t / base
        m["final_ppte_error"] = (None if m["final"]["ppte_um"] is None else m["final"]["ppte_um"] / best_known - 1)
        print(f"  {m['method']}: reach {t} (point {i}), final error {m['final_ppte_error']}", flush=True)
    result = {
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "python": platform.python_version(), "cpu_count": os.cpu_count()},
        "versions": {"casadi": ca.__version__, "numpy": np.__version__, "scipy": scipy.__version__,
                     "gearopt": go.__version__},
        "load_average": {"start": load_start, "end": load()},
        "repeats": REPEATS,
        "statistic": (f"Ipopt and SLSQP: medians of {REPEATS} runs (SLSQP: per iterate; its path is deterministic); "
                      "grids: one timed run each; every timed run starts with an empty evaluation cache"),
        "problem": {"pair": f"spur {MESH}", "torques_Nm": list(torques), "crank_gear_speed_rpm": speed,
                    "groups": list(GROUPS), "variables": list(NAMES), "aggregate": "max",
                    "bounds": {n: [float(a), float(b)] for n, (a, b) in zip(NAMES, lo_hi)},
                    "limits": limits, **lub, "check_positions": CHECK_POSITIONS, "nlp_positions": NLP_POSITIONS,
                    "ipopt_options": IPOPT_OPTIONS, "relief_smoothing_deg": RELIEF_SMOOTHING_DEG,
                    "feasibility_tolerance_relative": FEASIBILITY_TOL,
                    "reach_criterion": f"feasible and exact max PPTE <= {1 + REACH:g} x best known",
                    "grid_order": ("coarse to fine: levels of " + ", ".join(map(str, GRID_4D_LEVELS)) +
                                   " points per axis (4-D) and " + ", ".join(map(str, GRID_2D_LEVELS)) +
                                   " (2-D), only new points per level, lexicographic within a level")},
        "start": {"design": dict(zip(NAMES, map(float, x0))), **{k: v for k, v in start.items()}},
        "best_known_ppte_um": best_known,
        "best_known_by": [m["method"] for m in methods
                          if any(p["feasible"] and p["ppte_um"] == best_known for p in m["trace"])],
        "methods": methods, "quick": args.quick, "run_time_s": time.perf_counter() - t_start,
    }
    (OUT / "microgeometry_three_torques.json").write_text(json.dumps(result, indent=2, default=float) + "\n")
    plot(result, OUT / "microgeometry_three_torques.png")
    print(f"best known {best_known:.4f} um by {result['best_known_by']}; total {result['run_time_s']:.1f} s, "
          f"load {result['load_average']}")
    return result


if __name__ == "__main__":
    main()
