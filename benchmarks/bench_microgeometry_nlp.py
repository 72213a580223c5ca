"""The crank-cam microgeometry NLP: Ipopt with exact derivatives against a brute-force grid and scipy SLSQP with
finite differences, plus a stability study (random starts, smoothing widths, relief blending, positions).

Problem (:func:`gearopt.design.microgeometry_nlp.optimise_microgeometry` with its defaults, one solve: ``refine=False``,
the fixed 40-position NLP every method here works on): default spur crank-cam
pair, 300 N m on the crank gear, 6 variables (linear tip relief amount and start roll angle of both gears, profile
crown of both gears), minimum PPTE subject to the LTCA contact stress <= the unmodified pair's maximum and loaded
contact ratio >= 1.2; 40 mesh positions, 1 slice, contact smoothing 0.05 um, relief starts blended over 0.1 deg.

Common yardstick: every method's design is scored by the same exact numeric LTCA the library reports
(``design.ppte_um``: 40 positions, relief blended over 0.1 deg), and is feasible when its exact maximum contact
stress is <= the limit (+1e-3 MPa) and its exact loaded contact ratio >= 1.2. "Reached" means feasible with PPTE
within 1 % of Ipopt's. The same designs are also re-scored on 5120 positions (the converged value, see
``bench_ltca.py``), because an optimiser can hide TE peaks between the 40 sampled positions.

Methods (all timed in this one run; ratios to Ipopt's build + solve):

- Ipopt: the library call from scratch (the scene's exact screen of starts, smooth model build, NLP build, solve,
  exact re-evaluation) and Ipopt's own solve time;
- grid over the two relief amounts with the starts and crowns at Ipopt's optimum (5..65 points per axis), and the
  full 6-D grid (3..5 points per axis), each point one exact LTCA (``gearopt.contact.ltca.ltca``);
- scipy SLSQP with 2-point finite differences (variables scaled to [0, 1] by their bounds, same start as Ipopt):
  (a) the same smooth NLP as Ipopt (epigraph TE bounds, stress^2 per loaded spring, smooth loaded contact ratio) on
  numeric evaluations of the smooth model; (b) the exact LTCA directly: objective max(TE) - min(TE), constraints
  exact max stress and exact loaded contact ratio (piecewise constant in the variables: FD sees no slope).
  Time to reach is read from the iterates (SLSQP callback timestamps).

Stability: 20 Latin-hypercube starts within the bounds (success rate, spread of the exact PPTE), contact smoothing
0.5 .. 0.005 um, relief blending 0 .. 0.5 deg, and NLP positions 40 .. 320 (iterations, time, exact PPTE, converged
PPTE, failures with their typed error name), and the library's own multi-start (``starts=8``).

Writes ``benchmarks/results/microgeometry_nlp.json`` and ``benchmarks/results/microgeometry_nlp.png``.
Run: ``python benchmarks/bench_microgeometry_nlp.py [--quick] [--out DIR]`` (about two minutes here).
"""

from __future__ import annotations

import json
import platform
import statistics
import time
from dataclasses import replace
from itertools import product
from pathlib import Path

import casadi as ca
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402
from scipy.optimize import minimize  # noqa: E402
from scipy.stats import qmc  # noqa: E402

from _timing import bench_args, median_time  # noqa: E402  (benchmarks/_timing.py)

import gearopt as go  # noqa: E402
from gearopt.contact.ltca import ltca  # noqa: E402
from gearopt.contact.ltca_smooth import LTCAModel  # noqa: E402
from gearopt.contact.microgeometry import Microgeometry  # noqa: E402
from gearopt.design.microgeometry_nlp import min_tip_relief_design, optimise_microgeometry  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
REPEATS = 7
TORQUE_NM = 300.0
POSITIONS = 40                 # optimise_microgeometry default
RELIEF_SMOOTHING_DEG = 0.1     # optimise_microgeometry default
CONVERGED_POSITIONS = 5120
CHECK_POSITIONS = 1280         # optimise_microgeometry's check_positions default: what design.ppte_um is scored on
GRID_AMOUNTS = (5, 9, 17, 33, 65)
GRID_6D = (3, 4, 5)
RANDOM_STARTS = 20
SMOOTHING_SWEEP_UM = (0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005)
RELIEF_SWEEP_DEG = (0.0, 0.02, 0.05, 0.1, 0.2, 0.5)
POSITIONS_SWEEP = (40, 80, 160, 320)
LIBRARY_STARTS = 8
QUICK = {"REPEATS": 1, "CONVERGED_POSITIONS": 320, "GRID_AMOUNTS": (5,), "GRID_6D": (), "RANDOM_STARTS": 2,
         "SMOOTHING_SWEEP_UM": (0.05,), "RELIEF_SWEEP_DEG": (0.1,), "POSITIONS_SWEEP": (40,), "LIBRARY_STARTS": 2}
MIN_LCR = 1.2
MAX_TIP_RELIEF_UM, MAX_CROWN_UM, START_MARGIN_DEG = 40.0, 10.0, 0.25   # optimise_microgeometry defaults
REACH = 0.01                   # "same PPTE": within 1 % of Ipopt's
STRESS_TOL_MPA = 1e-3
NAMES = ("tip_relief_1_um", "tip_relief_2_um", "tip_relief_1_start_roll_deg", "tip_relief_2_start_roll_deg",
         "profile_crown_1_um", "profile_crown_2_um")


def bounds(pair):
    """Variable bounds of optimise_microgeometry (amounts, starts between the working pitch point and 0.25 deg
    below the tip, crowns), in NAMES order."""
    g = pair.geometry()
    starts = [(float(g["pitch_point_roll_deg"][i]), float(g["eap_roll_deg"][i]) - START_MARGIN_DEG) for i in (0, 1)]
    return np.array([(0.0, MAX_TIP_RELIEF_UM)] * 2 + starts + [(0.0, MAX_CROWN_UM)] * 2)


def mods_of(x, relief_smoothing_deg=RELIEF_SMOOTHING_DEG) -> Microgeometry:
    x = [float(v) for v in x]
    return Microgeometry(tip_relief_um=(x[0], x[1]), tip_relief_start_roll_deg=(x[2], x[3]), relief_shape="linear",
                         profile_crown_um=(x[4], x[5]), relief_smoothing_deg=relief_smoothing_deg)


class Scorer:
    """Exact LTCA yardstick: PPTE, max stress, loaded contact ratio of a design vector (40 positions)."""

    def __init__(self, pair, limit_MPa):
        self.pair, self.limit = pair, limit_MPa
        self.calls = 0

    def __call__(self, x, positions=POSITIONS):
        self.calls += 1
        r = ltca(self.pair, TORQUE_NM, microgeometry=mods_of(x), positions=positions)
        return r.ppte_um, r.max_contact_stress_MPa, r.loaded_contact_ratio

    def feasible(self, stress, lcr):
        return stress <= self.limit + STRESS_TOL_MPA and lcr >= MIN_LCR

    def summary(self, x):
        ppte, stress, lcr = self(x)
        return {"ppte_um": ppte, "max_contact_stress_MPa": stress, "loaded_contact_ratio": lcr,
                "feasible": bool(self.feasible(stress, lcr)),
                "ppte_converged_um": self(x, CONVERGED_POSITIONS)[0],
                "design": dict(zip(NAMES, [float(v) for v in x]))}


def vector(values: dict) -> np.ndarray:
    return np.array([values[n] for n in NAMES], dtype=float)


# ---------------------------------------------------------------- Ipopt
def bench_ipopt(pair):
    design = optimise_microgeometry(pair, TORQUE_NM, refine=False)
    t0 = time.perf_counter()
    model = LTCAModel(pair, positions=POSITIONS)
    t_model = time.perf_counter() - t0
    return design, model, {"smooth_model_build_s": t_model, "iterations": design.solve.iterations,
                           "status": design.solve.status}


def head_to_head(pair, slsqp_fun, exact_fun):
    """Interleaved rounds (the machine is shared: a burst of load hits every method of a round alike): Ipopt from
    scratch, the SLSQP run on the same smooth NLP, one exact LTCA. Medians."""
    rows = {k: [] for k in ("build_and_solve_s", "solve_only_s", "nlp_build_s",
                            "slsqp_fd_smooth_nlp_s", "slsqp_fd_smooth_nlp_to_reach_s", "exact_ltca_s")}
    out = None
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        d = optimise_microgeometry(pair, TORQUE_NM, refine=False)
        rows["build_and_solve_s"].append(time.perf_counter() - t0)
        rows["solve_only_s"].append(d.solve.solve_time_s)
        rows["nlp_build_s"].append(d.solve.build_time_s)
        out = slsqp_fun()
        rows["slsqp_fd_smooth_nlp_s"].append(out[1])
        rows["slsqp_fd_smooth_nlp_to_reach_s"].append(out[5])
        rows["exact_ltca_s"].append(median_time(exact_fun, 9))
    med = {k: (statistics.median(v) if None not in v else None) for k, v in rows.items()}
    return med, out


# ---------------------------------------------------------------- grids
def grid_search(score, axes):
    """Best feasible exact PPTE over the tensor grid ``axes`` (list of 1-D arrays in NAMES order)."""
    best, best_x, n = np.inf, None, 0
    for x in product(*axes):
        n += 1
        ppte, stress, lcr = score(x)
        if score.feasible(stress, lcr) and ppte < best:
            best, best_x = ppte, np.array(x)
    return best, best_x, n


def bench_grids(score, lo_hi, x_opt, target):
    rows = []
    for n in GRID_AMOUNTS:
        axes = [np.linspace(*lo_hi[0], n), np.linspace(*lo_hi[1], n)] + [[v] for v in x_opt[2:]]
        t0 = time.perf_counter()
        best, bx, count = grid_search(score, axes)
        rows.append({"method": f"grid_amounts_{n}x{n}", "points": count, "time_s": time.perf_counter() - t0,
                     **score.summary(bx), "reached": bool(best <= (1 + REACH) * target)})
    for n in GRID_6D:
        axes = [np.linspace(lo, hi, n) for lo, hi in lo_hi]
        t0 = time.perf_counter()
        best, bx, count = grid_search(score, axes)
        rows.append({"method": f"grid_6d_{n}^6", "points": count, "time_s": time.perf_counter() - t0,
                     **score.summary(bx), "reached": bool(best <= (1 + REACH) * target)})
    return rows


# ---------------------------------------------------------------- SLSQP
class Traced:
    """Cache of design evaluations (FD perturbations of the epigraph variables reuse them) and iterate timestamps."""

    def __init__(self, fun):
        self.fun, self.cache, self.evaluations = fun, {}, 0
        self.t0, self.iterates = None, []

    def __call__(self, z):
        key = tuple(np.round(z, 15))
        if key not in self.cache:
            if len(self.cache) > 64:
                self.cache.clear()
            self.evaluations += 1
            self.cache[key] = self.fun(np.asarray(z, dtype=float))
        return self.cache[key]

    def callback(self, z, *args):
        self.iterates.append((time.perf_counter() - self.t0, np.array(z, dtype=float)))


def slsqp_smooth(pair, lo_hi, x0, limit):
    """(a) The same smooth NLP as Ipopt, with finite differences: variables u in [0, 1]^6 and t_hi, t_lo. Timed
    from scratch (smooth model build included, as in Ipopt's build + solve)."""
    t_start = time.perf_counter()
    model = LTCAModel(pair, positions=POSITIONS)
    on_path = model.layout.on_path.reshape(POSITIONS, -1).T.astype(bool)
    span = lo_hi[:, 1] - lo_hi[:, 0]

    def x_of(u):
        return lo_hi[:, 0] + span * np.clip(u, 0.0, 1.0)

    def evaluate(u):
        r = model.evaluate(mods_of(x_of(u)), TORQUE_NM)
        s2 = np.asarray(r.contact_stress_squared_MPa2)[on_path]
        return np.asarray(r.transmission_error_um, dtype=float).ravel(), s2, float(r.loaded_contact_ratio)

    traced = Traced(lambda u: evaluate(u))

    def cons(z):
        te, s2, lcr = traced(z[:6])
        return np.concatenate([z[6] - te, te - z[7], (limit ** 2 - s2) / (limit ** 2 / 100.0),
                               [(lcr - MIN_LCR) / 0.1]])

    te0, _, _ = evaluate((x0 - lo_hi[:, 0]) / span)
    z0 = np.concatenate([(x0 - lo_hi[:, 0]) / span, [te0.max(), te0.min()]])
    zb = [(0.0, 1.0)] * 6 + [(None, None)] * 2
    traced.t0 = t_start
    r = minimize(lambda z: (z[6] - z[7]) / 5.0, z0, method="SLSQP", bounds=zb,
                 constraints=[{"type": "ineq", "fun": cons}], callback=traced.callback,
                 options={"maxiter": 300, "ftol": 1e-10})
    total = time.perf_counter() - traced.t0
    return r, total, traced, [(t, x_of(z[:6])) for t, z in traced.iterates], x_of(r.x[:6])


def reach_time(score, iterates, target):
    """Time of the first feasible iterate whose exact PPTE is within REACH of ``target`` (None if none)."""
    for t, x in iterates:
        ppte, stress, lcr = score(x)
        if score.feasible(stress, lcr) and ppte <= (1 + REACH) * target:
            return t
    return None


def slsqp_exact(score, lo_hi, x0):
    """(b) SLSQP on the exact LTCA: PPTE = max - min of the sampled TE, exact stress and loaded contact ratio."""
    span = lo_hi[:, 1] - lo_hi[:, 0]

    def x_of(u):
        return lo_hi[:, 0] + span * np.clip(u, 0.0, 1.0)

    traced = Traced(lambda u: score(x_of(u)))
    cons = [{"type": "ineq", "fun": lambda u: (score.limit - traced(u)[1]) / (score.limit / 100.0)},
            {"type": "ineq", "fun": lambda u: (traced(u)[2] - MIN_LCR) / 0.1}]
    traced.t0 = time.perf_counter()
    r = minimize(lambda u: traced(u)[0], (x0 - lo_hi[:, 0]) / span, method="SLSQP", bounds=[(0.0, 1.0)] * 6,
                 constraints=cons, callback=traced.callback, options={"maxiter": 300, "ftol": 1e-10})
    total = time.perf_counter() - traced.t0
    return r, total, traced, [(t, x_of(u)) for t, u in traced.iterates], x_of(r.x)


def slsqp_row(name, score, out, target, median_total=None, median_reach=None):
    """One SLSQP run's row: its trace scored with the exact LTCA; with medians from the interleaved rounds when
    given (time_s, time_to_reach_s), else this run's own times."""
    r, total, traced, iterates, x_final = out[:5]
    total = median_total if median_total is not None else total
    reach_time, trace = None, []
    for t, x in iterates:
        ppte, stress, lcr = score(x)
        ok = score.feasible(stress, lcr)
        trace.append({"time_s": t, "ppte_um": ppte, "feasible": bool(ok)})
        if reach_time is None and ok and ppte <= (1 + REACH) * target:
            reach_time = t
    if median_total is not None:
        reach_time = median_reach
    return {"method": name, "time_s": total, "iterations": int(r.nit), "model_evaluations": traced.evaluations,
            "scipy_status": int(r.status), "scipy_message": str(r.message), "time_to_reach_s": reach_time,
            "reached": reach_time is not None, **score.summary(x_final), "trace": trace}


# ---------------------------------------------------------------- stability
def attempt(pair, **kw):
    t0 = time.perf_counter()
    try:
        d = optimise_microgeometry(pair, TORQUE_NM, refine=False, **kw)
    except go.GearoptError as exc:           # typed: SolveError subclasses, GearoptInputError
        res = getattr(exc, "result", None)
        return {"success": False, "error": type(exc).__name__, "status": getattr(exc, "status", ""),
                "message": str(exc).splitlines()[0][:200], "time_s": time.perf_counter() - t0,
                "iterations": getattr(res, "iterations", None),
                "violated": [f"{v.name}: {v.violation:.3g}" for v in getattr(exc, "violated", [])]}
    except RuntimeError as exc:              # an untyped failure (e.g. CasADi rootfinder) is a finding, not hidden
        return {"success": False, "error": type(exc).__name__ + " (untyped)", "message": str(exc)[:200],
                "time_s": time.perf_counter() - t0}
    dt = time.perf_counter() - t0
    sharp = replace(d.microgeometry, relief_smoothing_deg=0.0)
    return {"success": True, "time_s": dt, "iterations": d.solve.iterations, "status": d.solve.status,
            "ppte_um": d.ppte_um,
            "ppte_converged_um": ltca(pair, TORQUE_NM, microgeometry=d.microgeometry,
                                      positions=CONVERGED_POSITIONS).ppte_um,
            "ppte_sharp_relief_um": ltca(pair, TORQUE_NM, microgeometry=sharp,
                                         positions=d.exact["optimised"][TORQUE_NM].settings["positions"]).ppte_um,
            "design": {k: float(v) for k, v in d.values.items()}}


def bench_stability(pair, lo_hi, target, score):
    sampler = qmc.LatinHypercube(d=6, seed=20240611)
    starts = qmc.scale(sampler.random(RANDOM_STARTS), lo_hi[:, 0], lo_hi[:, 1])
    random_starts = []
    for x in starts:
        row = attempt(pair, initial=mods_of(x, 0.0))
        row["start"] = dict(zip(NAMES, [float(v) for v in x]))
        _, stress, lcr = score(x)
        row["start_loaded_contact_ratio"] = lcr
        row["start_feasible"] = bool(score.feasible(stress, lcr))
        random_starts.append(row)
    ok = [r["ppte_um"] for r in random_starts if r["success"]]
    conv = [r["ppte_converged_um"] for r in random_starts if r["success"]]
    summary = {"starts": len(random_starts), "successes": len(ok), "success_rate": len(ok) / len(random_starts),
               "failures": sorted({r["error"] for r in random_starts if not r["success"]}),
               "feasible_starts": sum(r["start_feasible"] for r in random_starts),
               "successes_from_feasible_starts": sum(r["success"] for r in random_starts if r["start_feasible"]),
               "successes_from_infeasible_starts": sum(r["success"] for r in random_starts
                                                       if not r["start_feasible"]),
               "ppte_um_min_median_max": [min(ok), statistics.median(ok), max(ok)] if ok else None,
               "ppte_um_std": statistics.pstdev(ok) if ok else None,
               "ppte_converged_um_min_median_max": [min(conv), statistics.median(conv), max(conv)] if conv else None,
               "within_1pct_of_default_start": sum(p <= (1 + REACH) * target for p in ok),
               "median_time_s": statistics.median(r["time_s"] for r in random_starts),
               "median_iterations": statistics.median(r["iterations"] for r in random_starts if r["success"])
               if ok else None}
    smoothing = [{"smoothing_um": w, **attempt(pair, smoothing_um=w)} for w in SMOOTHING_SWEEP_UM]
    relief = [{"relief_smoothing_deg": w, **attempt(pair, relief_smoothing_deg=w)} for w in RELIEF_SWEEP_DEG]
    positions = [{"positions": P, **attempt(pair, positions=P)} for P in POSITIONS_SWEEP]
    # the library's own multi-start (default start + Latin-hypercube points, best optimum returned)
    multistart = {"starts": LIBRARY_STARTS, **attempt(pair, starts=LIBRARY_STARTS)}
    return {"random_starts": {"summary": summary, "runs": random_starts}, "smoothing_um": smoothing,
            "relief_smoothing_deg": relief, "positions": positions, "library_multistart": multistart}


def plot(result, path):
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    target = result["ipopt"]["ppte_um"]
    ax = axes[0]
    ip = result["ipopt"]["timing"]
    for label, t, c in (("ipopt build+solve", ip["build_and_solve_s"], "tab:red"),
                        ("ipopt solve only", ip["solve_only_s"], "salmon")):
        ax.loglog(t, target, "*", ms=12, label=label, color=c)
    for i, r in enumerate(result["grid"]):
        ax.loglog(r["time_estimate_s"], r["ppte_um"], "s" if "6d" in r["method"] else "o", color="grey",
                    label="grid (points x median exact LTCA)" if i == 0 else None)
        ax.annotate(r["method"].replace("grid_", ""), (r["time_estimate_s"], r["ppte_um"]), fontsize=6,
                    textcoords="offset points", xytext=(3, 2))
    for r, c in zip(result["slsqp"], ("tab:green", "tab:purple")):
        tr = [p for p in r["trace"] if p["feasible"]]
        ax.loglog([p["time_s"] for p in tr], [p["ppte_um"] for p in tr], ".-", color=c, lw=0.8, ms=3,
                    label=r["method"] + " (feasible iterates)")
        ax.loglog(r["time_s"], r["ppte_um"], "D", color=c)
    ax.axhline((1 + REACH) * target, color="k", ls="--", lw=0.8)
    ax.set_ylim(0.8 * target, 3.0)
    ax.set_xlabel("run time [s]")
    ax.set_ylabel("exact PPTE at 40 positions [um] (dashed: 1.01 x Ipopt)")
    ax.set_title("crank-cam microgeometry NLP, 300 N m")
    ax.legend(fontsize=7)
    ax = axes[1]
    rs = result["stability"]["random_starts"]["runs"]
    ok = [r for r in rs if r["success"]]
    ax.plot(range(len(ok)), [r["ppte_um"] for r in ok], "o", label="exact PPTE, 40 positions")
    ax.plot(range(len(ok)), [r["ppte_converged_um"] for r in ok], "x", label="same design, 5120 positions")
    ax.axhline(target, color="k", ls="--", lw=0.8, label="default start (40 positions)")
    s = result["stability"]["random_starts"]["summary"]
    ax.set_title(f"20 Latin-hypercube starts: {s['successes']}/{s['starts']} solved")
    ax.set_xlabel("successful start #")
    ax.set_ylabel("PPTE [um]")
    ax.legend(fontsize=7)
    ax = axes[2]
    for key, label, mk in (("smoothing_um", "contact smoothing [um]", "o"),
                           ("relief_smoothing_deg", "relief blending [deg]", "s")):
        rows = [r for r in result["stability"][key] if r["success"]]
        xs = [max(r[key], 1e-3) for r in rows]
        ax.semilogx(xs, [r["ppte_um"] for r in rows], mk + "-", label=f"{label}: PPTE (40 pos.)")
        ax.semilogx(xs, [r["ppte_converged_um"] for r in rows], mk + "--", label=f"{label}: PPTE (5120 pos.)")
        for r in result["stability"][key]:
            if not r["success"]:
                ax.semilogx(max(r[key], 1e-3), 0.0, "rx", ms=10)
                ax.annotate(r["error"], (max(r[key], 1e-3), 0.0), fontsize=6, color="r")
    ax.set_xlabel("width (0 plotted at 1e-3)")
    ax.set_ylabel("exact PPTE of the optimum [um]")
    ax.set_title("smoothing widths (red x: failure)")
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None):
    args = bench_args(__doc__, argv, globals(), QUICK)
    t_start = time.perf_counter()
    pair = go.load_default_train("spur").pairs["crank-cam"]
    lo_hi = bounds(pair)
    design, model, timing = bench_ipopt(pair)
    limit = ltca(pair, TORQUE_NM, positions=POSITIONS).max_contact_stress_MPa   # the NLP's default limit
    score = Scorer(pair, limit)
    x_opt = vector(design.values)
    ipopt = {"timing": timing, **score.summary(x_opt)}
    target = ipopt["ppte_um"]
    # the library reports its design's PPTE from an exact LTCA on check_positions; the yardstick must agree there
    ipopt["ppte_library_check_positions_um"] = score(x_opt, CHECK_POSITIONS)[0]
    assert abs(ipopt["ppte_library_check_positions_um"] - design.ppte_um) < 1e-9 * max(1.0, design.ppte_um)
    m0 = min_tip_relief_design(pair, TORQUE_NM)
    x0 = np.clip(np.array([*m0.tip_relief_um, *m0.tip_relief_start_roll_deg, 0.0, 0.0]), lo_hi[:, 0], lo_hi[:, 1])

    def slsqp_a():
        out = slsqp_smooth(pair, lo_hi, x0, limit)
        return (*out, reach_time(score, out[3], target))

    med, out_a = head_to_head(pair, slsqp_a, lambda: score(x_opt))
    timing.update({k: med[k] for k in ("build_and_solve_s", "solve_only_s", "nlp_build_s",
                                       "exact_ltca_s")})
    print(f"ipopt: PPTE {target:.4f} um (converged {ipopt['ppte_converged_um']:.4f}), "
          f"{timing['build_and_solve_s'] * 1e3:.1f} ms build+solve, {timing['solve_only_s'] * 1e3:.1f} ms solve",
          flush=True)
    grid = bench_grids(score, lo_hi, x_opt, target)
    for r in grid:
        print(f"  {r['method']}: {r['time_s']:.2f} s, PPTE {r['ppte_um']:.4f}", flush=True)
    slsqp = [slsqp_row("slsqp_fd_smooth_nlp", score, out_a, target, med["slsqp_fd_smooth_nlp_s"],
                       med["slsqp_fd_smooth_nlp_to_reach_s"]),
             slsqp_row("slsqp_fd_exact_ltca", score, slsqp_exact(score, lo_hi, x0), target)]
    for r in slsqp:
        print(f"  {r['method']}: {r['time_s']:.2f} s, {r['iterations']} it, PPTE {r['ppte_um']:.4f}, "
              f"feasible {r['feasible']}, reach {r['time_to_reach_s']}", flush=True)
    base = timing["build_and_solve_s"]
    ratios = {"ipopt_solve_only": timing["solve_only_s"] / base}
    for r in grid:   # grids: points x the interleaved median of one exact LTCA (the timed run is also kept)
        r["time_estimate_s"] = r["points"] * timing["exact_ltca_s"]
        r["time_ratio_to_ipopt"] = r["time_estimate_s"] / base
        ratios[r["method"]] = r["time_ratio_to_ipopt"]
    for r in slsqp:
        r["time_ratio_to_ipopt"] = r["time_s"] / base
        ratios[r["method"]] = r["time_ratio_to_ipopt"]
        if r.get("time_to_reach_s") is not None:
            ratios[r["method"] + "_to_reach"] = r["time_to_reach_s"] / base
    stability = bench_stability(pair, lo_hi, target, score)
    print("  stability:", stability["random_starts"]["summary"], flush=True)
    result = {
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "python": platform.python_version()},
        "versions": {"casadi": ca.__version__, "numpy": np.__version__, "scipy": scipy.__version__,
                     "gearopt": go.__version__},
        "repeats": REPEATS, "statistic": ("medians of interleaved rounds for Ipopt, SLSQP on the smooth NLP and one exact LTCA; "
                      "grid cost = points x that LTCA median (each grid's single timed run kept as time_s); "
                      "SLSQP on the exact LTCA and the stability runs: single timed runs"),
        "problem": {"pair": "spur crank-cam", "torque_Nm": TORQUE_NM, "positions": POSITIONS, "slices": 1,
                    "relief_smoothing_deg": RELIEF_SMOOTHING_DEG, "max_contact_stress_MPa": limit,
                    "min_loaded_contact_ratio": MIN_LCR, "variables": NAMES,
                    "bounds": {n: [float(a), float(b)] for n, (a, b) in zip(NAMES, lo_hi)},
                    "reach_criterion": f"feasible and exact PPTE <= {1 + REACH:g} x Ipopt's"},
        "ipopt": ipopt, "grid": grid, "slsqp": slsqp, "time_ratios_to_ipopt_build_and_solve": ratios,
        "stability": stability, "run_time_s": None, "quick": args.quick,
    }
    result["run_time_s"] = time.perf_counter() - t_start
    (OUT / "microgeometry_nlp.json").write_text(json.dumps(result, indent=2, default=float) + "\n")
    plot(result, OUT / "microgeometry_nlp.png")
    for key in ("smoothing_um", "relief_smoothing_deg", "positions"):
        for r in stability[key]:
            print(" ", key, r[key], {k: (f"{v:.4g}" if isinstance(v, float) else v) for k, v in r.items()
                                     if k in ("success", "error", "iterations", "time_s", "ppte_um",
                                              "ppte_converged_um", "ppte_sharp_relief_um")})
    print("  library multistart:", {k: v for k, v in stability["library_multistart"].items() if k != "design"})
    print(json.dumps(ratios, indent=1))
    print(f"total {result['run_time_s']:.1f} s")
    return result


if __name__ == "__main__":
    main()
