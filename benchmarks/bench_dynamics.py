"""Run time against error for the torsional dynamics of the default timing train (issue 5).

1. Work-precision at rated speed (2500 rpm), default spur model, with backlash and without: CVODES at several
   tolerances (interpreted and JIT-compiled right-hand side), IDAS, the fixed-step ``rk`` and ``collocation``
   integrators and scipy's ``solve_ivp`` (LSODA, BDF, Radau, with the CasADi Jacobian) on the same right-hand side,
   over one engine cycle from the same static initial state; error of the crank-cam mesh force against a tight
   CVODES reference (rtol 1e-10). The lash model rattles chaotically at rated speed: trajectories of different
   tolerances part after roughly 100 deg of crank angle (measured here), so its pointwise error is taken over the
   first 60 deg; the linear model's over the whole cycle. Run times are integration only (same for all methods),
   medians of repeats. Ratios "scipy time / CVODES time at equal error" interpolate CVODES' log-log curve.
2. The acceptance run: ``default_timing_model("spur").simulate(2500, cycles=10, backlash=True, rtol=1e-6)``, total
   wall time (static state, integration, outputs), interpreted and JIT; and the 10-cycle statistics (peak, RMS of the
   crank-cam force) at several tolerances against the reference (they converge statistically, not pointwise).
3. Model approximations against better references: excitation along the nominal motion vs at the vibrating
   angles; contact width and stiffness harmonics.
4. Speed sweep 750..3000 rpm, lash and no lash (peak/RMS mesh forces, cam-gear joint torque, impacts), the linear
   modes and forced response, and sensitivities of the crank-cam force (CVODES forward sensitivities vs finite
   differences).

The speed study of the 10-cycle lash run (work against statistical precision, JIT gain, compiler flags) is
``bench_dynamics_speed.py``.

Writes ``benchmarks/results/dynamics.json`` and ``benchmarks/results/dynamics.png``.
Run: ``python benchmarks/bench_dynamics.py [--quick] [--out DIR]`` (about 35 minutes on the 2-core test machine;
``--quick``: the no-lash work-precision of two CVODES tolerances against scipy LSODA only, seconds).
"""

from __future__ import annotations

import json
import math
import os
import platform
import statistics
import time
from pathlib import Path

import casadi as ca
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

from _timing import bench_args  # noqa: E402  (benchmarks/_timing.py)

import gearopt  # noqa: E402
from gearopt import compile_cache  # noqa: E402
from gearopt.cases.timing_train import default_timing_model  # noqa: E402
from gearopt.dynamics import campbell_diagram, forced_response  # noqa: E402
from gearopt.dynamics.modes import damped_modes  # noqa: E402
from gearopt.dynamics.sensitivity import response_sensitivities  # noqa: E402
from gearopt.dynamics.sweep import speed_sweep  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
SPEED = 2500.0
MESH = "crank-cam"
EARLY_DEG = 60.0
REPEATS = 3
REFERENCE_RTOL = 1e-10
QUICK = {"REPEATS": 1, "REFERENCE_RTOL": 1e-8}


def median_time(fun, repeats=REPEATS):
    times, result = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        result = fun()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), result


class Case:
    """One model + lash option at rated speed: reference, output evaluation, error metrics."""

    def __init__(self, model, lash):
        self.model, self.lash = model, lash
        self.params = model.parameters_at(SPEED)
        self.ref_sim = model.simulator(backlash=lash, rtol=REFERENCE_RTOL, atol=0.1 * REFERENCE_RTOL, jit=True)
        self.pvec = self.ref_sim.parameter_vector(SPEED, self.params)
        self.x0 = self.ref_sim.static_state(SPEED, self.params)
        self.grid = self.ref_sim.grid_rad
        self.idx = self.ref_sim.output_names.index(("mesh_force_N", MESH))
        self.ref = self.force(self.ref_sim, np.array(self.ref_sim.integrator(x0=self.x0, p=self.pvec)["xf"]))
        self.peak = float(np.max(np.abs(self.ref)))
        self.early = np.degrees(self.grid) <= EARLY_DEG

    def force(self, sim, xs):
        outs = np.array(sim.output_function(self.grid[None, :], xs, np.repeat(self.pvec[:, None], sim.n_out, 1)))
        return outs[self.idx]

    def errors(self, f):
        e = np.abs(f - self.ref) / self.peak
        return {"error_first_60deg": float(np.max(e[self.early])), "error_cycle": float(np.max(e))}


def casadi_runs(case, configs):
    rows = []
    for label, method, kwargs in configs:
        sim = case.model.simulator(backlash=case.lash, method=method, **kwargs)
        t, res = median_time(lambda: sim.integrator(x0=case.x0, p=case.pvec))
        f = case.force(sim, np.array(res["xf"]))
        stats = sim.integrator.stats()
        rows.append({"method": label, "integrator": method, "time_s": t, "build_time_s": sim.build_time_s,
                     "steps": int(stats.get("nsteps", 0)), **case.errors(f),
                     **{k: v for k, v in kwargs.items() if k in ("rtol", "fixed_step_deg", "jit")}})
        print(f"  {label:28s} {t:7.3f} s  err60 {rows[-1]['error_first_60deg']:.2e}  "
              f"err {rows[-1]['error_cycle']:.2e}", flush=True)
    return rows


def scipy_runs(case, tolerances, methods=("LSODA", "BDF", "Radau")):
    eq = case.ref_sim.eq
    graph = ca.Function("rhs_def", [eq.tau, eq.x, eq.p], [eq.rhs]).serialize()
    f = compile_cache.compiled("scipy_rhs", graph, lambda extra: ca.Function(
        "rhs", [eq.tau, eq.x, eq.p], [eq.rhs], dict({"cse": True}, **extra)))[0]
    jf = compile_cache.compiled("scipy_rhs_jac", graph, lambda extra: ca.Function(
        "rhs_jac", [eq.tau, eq.x, eq.p], [ca.jacobian(eq.rhs, eq.x)], dict({"cse": True}, **extra)))[0]
    p = case.pvec

    def fun(t, x):
        return np.array(f(t, x, p)).ravel()

    def jac(t, x):
        return np.array(jf(t, x, p))

    rows = []
    t_end = case.grid[-1]
    for method in methods:
        for rtol in tolerances:
            def solve():
                return solve_ivp(fun, (0.0, t_end), case.x0, method=method, rtol=rtol, atol=0.1 * rtol,
                                 t_eval=case.grid, jac=jac)
            t, sol = median_time(solve, repeats=1 if method == "Radau" else 2)
            if sol.status != 0:
                rows.append({"method": f"scipy {method} rtol {rtol:g}", "integrator": f"scipy_{method}",
                             "rtol": rtol, "time_s": t, "failed": sol.message})
                continue
            force = case.force(case.ref_sim, sol.y)
            rows.append({"method": f"scipy {method} rtol {rtol:g}", "integrator": f"scipy_{method}", "rtol": rtol,
                         "time_s": t, "nfev": int(sol.nfev), **case.errors(force)})
            print(f"  {rows[-1]['method']:28s} {t:7.3f} s  err60 {rows[-1]['error_first_60deg']:.2e}  "
                  f"err {rows[-1]['error_cycle']:.2e}", flush=True)
    return rows


def ratios_at_equal_error(rows, metric):
    """scipy time / CVODES (JIT) time at the scipy run's error, by log-log interpolation of CVODES' curve."""
    cv = sorted([(r[metric], r["time_s"]) for r in rows if r["integrator"] == "cvodes" and r.get("jit")
                 and metric in r], key=lambda v: v[0])
    if len(cv) < 2:
        return []
    le, lt = np.log10([c[0] for c in cv]), np.log10([c[1] for c in cv])
    out = []
    for r in rows:
        if not r["integrator"].startswith("scipy") or metric not in r:
            continue
        e = math.log10(max(r[metric], 1e-300))
        t_cv = 10 ** float(np.interp(e, le, lt))         # clamps outside CVODES' range (conservative)
        out.append({"method": r["method"], "error": r[metric], "scipy_time_s": r["time_s"],
                    "cvodes_time_at_equal_error_s": t_cv, "ratio": r["time_s"] / t_cv,
                    "inside_cvodes_range": bool(le[0] <= e <= le[-1])})
    return out


def configs():
    cv = [(f"cvodes rtol {r:g}", "cvodes", {"rtol": r, "jit": False}) for r in (1e-4, 1e-6, 1e-8)]
    cv += [(f"cvodes jit rtol {r:g}", "cvodes", {"rtol": r, "jit": True}) for r in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8)]
    other = [("idas jit rtol 1e-06", "idas", {"rtol": 1e-6, "jit": True}),
             ("idas jit rtol 1e-08", "idas", {"rtol": 1e-8, "jit": True}),
             ("rk jit step 0.02 deg", "rk", {"fixed_step_deg": 0.02, "jit": True}),
             ("rk jit step 0.005 deg", "rk", {"fixed_step_deg": 0.005, "jit": True}),
             ("collocation jit step 0.1 deg", "collocation", {"fixed_step_deg": 0.1, "jit": True})]
    return cv + other


def acceptance_runs(model):
    rows = {}
    for jit in (False, True):
        model.simulator(backlash=True, rtol=1e-6, jit=jit)      # build outside the timing
        t, sim = median_time(lambda: model.simulate(SPEED, cycles=10, backlash=True, rtol=1e-6, jit=jit,
                                                    reuse=False), repeats=REPEATS if jit else 1)
        rows["jit" if jit else "interpreted"] = {
            "wall_time_s": t, "integration_time_s": sim.stats["integration_time_s"],
            "steps_per_cycle": sim.stats["steps_per_cycle"],
            "build_time_s": sim.stats["build_time_s"]}
        print(f"  10 cycles with lash, jit={jit}: {t:.2f} s", flush=True)
    stats = {}
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10):
        sim = model.simulate(SPEED, cycles=10, backlash=True, rtol=rtol, jit=True,
                             **({"atol": 1e-11} if rtol == 1e-10 else {}))
        f = sim.mesh_force_N[MESH]
        stats[f"{rtol:g}"] = {"peak_drive_force_N": float(f.max()), "rms_force_N": float(np.sqrt((f ** 2).mean())),
                              "back_impacts": float(sim.contact_summary().loc[MESH, "back_impacts_integrated"]),
                              "steps_per_cycle_mean": float(np.mean(sim.stats["steps_per_cycle"]))}
    ref = stats["1e-10"]
    for v in stats.values():
        v["rms_error_vs_1e-10"] = abs(v["rms_force_N"] - ref["rms_force_N"]) / ref["rms_force_N"]
        v["peak_error_vs_1e-10"] = abs(v["peak_drive_force_N"] - ref["peak_drive_force_N"]) / ref["peak_drive_force_N"]
    rows["ten_cycle_statistics"] = stats
    return rows


def approximation_checks():
    out = {}
    base = default_timing_model("spur")
    actual = default_timing_model("spur", excitation_angle="actual")
    res = {}
    for label, m in (("nominal", base), ("actual", actual)):
        t0 = time.perf_counter()
        sim = m.simulate(SPEED, cycles=1, backlash=False, run_in_cycles=2, jit=True)
        f = sim.mesh_force_N[MESH]
        res[label] = {"peak_N": float(f.abs().max()), "rms_N": float(np.sqrt((f ** 2).mean())),
                      "time_s": time.perf_counter() - t0, "trace": f.to_numpy()}
    out["excitation_angle"] = {
        k: {kk: vv for kk, vv in v.items() if kk != "trace"} for k, v in res.items()}
    out["excitation_angle"]["max_trace_difference_over_peak"] = float(
        np.max(np.abs(res["nominal"]["trace"] - res["actual"]["trace"])) / res["actual"]["peak_N"])
    rows = []
    for harmonics in (3, 5, 9):
        m = default_timing_model("spur", stiffness_harmonics=harmonics)
        f = m.simulate(SPEED, cycles=1, backlash=False, run_in_cycles=2, jit=True).mesh_force_N[MESH]
        rows.append({"stiffness_harmonics": harmonics, "peak_N": float(f.abs().max()),
                     "rms_N": float(np.sqrt((f ** 2).mean()))})
    out["stiffness_harmonics_no_lash"] = rows
    rows = []
    for width in (0.2, 0.05, 0.0125):
        m = default_timing_model("spur", contact_width_um=width)
        sim = m.simulate(1000.0, cycles=1, backlash=True, run_in_cycles=1, jit=True)
        f = sim.mesh_force_N[MESH]
        rows.append({"contact_width_um": width, "speed_rpm": 1000.0, "peak_N": float(f.abs().max()),
                     "rms_N": float(np.sqrt((f ** 2).mean())),
                     "back_impacts": float(sim.contact_summary().loc[MESH, "back_impacts_integrated"]),
                     "steps_per_cycle": sim.stats["steps_per_cycle"][-1]})
    out["contact_width_lash_1000rpm"] = rows
    return out


def linear_analysis():
    out = {}
    for kind in ("spur", "helical"):
        m = default_timing_model(kind)
        modes = damped_modes(m.network)
        out[kind] = {"damped_modes": modes.head(8).round(4).to_dict("records"),
                     "undamped_frequencies_Hz": [float(v) for v in m.natural_frequencies_Hz()[:10]]}
    base = default_timing_model("spur")
    camp = campbell_diagram(base.network, np.arange(750.0, 3001.0, 50.0), orders=np.arange(0.5, 12.01, 0.5),
                            max_frequency_Hz=1000.0)
    out["campbell_crossings_major_orders"] = camp["crossings"][camp["crossings"]["order"] % 1.5 == 0].round(
        2).to_dict("records")
    m = default_timing_model("spur", stiffness_variation=0.0)
    out["forced_response_vs_time_domain"] = []
    for speed in (1500.0, SPEED):
        fr = forced_response(m.network, [speed], max_order=48.0, parameters=m.parameters_at(speed))["summary"]
        sim = m.simulate(speed, cycles=1, backlash=False, steady_state_tol=1e-4, jit=True)
        f = sim.mesh_force_N[MESH]
        row = fr[fr.element == MESH].iloc[0]
        out["forced_response_vs_time_domain"].append({
            "speed_rpm": speed, "harmonic_balance_max_N": float(row["max"]),
            "harmonic_balance_min_N": float(row["min"]), "time_domain_max_N": float(f.max()),
            "time_domain_min_N": float(f.min()), "harmonic_balance_rms_dynamic_N": float(row["rms_dynamic"]),
            "time_domain_rms_dynamic_N": float(np.sqrt(((f - f.mean()) ** 2).mean())),
            "note": "linear model, constant mesh stiffness; the time domain keeps the state-dependent reciprocating "
                    "inertia torques, the harmonic balance the nominal-motion excitation"})
    return out


def sensitivities():
    m = default_timing_model("spur")
    sim = m.simulator(backlash=False, rtol=1e-8, jit=True)
    df = response_sensitivities(sim, SPEED, ["crank-cam.stiffness_N_per_m", "crank-cam.damping_N_s_per_m",
                                             "damper.damping_Nms_per_rad"],
                                output=("mesh_force_N", "crank-cam"), overrides=m.parameters_at(SPEED), cycles=2,
                                run_in_cycles=3)
    out = {"no_lash_2500rpm": df.to_dict("records")}
    sim_l = m.simulator(backlash=True, rtol=1e-8, jit=True)
    df_l = response_sensitivities(sim_l, 750.0, ["crank-cam.backlash_mm", "crank-cam.damping_N_s_per_m"],
                                  output=("mesh_force_N", "crank-cam"), overrides=m.parameters_at(750.0), cycles=1,
                                  run_in_cycles=2)
    out["lash_750rpm"] = df_l.to_dict("records")
    out["lash_750rpm_note"] = ("with lash the default train rattles at every speed (speed sweep: 6-22 back-flank "
                               "impacts per cycle on crank-cam, cycle-to-cycle change 0.6-1): the response is not "
                               "periodic and its derivatives are not meaningful -- the finite differences disagree")
    return out


def main(argv=None):
    args = bench_args(__doc__, argv, globals(), QUICK)
    if args.quick:
        return quick_main()
    result = {
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "python": platform.python_version(), "cpus": os.cpu_count(),
                    "load_average_start": list(os.getloadavg())},
        "versions": {"gearopt": gearopt.__version__, "casadi": ca.__version__, "numpy": np.__version__,
                     "scipy": scipy.__version__},
        "speed_rpm": SPEED, "mesh": MESH, "quick": False,
    }
    model = default_timing_model("spur")
    for lash in (True, False):
        key = "lash" if lash else "no_lash"
        print(f"work-precision, {key}", flush=True)
        case = Case(model, lash)
        rows = casadi_runs(case, configs())
        rows += scipy_runs(case, (1e-4, 1e-6, 1e-8) if not lash else (1e-4, 1e-6))
        metric = "error_first_60deg" if lash else "error_cycle"
        result[f"work_precision_{key}"] = {"error_metric": metric, "reference": "cvodes rtol 1e-10 atol 1e-11 jit",
                                           "peak_reference_force_N": case.peak, "rows": rows,
                                           "scipy_over_cvodes_at_equal_error": ratios_at_equal_error(rows, metric)}
        if lash:
            div = {}
            for rtol in (1e-5, 1e-6, 1e-7):
                sim = model.simulator(backlash=True, rtol=rtol, jit=True)
                f = case.force(sim, np.array(sim.integrator(x0=case.x0, p=case.pvec)["xf"]))
                e = np.abs(f - case.ref) / case.peak
                first = np.nonzero(e > 0.01)[0]
                div[f"{rtol:g}"] = float(np.degrees(case.grid[first[0]])) if first.size else None
            result["work_precision_lash"]["divergence_angle_deg_at_1pct"] = div
    print("acceptance runs", flush=True)
    result["acceptance_10_cycles_lash"] = acceptance_runs(model)
    print("approximations", flush=True)
    result["approximations"] = approximation_checks()
    print("linear analysis", flush=True)
    result["linear_analysis"] = linear_analysis()
    print("sensitivities", flush=True)
    result["sensitivities"] = sensitivities()
    print("speed sweep", flush=True)
    speeds = np.arange(750.0, 3001.0, 250.0)
    t0 = time.perf_counter()
    sweep = speed_sweep(model, speeds, backlash=(False, True), cycles=2, run_in_cycles=2, jit=True)
    result["speed_sweep"] = {"time_s": time.perf_counter() - t0,
                             "rows": sweep.replace({np.nan: None}).to_dict("records")}
    helical = default_timing_model("helical")
    hsweep = speed_sweep(helical, speeds, backlash=(False, True), cycles=2, run_in_cycles=2, jit=True,
                         joints=("cam", "fp", "ac"))
    result["speed_sweep_helical"] = {"rows": hsweep.replace({np.nan: None}).to_dict("records")}
    result["machine"]["load_average_end"] = list(os.getloadavg())
    (OUT / "dynamics.json").write_text(json.dumps(result, indent=2, default=float) + "\n")
    plot(result, sweep, hsweep, model)
    return result


def plot(result, sweep, hsweep, model):
    fig, ax = plt.subplots(2, 3, figsize=(18, 9))
    for a, key in ((ax[0, 0], "work_precision_lash"), (ax[0, 1], "work_precision_no_lash")):
        wp = result[key]
        metric = wp["error_metric"]
        groups = {}
        for r in wp["rows"]:
            if metric in r:
                label = r["integrator"] + (" jit" if r.get("jit") else "")
                groups.setdefault(label, []).append((r[metric], r["time_s"]))
        for label, pts in groups.items():
            pts.sort()
            a.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=label)
        a.set_xlabel(f"{metric} (crank-cam force, relative to peak)")
        a.set_ylabel("integration time for one cycle [s]")
        a.set_title(f"{key.replace('_', ' ')}, {SPEED:.0f} rpm")
        a.grid(True, which="both", alpha=0.3)
        a.legend(fontsize=7)
    a = ax[0, 2]
    for lash, color in ((False, "tab:blue"), (True, "tab:red")):
        sim = model.simulate(SPEED, cycles=1, backlash=lash, run_in_cycles=2, jit=True)
        a.plot(sim.crank_angle_deg, sim.mesh_force_N[MESH], color=color, lw=0.7,
               label=f"{'lash' if lash else 'no lash'}")
    a.set_xlabel("crank angle [deg]")
    a.set_ylabel("crank-cam mesh force [N]")
    a.set_title(f"crank-cam force at {SPEED:.0f} rpm (third cycle, spur)")
    a.legend()
    a.grid(alpha=0.3)
    a = ax[1, 0]
    for mesh, style in (("crank-cam", "-"), ("cam-ac", "--"), ("cam-fp", ":")):
        for lash, color in ((False, "tab:blue"), (True, "tab:red")):
            d = sweep[(sweep.element == mesh) & (sweep.backlash == lash)]
            a.plot(d.speed_rpm, d.peak_drive_force_N, style, color=color,
                   label=f"{mesh} {'lash' if lash else 'no lash'}")
    a.set_xlabel("engine speed [rpm]")
    a.set_ylabel("peak drive-flank force [N]")
    a.set_title("speed sweep (spur, 2 recorded cycles)")
    a.legend(fontsize=7)
    a.grid(alpha=0.3)
    a = ax[1, 1]
    for lash, color in ((False, "tab:blue"), (True, "tab:red")):
        d = hsweep[(hsweep.element == "joint:cam") & (hsweep.backlash == lash)]
        a.plot(d.speed_rpm, d.peak_axial_force_N, "-", color=color, label=f"peak |F_a| {'lash' if lash else 'no lash'}")
    a.set_xlabel("engine speed [rpm]")
    a.set_ylabel("cam gear net axial force [N]")
    a2 = a.twinx()
    for lash, color in ((False, "tab:blue"), (True, "tab:red")):
        d = hsweep[(hsweep.element == "joint:cam") & (hsweep.backlash == lash)]
        a2.plot(d.speed_rpm, d.min_combined_margin, "--", color=color)
    a2.set_ylabel("cam joint min combined slip margin (dashed)")
    a.set_title("helical train: cam gear thrust and walk-off margin")
    a.legend(fontsize=7)
    a.grid(alpha=0.3)
    a = ax[1, 2]
    camp = campbell_diagram(model.network, np.arange(750.0, 3001.0, 50.0), orders=[1.5, 3, 4.5, 6, 7.5, 9],
                            max_frequency_Hz=1200.0)
    for f in camp["modes"]["frequency_Hz"]:
        a.axhline(f, color="0.6", lw=0.8)
    for order, d in camp["lines"].groupby("order"):
        a.plot(d.speed_rpm, d.frequency_Hz, label=f"order {order:g}")
    a.set_ylim(0, 1200)
    a.set_xlabel("engine speed [rpm]")
    a.set_ylabel("frequency [Hz]")
    a.set_title("Campbell diagram (spur, linearised; grey: natural frequencies)")
    a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(OUT / "dynamics.png", dpi=120)


def quick_main():
    """The no-lash work-precision of CVODES (JIT, two tolerances) against scipy LSODA at one tolerance, one cycle
    (the test suite's run: scipy must be slower than CVODES at equal error, as in the full run)."""
    model = default_timing_model("spur")
    case = Case(model, False)
    rows = casadi_runs(case, [(f"cvodes jit rtol {r:g}", "cvodes", {"rtol": r, "jit": True}) for r in (1e-4, 1e-6)])
    rows += scipy_runs(case, (1e-4,), methods=("LSODA",))
    result = {"quick": True, "speed_rpm": SPEED, "mesh": MESH,
              "work_precision_no_lash": {"error_metric": "error_cycle", "rows": rows,
                                         "reference": f"cvodes rtol {REFERENCE_RTOL:g} jit",
                                         "scipy_over_cvodes_at_equal_error": ratios_at_equal_error(rows,
                                                                                                   "error_cycle")}}
    (OUT / "dynamics.json").write_text(json.dumps(result, indent=2, default=float) + "\n")
    return result


if __name__ == "__main__":
    main()
