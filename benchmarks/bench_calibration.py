"""Walk-off calibration benchmark: the CPU time of :func:`gearopt.studies.calibration.calibrate_walk_off` against
its error, and what the exact marginalisation of the interference shifts buys over plain importance sampling.

The problem: the packaged engine's field record (213 cam walk-offs and no crank walk-off in 247 853 engines,
``field_record(system).evidence``) calibrates the eleven estimated inputs of ``default_uncertain_inputs(("cam",
"crank"), record)`` and each joint's mounting, on the creep maps of one envelope of the helical timing model (cam
and crank with their shoulder-flipped copies, :func:`gearopt.dynamics.walk_off_envelope.joint_envelope`, ``levels=4,
cycles=2, run_in_cycles=1``, every speed band and damper state; ``--quick``: 3300 rpm, the degraded damper only,
``levels=3, cycles=1, run_in_cycles=0``, as ``failure_reproduction(quick=True)``). The envelope is computed once
per run and is not part of any timing.

The knobs: ``prior_samples`` P (scrambled-Sobol' samples of the inputs that are not marginalised),
``pivot_points`` G (grid of each joint's interference shift) and ``samples`` M (engines per probability of
:class:`~gearopt.studies.calibration.WalkOffModel`). A setting's CPU time (``time.process_time``, this process, one
thread) covers the ``WalkOffModel`` build and ``calibrate_walk_off``; the summaries read for the errors
(``predict``, ``mounting_summary``, ``input_summary``) are timed apart (``summary_cpu_s``).

Error measures against a reference computed in the same run (``REFERENCE``, its own seeds so that no sweep
setting shares its Sobol' points or common random numbers):

- ``cam_probability_rel_error``: relative error of the posterior predictive cam walk-off probability
  (``cal.predict("cam")["walk_off_probability"]``); beside it ``cam_probability_rel_error_to_converged``, the same
  probability against the reference's likelihood-weighted within-segment value in closed form
  (``cam_within_segment``, the pivot check below);
- ``crank_retained_abs_error``: absolute error of the crank's posterior probability of an axially retained gear
  (``cal.mounting_summary("crank")["posterior"]["retained"]``);
- ``median_error_max``: the largest error of the inputs' posterior medians (``cal.input_summary(u)["posterior"]
  ["median"]``), each relative to its prior width (of ``log(value)`` for a log-uniform input).

Sweep: every combination of ``PRIOR_SAMPLES`` x ``PIVOT_POINTS`` x ``ENGINES`` at seed 0; the default of
``failure_reproduction`` (``DEFAULT``: P=256, G=25, M=1000; quick: P=64, as ``failure_reproduction(quick=True)``)
is marked, and it and the largest setting run again at ``REPEAT_SEEDS`` (the seed-to-seed spread of the errors).

Baseline (in this file, measured in the same run): plain importance sampling that does not marginalise the shifts
and mountings -- the eleven inputs and both joints' mountings drawn together from the prior (one scrambled Sobol'
sequence; a mounting uniform over the joint's options), ``model.probability`` per sample and joint, weighted by the
Poisson likelihood of the field counts -- run at the CPU time of the default calibration (``BASELINE_BUDGETS`` x
it; the ``WalkOffModel`` build counted as for the calibration), M as the default. Reported: its samples, effective
sample size and errors against the same reference.

Pivot check: the posterior predictive cam probability against G at fixed P and M (``PIVOT_CHECK``): ``predict``
resolves the posterior at 64 points within each grid segment (it once averaged the probability at a segment's two
ends, +27 % at G=25: this benchmark found it); beside it the likelihood-weighted mean of the probability within
each segment in closed form (a log-linear probability and a Poisson likelihood, computed here from ``cal.detail``),
an independent check of ``predict`` and of how far the reference is from G -> infinity.

Writes ``benchmarks/results/calibration.json`` and ``benchmarks/results/calibration.png``.
Run: ``python benchmarks/bench_calibration.py`` (about 10 CPU-minutes; ``--quick``: seconds; ``--out DIR``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")     # process_time counts every thread of the process

import json
import math
import platform
import sys
import time
import warnings
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import scipy
from scipy import special, stats

import gearopt as go
from gearopt.cases.timing_train.model import default_timing_model
from gearopt.data import load_system
from gearopt.dynamics.walk_off_envelope import joint_envelope
from gearopt.studies.calibration import (FLIPPED_PREFIX, WalkOffModel, calibrate_walk_off, default_uncertain_inputs,
                                         field_record, joint_mountings)

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _timing import bench_args  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
JOINTS = ("cam", "crank")
ENVELOPE = {"levels": 4, "cycles": 2, "run_in_cycles": 1}          # + every speed band and damper state
REFERENCE = {"prior_samples": 512, "pivot_points": 33, "samples": 4000}
REFERENCE_SEED = 100
PRIOR_SAMPLES = (64, 256)
PIVOT_POINTS = (13, 25)
ENGINES = (500, 1000, 2000)
DEFAULT = {"prior_samples": 256, "pivot_points": 25, "samples": 1000}   # failure_reproduction's
SEED = 0
REPEAT_SEEDS = (1, 2)                 # the default and the largest setting again at these seeds
BASELINE_SEEDS = (0, 1, 2)
BASELINE_BUDGETS = (1.0, 4.0)         # x the default calibration's CPU time (the larger at the first seed only)
PIVOT_CHECK = {"prior_samples": 64, "samples": 1000, "pivot_points": (13, 25, 49, 97)}
QUICK = {"ENVELOPE": {"speeds_rpm": [3300.0], "damper_states": ("degraded",), "levels": 3, "cycles": 1,
                      "run_in_cycles": 0},
         "REFERENCE": {"prior_samples": 128, "pivot_points": 33, "samples": 1000},
         "PRIOR_SAMPLES": (16, 32), "PIVOT_POINTS": (9, 17), "ENGINES": (250,),
         "DEFAULT": {"prior_samples": 64, "pivot_points": 25, "samples": 1000},   # failure_reproduction(quick=True)
         "REPEAT_SEEDS": (), "BASELINE_SEEDS": (0,), "BASELINE_BUDGETS": (1.0,),
         "PIVOT_CHECK": {"prior_samples": 16, "samples": 250, "pivot_points": (9, 17, 33)}}
FLOOR = 1e-6                          # errors of exactly 0 are drawn here on the log axes


# -- the problem ----------------------------------------------------------------------------------------------------

def envelope(system) -> tuple[object, float]:
    """The helical train's envelope of cam and crank with their shoulder-flipped copies, and its CPU seconds."""
    c0 = time.process_time()
    model = default_timing_model("helical", system=system)
    env = joint_envelope(model, JOINTS, variants={FLIPPED_PREFIX + j: (j, -1.0) for j in JOINTS}, **ENVELOPE)
    return env, time.process_time() - c0


class Problem:
    def __init__(self, env, system):
        self.env, self.system = env, system
        self.record = field_record(system)
        self.evidence = [e for e in self.record.evidence if e.joint in JOINTS]
        self.inputs = default_uncertain_inputs(JOINTS, self.record)

    def model(self, samples: int, seed: int) -> WalkOffModel:
        return WalkOffModel(self.env, self.system, JOINTS, exposure_hours=self.record.exposure_hours,
                            samples=samples, seed=seed)


def width_error(u, value: float, reference: float) -> float:
    """|value - reference| relative to the prior width of ``u`` (of log(value) for a log-uniform input)."""
    if not (math.isfinite(value) and math.isfinite(reference)):
        return float("nan")
    if u.scale == "log":
        return abs(math.log(value / reference)) / math.log(u.high / u.low)
    return abs(value - reference) / (u.high - u.low)


def errors(m: dict, ref: dict, inputs) -> dict:
    per_input = {u.name: width_error(u, m["medians"][u.name], ref["medians"][u.name]) for u in inputs}
    worst = max(per_input, key=lambda k: per_input[k])
    shifts = [k for k in per_input if k.endswith(".interference_shift_um")]
    return {"cam_probability_rel_error": abs(m["cam_walk_off_probability"] / ref["cam_walk_off_probability"] - 1.0),
            "cam_probability_rel_error_to_converged": abs(m["cam_walk_off_probability"] / ref["cam_within_segment"]
                                                          - 1.0),
            "crank_retained_abs_error": abs(m["crank_retained_probability"] - ref["crank_retained_probability"]),
            "median_error_max": per_input[worst], "median_error_worst_input": worst,
            "median_error_max_shifts": max(per_input[k] for k in shifts),
            "median_error_max_sampled_inputs": max(v for k, v in per_input.items() if k not in shifts),
            "median_errors": per_input}


def run_calibration(problem: Problem, prior_samples: int, pivot_points: int, samples: int, seed: int) -> dict:
    """One calibration, timed (model build + calibrate_walk_off), and the quantities its errors are measured on."""
    c0, w0 = time.process_time(), time.perf_counter()
    model = problem.model(samples, seed)
    cal = calibrate_walk_off(model, problem.evidence, problem.inputs, prior_samples=prior_samples,
                             pivot_points=pivot_points, seed=seed)
    cpu, wall = time.process_time() - c0, time.perf_counter() - w0
    c1 = time.process_time()
    measured = {"cam_walk_off_probability": cal.predict("cam")["walk_off_probability"],
                "crank_retained_probability": cal.mounting_summary("crank")["posterior"].get("retained", 0.0),
                "medians": {u.name: cal.input_summary(u)["posterior"]["median"] for u in problem.inputs}}
    summary_cpu = time.process_time() - c1
    measured["cam_within_segment"] = within_segment_mean(cal, "cam")
    row = {"prior_samples": prior_samples, "pivot_points": pivot_points, "samples": samples, "seed": seed,
           "cpu_s": cpu, "wall_s": wall, "summary_cpu_s": summary_cpu,
           "effective_samples": cal.effective_samples,
           "cam_mounting_posterior": cal.mounting_summary("cam")["posterior"], **measured}
    print(f"  P={prior_samples:5d} G={pivot_points:3d} M={samples:5d} seed {seed}: {cpu:7.2f} CPU-s, "
          f"p_cam {measured['cam_walk_off_probability']:.4g}, crank retained "
          f"{measured['crank_retained_probability']:.6f}, ESS {cal.effective_samples:.1f}", flush=True)
    return row, cal


# -- the baseline: plain importance sampling ------------------------------------------------------------------------

def _poisson_log_likelihood(k: int, lam: float) -> float:
    lam = max(lam, 1e-300)
    return k * math.log(lam) - lam - math.lgamma(k + 1)


def _weighted_median(x, w) -> float:
    x, w = np.asarray(x, dtype=float), np.asarray(w, dtype=float)
    order = np.argsort(x)
    cw = np.cumsum(w[order])
    if len(x) == 0 or cw[-1] <= 0:
        return float("nan")
    return float(x[order][min(np.searchsorted(cw, 0.5 * cw[-1]), len(x) - 1)])


def plain_importance_sampling(problem: Problem, budget_cpu_s: float, samples: int, seed: int) -> dict:
    """Every input (the shifts too) and each joint's mounting drawn from the prior in one scrambled Sobol'
    sequence, ``model.probability`` per sample and joint, weighted by the Poisson likelihood of the counts; samples
    are evaluated until ``budget_cpu_s`` CPU seconds (model build included) are spent."""
    c0 = time.process_time()
    model = problem.model(samples, seed)
    options = {j: joint_mountings(problem.system, j, model) for j in JOINTS}
    inputs, counts = problem.inputs, {e.joint: e for e in problem.evidence}
    dim = len(inputs) + len(JOINTS)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        units = stats.qmc.Sobol(dim, scramble=True, seed=seed).random(2 ** 17)
    values, mounts, log_l, p_cam = [], [], [], []
    for row in units:
        if time.process_time() - c0 >= budget_cpu_s:
            break
        theta = {u.name: float(u.from_unit(row[k])) for k, u in enumerate(inputs)}
        mount = {j: options[j][min(int(row[len(inputs) + i] * len(options[j])), len(options[j]) - 1)]
                 for i, j in enumerate(JOINTS)}
        total, p = 0.0, {}
        for j in JOINTS:
            p[j] = 0.0 if mount[j] == "retained" else model.probability(j, theta, mount[j])[0]
            if j in counts:
                total += _poisson_log_likelihood(counts[j].failures, counts[j].fleet_size * p[j])
        values.append(theta)
        mounts.append(mount)
        log_l.append(total)
        p_cam.append(p["cam"])
    cpu = time.process_time() - c0
    log_l = np.array(log_l)
    w = np.exp(log_l - log_l.max())
    w /= w.sum()
    measured = {"cam_walk_off_probability": float(np.sum(w * np.array(p_cam))),
                "crank_retained_probability": float(sum(wi for wi, m in zip(w, mounts) if m["crank"] == "retained")),
                "medians": {u.name: _weighted_median([v[u.name] for v in values], w) for u in inputs}}
    ess = float(1.0 / np.sum(w ** 2))
    out = {"seed": seed, "samples": samples, "budget_cpu_s": budget_cpu_s, "cpu_s": cpu,
           "prior_samples_evaluated": len(values), "effective_samples": ess,
           "largest_weight": float(w.max()), **measured}
    print(f"  plain IS seed {seed}: {len(values)} samples in {cpu:.2f} CPU-s, ESS {ess:.2f}, "
          f"p_cam {measured['cam_walk_off_probability']:.4g}", flush=True)
    return out


# -- the pivot check ------------------------------------------------------------------------------------------------

def within_segment_mean(cal, joint: str) -> float:
    """Posterior predictive probability of ``joint`` with the likelihood-weighted mean of the probability in each
    grid segment (log-linear probability, Poisson likelihood: the ratio of regularised incomplete gamma differences
    of orders k + 1 and k), independent of ``predict``'s resolution within the segment. Diagnostic only."""
    e = next(e for e in cal.evidence if e.joint == joint)
    k, n = e.failures, e.fleet_size
    num = den = 0.0
    for m in cal.mountings[joint]:
        share = cal.weights * cal._mounting_share(joint, m)
        probs, masses = cal.detail[(joint, m)][3], cal.detail[(joint, m)][1]
        if probs is None or masses is None:
            return float("nan")
        lam = n * np.maximum(probs, 1e-300)
        la, lb = lam[:, :-1], lam[:, 1:]
        if k >= 1:
            i0 = np.abs(special.gammainc(k, lb) - special.gammainc(k, la)) / k
            i1 = np.abs(special.gammainc(k + 1, lb) - special.gammainc(k + 1, la))
            mean = np.where(i0 > 1e-300, i1 / np.where(i0 > 1e-300, i0, 1.0), 0.5 * (la + lb)) / n
        else:
            mean = 0.5 * (la + lb) / n
        norm = masses.sum(axis=1, keepdims=True)
        wseg = share[:, None] * np.where(norm > 0, masses / np.where(norm > 0, norm, 1.0), 0.0)
        num += float(np.sum(wseg * mean))
        den += float(np.sum(wseg))
    return num / den if den > 0 else 0.0


# -- the run --------------------------------------------------------------------------------------------------------

def key(row) -> tuple:
    return row["prior_samples"], row["pivot_points"], row["samples"]


def main(argv=None) -> dict:
    args = bench_args(__doc__, argv, globals(), QUICK)
    warnings.filterwarnings("ignore", category=UserWarning)
    load_start = list(os.getloadavg())
    system = load_system()
    print("envelope ...", flush=True)
    env, env_cpu = envelope(system)
    problem = Problem(env, system)
    default_key = (DEFAULT["prior_samples"], DEFAULT["pivot_points"], DEFAULT["samples"])

    print("reference ...", flush=True)
    ref_row, _ = run_calibration(problem, REFERENCE["prior_samples"], REFERENCE["pivot_points"],
                                 REFERENCE["samples"], REFERENCE_SEED)

    print("sweep ...", flush=True)
    grid = sorted({(p, g, m) for p in PRIOR_SAMPLES for g in PIVOT_POINTS for m in ENGINES} | {default_key})
    rows = [run_calibration(problem, p, g, m, SEED)[0] for p, g, m in grid]
    largest = max(grid, key=lambda s: (s[0] * s[1] * s[2], s))
    repeats = [run_calibration(problem, *s, seed)[0] for s in dict.fromkeys((default_key, largest))
               for seed in REPEAT_SEEDS]
    for r in rows + repeats:
        r.update(errors(r, ref_row, problem.inputs))
        r["default"] = key(r) == default_key
    default_row = next(r for r in rows if r["default"])
    for r in rows + repeats:
        r["cpu_ratio_to_default"] = r["cpu_s"] / default_row["cpu_s"]

    print("baseline: plain importance sampling ...", flush=True)
    baseline = []
    for factor in BASELINE_BUDGETS:
        for seed in (BASELINE_SEEDS if factor == BASELINE_BUDGETS[0] else BASELINE_SEEDS[:1]):
            b = plain_importance_sampling(problem, factor * default_row["cpu_s"], DEFAULT["samples"], seed)
            b.update(errors(b, ref_row, problem.inputs), budget_factor_of_default=factor)
            baseline.append(b)

    print("pivot check ...", flush=True)
    pivot_rows = []
    for g in PIVOT_CHECK["pivot_points"]:
        row, _ = run_calibration(problem, PIVOT_CHECK["prior_samples"], g, PIVOT_CHECK["samples"], SEED)
        pivot_rows.append({"pivot_points": g, "cpu_s": row["cpu_s"], "predict": row["cam_walk_off_probability"],
                           "within_segment_mean": row["cam_within_segment"]})
    finest = pivot_rows[-1]["within_segment_mean"]
    for r in pivot_rows:
        r["predict_rel_to_finest_within_segment"] = r["predict"] / finest - 1.0
        r["within_segment_rel_to_finest"] = r["within_segment_mean"] / finest - 1.0

    summary = summarise(rows, repeats, baseline, default_row, ref_row, pivot_rows, problem)
    cam = next(e for e in problem.evidence if e.joint == "cam")
    result = {
        "machine": {"python": sys.version.split()[0], "platform": platform.platform(),
                    "processor": platform.processor(), "cpus": os.cpu_count(),
                    "omp_num_threads": os.environ.get("OMP_NUM_THREADS"),
                    "load_average_1_5_15_min": {"start": load_start, "end": list(os.getloadavg())}},
        "versions": {"gearopt": getattr(go, "__version__", "?"), "numpy": np.__version__,
                     "scipy": scipy.__version__},
        "quick": bool(args.quick),
        "settings": {"envelope": {k: list(v) if isinstance(v, tuple) else v for k, v in ENVELOPE.items()},
                     "envelope_rows": int(len(env)), "envelope_cpu_s": env_cpu,
                     "reference": dict(REFERENCE, seed=REFERENCE_SEED), "default": dict(DEFAULT),
                     "prior_samples": list(PRIOR_SAMPLES), "pivot_points": list(PIVOT_POINTS),
                     "engines": list(ENGINES), "seed": SEED, "repeat_seeds": list(REPEAT_SEEDS),
                     "baseline_seeds": list(BASELINE_SEEDS), "baseline_budget_factors": list(BASELINE_BUDGETS),
                     "pivot_check": {k: list(v) if isinstance(v, tuple) else v for k, v in PIVOT_CHECK.items()},
                     "cpu_time": "time.process_time of this process: WalkOffModel build + calibrate_walk_off "
                                 "(the envelope excluded; the summaries apart as summary_cpu_s)",
                     "median_error": "|median - reference median| / prior width (of log(value) for a log input)"},
        "field": {"cam_failures": cam.failures, "fleet_size": cam.fleet_size,
                  "cam_field_rate": cam.failures / cam.fleet_size},
        "inputs": [{"name": u.name, "low": u.low, "high": u.high, "scale": u.scale} for u in problem.inputs],
        "reference": ref_row, "sweep": rows, "repeats": repeats, "baseline": baseline,
        "pivot_check": pivot_rows, "summary": summary}
    (Path(OUT) / "calibration.json").write_text(json.dumps(result, indent=1))
    figure(result, Path(OUT) / "calibration.png")
    print(json.dumps(summary, indent=1))
    return result


TOLERANCES = (0.10, 0.05)            # "within X": cam probability relative error and every median error <= X


def summarise(rows, repeats, baseline, default_row, ref_row, pivot_rows, problem) -> dict:
    measures = ("cam_probability_rel_error", "cam_probability_rel_error_to_converged", "crank_retained_abs_error",
                "median_error_max", "median_error_max_shifts", "median_error_max_sampled_inputs")

    def pick(r):
        return {k: r[k] for k in ("prior_samples", "pivot_points", "samples", "cpu_s", *measures,
                                  "median_error_worst_input")}

    within = {}
    for tol in TOLERANCES:
        ok = [r for r in rows if r["cam_probability_rel_error"] <= tol and r["median_error_max"] <= tol]
        within[f"{tol:g}"] = pick(min(ok, key=lambda r: r["cpu_s"])) if ok else None
    spread = {}
    for s in {key(r) for r in repeats}:
        same = [r for r in rows + repeats if key(r) == s]
        spread["P{}_G{}_M{}".format(*s)] = {m: [min(r[m] for r in same), max(r[m] for r in same)] for m in measures}
        spread["P{}_G{}_M{}".format(*s)]["seeds"] = sorted(r["seed"] for r in same)
    equal = [b for b in baseline if b["budget_factor_of_default"] == 1.0]
    return {
        "reference": {"cam_walk_off_probability": ref_row["cam_walk_off_probability"],
                      "cam_within_segment": ref_row["cam_within_segment"],
                      "crank_retained_probability": ref_row["crank_retained_probability"],
                      "medians": ref_row["medians"], "cpu_s": ref_row["cpu_s"],
                      "effective_samples": ref_row["effective_samples"]},
        "default": pick(default_row) | {"effective_samples": default_row["effective_samples"],
                                        "summary_cpu_s": default_row["summary_cpu_s"]},
        "cheapest_within": within,
        "seed_spread": spread,
        "baseline_equal_cpu": {
            "cpu_s": [b["cpu_s"] for b in equal], "prior_samples_evaluated": [b["prior_samples_evaluated"]
                                                                              for b in equal],
            "effective_samples": [b["effective_samples"] for b in equal],
            **{m: [b[m] for b in equal] for m in measures},
            "calibration_effective_samples": default_row["effective_samples"],
            "calibration_errors": {m: default_row[m] for m in measures}},
        "baseline_larger_budget": [{k: b[k] for k in ("budget_factor_of_default", "cpu_s", "prior_samples_evaluated",
                                                       "effective_samples", *measures)}
                                   for b in baseline if b["budget_factor_of_default"] != 1.0],
        "pivot_check": {"finest_within_segment": pivot_rows[-1]["within_segment_mean"],
                        "predict_rel_error_by_pivot_points": {str(r["pivot_points"]):
                                                              r["predict_rel_to_finest_within_segment"]
                                                              for r in pivot_rows},
                        "within_segment_rel_error_by_pivot_points": {str(r["pivot_points"]):
                                                                     r["within_segment_rel_to_finest"]
                                                                     for r in pivot_rows}}}


def figure(data: dict, path: Path) -> None:
    rows, base, ref = data["sweep"], data["baseline"], data["reference"]
    panels = (("cam_probability_rel_error", "cam predictive walk-off probability:\nrelative error"),
              ("cam_probability_rel_error_to_converged", "the same against the reference's\n"
               "within-segment value (G -> inf)"),
              ("crank_retained_abs_error", "crank P(retained):\nabsolute error"),
              ("median_error_max", "posterior medians: largest error\n/ prior width"),
              ("median_error_max_shifts", "medians of the two shifts (on the grid):\nlargest error / prior width"),
              ("median_error_max_sampled_inputs", "medians of the sampled inputs:\nlargest error / prior width"))
    fig, axes = plt.subplots(2, 4, figsize=(19, 8.6))
    ps = sorted({r["prior_samples"] for r in rows})
    colours = dict(zip(ps, plt.cm.viridis(np.linspace(0.0, 0.85, len(ps)))))
    markers = dict(zip(sorted({r["pivot_points"] for r in rows}), "os^Dv"))
    ms = sorted({r["samples"] for r in rows})
    sizes = dict(zip(ms, np.linspace(25, 90, len(ms))))
    for ax, (m, label) in zip([*axes[0, :3], *axes[1, :3]], panels):
        for r in rows:
            ax.scatter(r["cpu_s"], max(r[m], FLOOR), s=sizes[r["samples"]], c=[colours[r["prior_samples"]]],
                       marker=markers[r["pivot_points"]], edgecolors="k", linewidths=0.3, zorder=3)
        for r in data["repeats"]:
            ax.scatter(r["cpu_s"], max(r[m], FLOOR), s=14, c="0.5", marker="x", zorder=2)
        d = next(r for r in rows if r["default"])
        ax.scatter(d["cpu_s"], max(d[m], FLOOR), s=260, facecolors="none", edgecolors="r", linewidths=1.6,
                   zorder=4)
        for b in base:
            ax.scatter(b["cpu_s"], max(b[m], FLOOR), s=70, c="k", marker="X", zorder=4)
        ax.axvline(ref["cpu_s"], color="0.6", ls="--", lw=0.8)
        if max(r[m] for r in rows + data["repeats"] + base) < FLOOR:
            ax.text(0.5, 0.75, f"every run within {FLOOR:g} of the reference", transform=ax.transAxes,
                    ha="center", fontsize=8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CPU time per calibration [s]")
        ax.set_ylabel(label, fontsize=9)
        ax.grid(alpha=0.3, which="both")
    handles = [plt.Line2D([], [], ls="", marker="o", color=colours[p], label=f"P = {p}") for p in ps]
    handles += [plt.Line2D([], [], ls="", marker=mk, color="0.4", label=f"G = {g}") for g, mk in markers.items()]
    handles += [plt.Line2D([], [], ls="", marker="o", color="0.4", ms=3 + 2 * i, label=f"M = {m}")
                for i, m in enumerate(ms)]
    handles += [plt.Line2D([], [], ls="", marker="o", mfc="none", mec="r", ms=12, label="default"),
                plt.Line2D([], [], ls="", marker="x", color="0.5", label="other seeds"),
                plt.Line2D([], [], ls="", marker="X", color="k", label="plain IS (no marginalisation)"),
                plt.Line2D([], [], ls="--", color="0.6", label="reference's CPU time")]
    axes[1, 3].legend(handles=handles, fontsize=8, ncol=2, loc="center")
    axes[1, 3].set_axis_off()
    ax = axes[0, 3]
    pc = data["pivot_check"]
    g = [r["pivot_points"] for r in pc]
    ax.plot(g, [r["predict"] for r in pc], "o-", label="Calibration.predict (within-segment posterior)")
    ax.plot(g, [r["within_segment_mean"] for r in pc], "s-", label="likelihood-weighted within each segment")
    ax.axhline(ref["cam_walk_off_probability"], color="0.6", ls="--", lw=0.8, label="reference (predict)")
    ax.axhline(ref["cam_within_segment"], color="C1", ls="--", lw=0.8, label="reference (within segment)")
    ax.axhline(data["field"]["cam_field_rate"], color="r", ls=":", lw=0.8, label="field rate")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"pivot points G (P = {data['settings']['pivot_check']['prior_samples']}, "
                  f"M = {data['settings']['pivot_check']['samples']})")
    ax.set_ylabel("cam posterior predictive\nwalk-off probability", fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    s = data["settings"]["reference"]
    fig.suptitle(f"Walk-off calibration: CPU time against error (reference P = {s['prior_samples']}, "
                 f"G = {s['pivot_points']}, M = {s['samples']}; errors of 0 drawn at {FLOOR:g})", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
