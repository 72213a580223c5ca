"""Run time against error for the geometry layer.

1. Inverse involute: the symbolic form (unrolled Newton, 1..6 steps) evaluated through a mapped CasADi Function, the
   numeric vectorised Newton, and scipy's brentq per point (baseline) -- error against the exact angle.
2. Profile-shift split of the default crank-cam pair (maximise the smaller tip thickness, worst-case contact ratio
   >= 1.2): Ipopt with exact derivatives, a brute-force grid over x1 (several resolutions), and scipy SLSQP with
   finite differences -- objective error against a tight Ipopt reference.

Writes ``benchmarks/results/geometry.json`` (machine, versions, medians of repeats, ratios measured in this run) and
``benchmarks/results/geometry.png``. Run: ``python benchmarks/bench_geometry.py [--quick] [--out DIR]``.
"""

from __future__ import annotations

import json
import math
import platform
import time
from dataclasses import replace
from pathlib import Path

import casadi as ca
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402
from scipy.optimize import brentq, minimize  # noqa: E402

from _timing import bench_args, median_time  # noqa: E402  (benchmarks/_timing.py)

import gearopt as go  # noqa: E402
from gearopt import numerics as nm  # noqa: E402
from gearopt.design.shift_distribution import optimise_shift_split  # noqa: E402
from gearopt.errors import GeometryError  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
REPEATS = 7
INV_POINTS = 100_000
NEWTON_STEPS = tuple(range(1, 7))
GRID_SIZES = (11, 41, 161, 641)
QUICK = {"INV_POINTS": 2_000, "NEWTON_STEPS": (1, 2, 3), "GRID_SIZES": (11, 41)}


def bench_inverse_involute(n=None):
    n = INV_POINTS if n is None else n
    alpha = np.linspace(1e-3, math.radians(75.0), n)
    y = nm.involute(alpha)
    rows = []
    for steps in NEWTON_STEPS:
        nm._SYMBOLIC_NEWTON_STEPS, saved = steps, nm._SYMBOLIC_NEWTON_STEPS
        v = ca.SX.sym("v")
        f = ca.Function("inv_inv", [v], [nm.inverse_involute(v)]).map(n)
        nm._SYMBOLIC_NEWTON_STEPS = saved
        out = np.array(f(y[None, :])).ravel()
        rows.append({"method": f"casadi_newton_{steps}", "time_s": median_time(lambda: f(y[None, :])),
                     "max_error_rad": float(np.max(np.abs(out - alpha)))})
    out = nm.inverse_involute(y)
    rows.append({"method": "numpy_newton", "time_s": median_time(lambda: nm.inverse_involute(y)),
                 "max_error_rad": float(np.max(np.abs(out - alpha)))})
    sub = slice(0, n, 100)  # brentq per point is slow: time 1/100 of the points and scale
    ys = y[sub]

    def brent():
        return np.array([brentq(lambda a, t=t: math.tan(a) - a - t, 1e-12, math.radians(80.0), xtol=1e-15)
                         for t in ys])

    out_b = brent()
    rows.append({"method": "scipy_brentq_per_point", "time_s": median_time(brent, 3) * 100,
                 "max_error_rad": float(np.max(np.abs(out_b - alpha[sub])))})
    return {"points": n, "rows": rows}


def _min_tip_thickness(pair, x1):
    trial = replace(pair, profile_shifts=(x1, sum(pair.profile_shifts) - x1), tip_diameters_mm=None)
    try:
        trial.check(min_contact_ratio=1.2, min_backlash_mm=None)
    except GeometryError:
        return None
    return min(trial.geometry()["tip_thickness_mm"])


def bench_shift_split():
    pair = go.load_default_train("spur").pairs["crank-cam"]
    reference = optimise_shift_split(pair, min_contact_ratio=1.2)["objective_value"]
    rows = []
    t_ipopt = median_time(lambda: optimise_shift_split(pair, min_contact_ratio=1.2))
    res = optimise_shift_split(pair, min_contact_ratio=1.2)
    rows.append({"method": "ipopt_exact_derivatives", "time_s": t_ipopt,
                 "objective_error_mm": abs(res["objective_value"] - reference)})
    # the same solve without building the NLP (Ipopt's own wall time): what a re-solve with new data costs
    rows.append({"method": "ipopt_solve_only", "time_s": res["solve_time_s"],
                 "objective_error_mm": abs(res["objective_value"] - reference)})
    for n in GRID_SIZES:
        grid = np.linspace(-0.8, 1.6, n)

        def scan():
            vals = [_min_tip_thickness(pair, x) for x in grid]
            return max(v for v in vals if v is not None)

        best = scan()
        rows.append({"method": f"grid_{n}", "time_s": median_time(scan, 3), "objective_error_mm": abs(best - reference)})
    sum_x = float(sum(pair.profile_shifts))

    def slsqp():
        def thickness(x):
            p = replace(pair, profile_shifts=(x[0], sum_x - x[0]), tip_diameters_mm=None)
            return np.array(p.geometry()["tip_thickness_mm"])

        def margins(x):
            p = replace(pair, profile_shifts=(x[0], sum_x - x[0]), tip_diameters_mm=None)
            c = p.constraints(min_contact_ratio=1.2, min_backlash_mm=None)
            return np.array([float(v) for v in c.values()] + list(thickness(x) - x[1]))

        r = minimize(lambda x: -x[1], x0=[float(pair.profile_shifts[0]), 1.0], method="SLSQP",
                     constraints=[{"type": "ineq", "fun": margins}], options={"ftol": 1e-10, "maxiter": 200})
        return -r.fun

    best = slsqp()
    rows.append({"method": "scipy_slsqp_finite_differences", "time_s": median_time(slsqp, 3),
                 "objective_error_mm": abs(best - reference)})
    base = rows[0]["time_s"]
    for r in rows:
        r["time_ratio_to_ipopt"] = r["time_s"] / base
    return {"reference_min_tip_thickness_mm": reference, "rows": rows}


def main(argv=None):
    args = bench_args(__doc__, argv, globals(), QUICK)
    inv = bench_inverse_involute()
    split = bench_shift_split()
    result = {
        "machine": {"platform": platform.platform(), "processor": platform.processor(), "python":
                    platform.python_version()},
        "versions": {"casadi": ca.__version__, "numpy": np.__version__, "scipy": scipy.__version__,
                     "gearopt": go.__version__},
        "repeats": REPEATS, "statistic": "median wall time", "quick": args.quick,
        "inverse_involute": inv, "shift_split": split,
    }
    (OUT / "geometry.json").write_text(json.dumps(result, indent=2) + "\n")
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, block, err_key, title in ((axes[0], inv, "max_error_rad", f"inverse involute, {inv['points']} points"),
                                      (axes[1], split, "objective_error_mm", "crank-cam shift split")):
        for r in block["rows"]:
            ax.loglog(r["time_s"], max(r[err_key], 1e-17), "o")
            ax.annotate(r["method"], (r["time_s"], max(r[err_key], 1e-17)), fontsize=7,
                        textcoords="offset points", xytext=(4, 2))
        ax.set_xlabel("run time [s] (median)")
        ax.set_ylabel(err_key.replace("_", " "))
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(OUT / "geometry.png", dpi=120)
    for block in (inv, split):
        for r in block["rows"]:
            print({k: (f"{v:.3g}" if isinstance(v, float) else v) for k, v in r.items()})
    return result


if __name__ == "__main__":
    main()
