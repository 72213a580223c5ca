"""Converged-reference study of the LTCA: PPTE and maximum contact stress against the discretisation, with run time.

Cases (default data, 300 N m on the crank gear, ISO 6336 single-pair stiffness):

- ``spur_crowned``: spur crank-cam pair with linear tip relief on both gears (10 um each, starting at each gear's
  single-contact boundary next to its tip), profile crown 2 um and lead crown 4 um per gear, so the load varies
  over the face and the slices matter;
- ``spur_plain``: the same without the lead crown (the library then uses one slice: checked here against 161);
- ``helical_crowned``: the helical crank-cam pair with the microgeometry of ``spur_crowned`` (starts at the helical
  pair's own single-contact boundaries).

Reference: the finest exact run (``positions=5120``, ``slices=161``); its own convergence is reported (difference to
2560 positions and to 81 slices). Knobs, each swept with the others at the reference resolution so the error is the
knob's own: mesh positions per base pitch, slices over the face, and the softplus width of the smooth CasADi form
(at the default discretisation, error against the exact solver on the same discretisation, i.e. the smoothing
error alone). A positions x slices grid gives the combined error of practical settings. Run time per LTCA is the
median of repeats: the exact numeric solver, the smooth model (built once, evaluated numerically) and a symbolic
smooth model (6 microgeometry symbols) evaluated through a ``casadi.Function`` with and without its Jacobian.

Writes ``benchmarks/results/ltca.json`` (machine, versions, medians, the recommendation derived from the numbers)
and ``benchmarks/results/ltca.png`` (run time against PPTE and stress relative error, one series per knob).
Run: ``python benchmarks/bench_ltca.py [--quick] [--out DIR]`` (about a minute here).
"""

from __future__ import annotations

import json
import math
import platform
import time
from pathlib import Path

import casadi as ca
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402

from _timing import bench_args, median_time as _median_time  # noqa: E402  (benchmarks/_timing.py)

import gearopt as go  # noqa: E402
from gearopt.contact.layout import default_slices  # noqa: E402
from gearopt.contact.ltca import ltca  # noqa: E402
from gearopt.contact.ltca_smooth import DEFAULT_SMOOTHING_UM, LTCAModel  # noqa: E402
from gearopt.contact.microgeometry import Microgeometry  # noqa: E402

OUT = Path(__file__).resolve().parent / "results"
REPEATS = 7


def median_time(fun, repeats=REPEATS):
    """Median wall time; fewer repeats (at least 3) once the calls pass 1 s."""
    return _median_time(fun, repeats, budget_s=1.0)
TORQUE_NM = 300.0
TOLERANCE = 0.01                     # PPTE within 1 % of the converged value
REF_POSITIONS, REF_SLICES = 5120, 161
DEFAULT_POSITIONS = 40               # library defaults under test (ltca, LTCAModel, optimise_microgeometry)
POSITIONS = (10, 15, 20, 30, 40, 60, 80, 120, 160, 240, 320, 480, 640, 1280, 2560)
SLICES = (1, 2, 3, 5, 7, 11, 15, 21, 31, 41, 81)
GRID_POSITIONS = (20, 40, 80, 160, 320, 640, 1280)
GRID_SLICES = (1, 5, 11, 21, 41, 81)
SMOOTHING_UM = (1.0, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001)
SYMBOLIC_POSITIONS = (40, 160, 320)
CASES = ("spur_crowned", "spur_plain", "helical_crowned")
QUICK = {"REF_POSITIONS": 320, "REF_SLICES": 11, "POSITIONS": (20, 40), "SLICES": (1, 5), "GRID_POSITIONS": (40,),
         "GRID_SLICES": (1,), "SMOOTHING_UM": (0.05,), "SYMBOLIC_POSITIONS": (40,), "CASES": ("spur_crowned",)}


def relief_starts(pair) -> tuple:
    """Each gear's single-contact boundary next to its tip (roll angle, deg): where a 'long' tip relief starts."""
    g = pair.geometry()
    return tuple(max(float(g["lpstc_roll_deg"][i]), float(g["hpstc_roll_deg"][i])) for i in range(2))


def cases() -> dict:
    spur = go.load_default_train("spur").pairs["crank-cam"]
    hel = go.load_default_train("helical").pairs["crank-cam"]

    def mods(pair, lead_crown_um):
        return Microgeometry(tip_relief_um=(10.0, 10.0), tip_relief_start_roll_deg=relief_starts(pair),
                             relief_shape="linear", profile_crown_um=(2.0, 2.0), lead_crown_um=lead_crown_um)

    every = {"spur_crowned": (spur, mods(spur, (4.0, 4.0))),
             "spur_plain": (spur, mods(spur, (0.0, 0.0))),
             "helical_crowned": (hel, mods(hel, (4.0, 4.0)))}
    return {name: every[name] for name in CASES}


def rel(value, reference):
    return abs(value - reference) / abs(reference)


def exact_row(pair, mods, positions, slices, ref, **extra):
    res = ltca(pair, TORQUE_NM, microgeometry=mods, positions=positions, slices=slices)
    t = median_time(lambda: ltca(pair, TORQUE_NM, microgeometry=mods, positions=positions, slices=slices))
    return {"positions": positions, "slices": slices, "time_s": t, "ppte_um": res.ppte_um,
            "max_contact_stress_MPa": res.max_contact_stress_MPa,
            "ppte_rel_error": rel(res.ppte_um, ref["ppte_um"]),
            "ppte_abs_error_um": abs(res.ppte_um - ref["ppte_um"]),
            "stress_rel_error": rel(res.max_contact_stress_MPa, ref["max_contact_stress_MPa"]), **extra}


def smallest_converged(rows, knob, key="ppte_rel_error", tol=TOLERANCE, reverse=False):
    """Smallest knob value (largest for ``reverse``, i.e. smoothing width) such that it and every finer setting in
    the sweep stay within ``tol``; None if even the finest misses."""
    ordered = sorted(rows, key=lambda r: r[knob], reverse=not reverse)   # finest first
    best = None
    for r in ordered:
        if r[key] is None or r[key] > tol:
            break
        best = r[knob]
    return best


def symbolic_timing(pair, mods, positions, slices, smoothing_um):
    """A smooth model whose tip relief amounts/starts and profile crowns are MX symbols (the NLP's variables),
    wrapped in casadi Functions: TE, contact stress^2 and loaded contact ratio, and the same with their Jacobian."""
    model = LTCAModel(pair, positions=positions, slices=slices, smoothing_um=smoothing_um,
                      lead_modification=mods.has_lead_modification)
    x = ca.MX.sym("x", 6)
    sym = Microgeometry(tip_relief_um=(x[0], x[1]), tip_relief_start_roll_deg=(x[2], x[3]),
                        relief_shape=mods.relief_shape, profile_crown_um=(x[4], x[5]),
                        lead_crown_um=mods.lead_crown_um)
    t0 = time.perf_counter()
    res = model.evaluate(sym, TORQUE_NM)
    out = ca.vertcat(ca.vec(res.transmission_error_um), ca.vec(res.contact_stress_squared_MPa2),
                     ca.vec(res.loaded_contact_ratio))
    f = ca.Function("ltca_smooth", [x], [out])
    fj = ca.Function("ltca_smooth_jac", [x], [out, ca.jacobian(out, x)])
    build = time.perf_counter() - t0
    x0 = np.array([*mods.tip_relief_um, *mods.tip_relief_start_roll_deg, *mods.profile_crown_um], dtype=float)
    te = np.array(f(x0)).ravel()[:positions]
    numeric = model.evaluate(mods, TORQUE_NM).transmission_error_um
    return {"positions": positions, "slices": model.layout.slices, "smoothing_um": smoothing_um,
            "outputs": int(out.numel()), "symbols": 6, "build_s": build,
            "evaluate_s": median_time(lambda: f(x0)), "evaluate_with_jacobian_s": median_time(lambda: fj(x0)),
            "max_te_difference_to_numeric_um": float(np.max(np.abs(te - numeric)))}


def study(name, pair, mods):
    print(f"[{name}]", flush=True)
    ref_res = ltca(pair, TORQUE_NM, microgeometry=mods, positions=REF_POSITIONS, slices=REF_SLICES)
    unmodified = ltca(pair, TORQUE_NM, positions=REF_POSITIONS, slices=REF_SLICES)
    ref = {"positions": REF_POSITIONS, "slices": REF_SLICES, "ppte_um": ref_res.ppte_um,
           "max_contact_stress_MPa": ref_res.max_contact_stress_MPa,
           "unmodified_ppte_um": unmodified.ppte_um}
    self_check = {}
    for label, (P, J) in {"half_positions": (REF_POSITIONS // 2, REF_SLICES),
                          "half_slices": (REF_POSITIONS, (REF_SLICES + 1) // 2)}.items():
        r = ltca(pair, TORQUE_NM, microgeometry=mods, positions=P, slices=J)
        self_check[label] = {"positions": P, "slices": J, "ppte_rel_change": rel(r.ppte_um, ref["ppte_um"]),
                             "stress_rel_change": rel(r.max_contact_stress_MPa, ref["max_contact_stress_MPa"])}
    ref["self_convergence"] = self_check
    # where the extremes of the converged TE sit (fraction of the base pitch from the first position, at which a
    # tooth pair enters the path at A) and the largest step between neighbouring reference positions: a TE jump
    # (a loaded pair leaving the path at E) is what makes the sampled PPTE converge only like 1/positions
    te = ref_res.transmission_error_um
    g = pair.geometry()
    steps = np.abs(np.diff(np.append(te, te[0])))
    ref["te_diagnostics"] = {
        "max_at_pitch_fraction": int(np.argmax(te)) / te.size, "min_at_pitch_fraction": int(np.argmin(te)) / te.size,
        "largest_step_um": float(steps.max()), "largest_step_at_pitch_fraction": (int(np.argmax(steps)) + 1) / te.size,
        "transverse_contact_ratio_minus_1": float(g["transverse_contact_ratio"]) - 1.0}

    positions = [exact_row(pair, mods, P, REF_SLICES, ref) for P in POSITIONS]
    slices = [exact_row(pair, mods, REF_POSITIONS, J, ref) for J in SLICES]
    grid = [exact_row(pair, mods, P, J, ref) for P in GRID_POSITIONS for J in GRID_SLICES]
    lib_slices = default_slices(pair, mods)
    default = exact_row(pair, mods, DEFAULT_POSITIONS, lib_slices, ref)

    smooth = []
    exact_default = ltca(pair, TORQUE_NM, microgeometry=mods, positions=DEFAULT_POSITIONS, slices=lib_slices)
    for w in SMOOTHING_UM:
        row = {"smoothing_um": w, "positions": DEFAULT_POSITIONS, "slices": lib_slices}
        try:
            t0 = time.perf_counter()
            model = LTCAModel(pair, positions=DEFAULT_POSITIONS, slices=lib_slices, smoothing_um=w,
                              lead_modification=mods.has_lead_modification)
            row["build_s"] = time.perf_counter() - t0
            r = model.evaluate(mods, TORQUE_NM)
            row.update(time_s=median_time(lambda m=model: m.evaluate(mods, TORQUE_NM)), ppte_um=r.ppte_um,
                       max_contact_stress_MPa=r.max_contact_stress_MPa,
                       ppte_rel_error=rel(r.ppte_um, exact_default.ppte_um),
                       stress_rel_error=rel(r.max_contact_stress_MPa, exact_default.max_contact_stress_MPa),
                       ppte_rel_error_to_reference=rel(r.ppte_um, ref["ppte_um"]),
                       max_te_offset_um=float(np.max(np.abs(r.transmission_error_um
                                                            - exact_default.transmission_error_um))),
                       te_offset_bound_um=w * math.log(2.0), failure=None)
        except (RuntimeError, go.GearoptError) as exc:   # rootfinder failure or typed gearopt error
            row.update(failure=type(exc).__name__, message=str(exc)[:200], ppte_rel_error=None,
                       stress_rel_error=None)
        smooth.append(row)
    symbolic = [symbolic_timing(pair, mods, P, lib_slices, DEFAULT_SMOOTHING_UM) for P in SYMBOLIC_POSITIONS]

    converged = {
        "positions_ppte": smallest_converged(positions, "positions"),
        "positions_stress": smallest_converged(positions, "positions", "stress_rel_error"),
        "slices_ppte": smallest_converged(slices, "slices"),
        "slices_stress": smallest_converged(slices, "slices", "stress_rel_error"),
        "positions_ppte_abs_1pct_of_unmodified": smallest_converged(
            positions, "positions", "ppte_abs_error_um", TOLERANCE * ref["unmodified_ppte_um"]),
        "largest_smoothing_um_ppte": smallest_converged([r for r in smooth if r["ppte_rel_error"] is not None],
                                                        "smoothing_um", reverse=True),
    }
    ok = [r for r in grid if r["ppte_rel_error"] <= TOLERANCE and r["stress_rel_error"] <= TOLERANCE]
    cheapest = min(ok, key=lambda r: r["time_s"]) if ok else None
    return {"pair": name, "microgeometry": {k: v for k, v in vars(mods).items() if k in (
        "tip_relief_um", "tip_relief_start_roll_deg", "relief_shape", "profile_crown_um", "lead_crown_um")},
        "library_default_slices": lib_slices, "reference": ref, "positions_sweep": positions,
        "slices_sweep": slices, "grid": grid, "library_default": default, "smoothing_sweep": smooth,
        "symbolic": symbolic, "converged_within_1pct": converged,
        "cheapest_grid_setting_within_1pct": cheapest}


def recommendation(results: dict) -> dict:
    """Text and numbers derived from the measured sweeps (nothing here is typed in by hand)."""
    lines, worst_default = [], 0.0
    for name, r in results.items():
        d = r["library_default"]
        worst_default = max(worst_default, d["ppte_rel_error"])
        c = r["converged_within_1pct"]
        ref = r["reference"]
        lines.append(f"{name}: converged PPTE {ref['ppte_um']:.4f} um (unmodified pair {ref['unmodified_ppte_um']:.3f} "
                     f"um); defaults (positions={d['positions']}, slices={d['slices']}) give PPTE error "
                     f"{100 * d['ppte_rel_error']:.2f} % ({d['ppte_abs_error_um']:.4f} um) and stress error "
                     f"{100 * d['stress_rel_error']:.2f} %; "
                     f"PPTE within 1 % from positions >= {c['positions_ppte']} (at reference slices; within 1 % of "
                     f"the unmodified PPTE from {c['positions_ppte_abs_1pct_of_unmodified']}), "
                     f"slices >= {c['slices_ppte']} (at reference positions), smoothing <= "
                     f"{c['largest_smoothing_um_ppte']} um")
    need_p = max((r["converged_within_1pct"]["positions_ppte"] or math.inf) for r in results.values())
    need_j = max((r["converged_within_1pct"]["slices_ppte"] or math.inf) for r in results.values()
                 if r["library_default_slices"] > 1)
    need_p_abs = max((r["converged_within_1pct"]["positions_ppte_abs_1pct_of_unmodified"] or math.inf)
                     for r in results.values())
    need_w = min((r["converged_within_1pct"]["largest_smoothing_um_ppte"] or 0.0) for r in results.values())
    plain = results.get("spur_plain")
    one_slice_exact = plain is not None and max(s["ppte_rel_error"] for s in plain["slices_sweep"]) < 1e-9
    verdict = {
        "tolerance": TOLERANCE,
        "defaults_within_tolerance": bool(worst_default <= TOLERANCE),
        "worst_default_ppte_rel_error": worst_default,
        "positions_needed": need_p, "positions_needed_for_1pct_of_unmodified_ppte": need_p_abs, "slices_needed_with_lead_modification_or_helix": need_j,
        "largest_smoothing_um_within_tolerance": need_w,
        "one_slice_exact_for_plain_spur": bool(one_slice_exact),
        "keep": [], "change": [],
    }
    (verdict["keep"] if need_p <= DEFAULT_POSITIONS else verdict["change"]).append(
        f"positions: {DEFAULT_POSITIONS} -> {'keep' if need_p <= DEFAULT_POSITIONS else need_p} "
        f"(smallest value keeping PPTE within 1 % in every case)")
    (verdict["keep"] if need_j <= 11 else verdict["change"]).append(
        f"slices with lead modification or helix: 11 -> {'keep' if need_j <= 11 else need_j}")
    (verdict["keep"] if need_w >= DEFAULT_SMOOTHING_UM else verdict["change"]).append(
        f"smoothing: {DEFAULT_SMOOTHING_UM} um -> {'keep' if need_w >= DEFAULT_SMOOTHING_UM else need_w}")
    verdict["keep"].append(f"slices for a plain spur pair: 1 (exact: "
                           f"{'identical to 161 slices' if one_slice_exact else 'NOT identical to 161 slices'})")
    verdict["per_case"] = lines
    return verdict


def plot(results: dict, path: Path) -> None:
    names = list(results)
    fig, axes = plt.subplots(2, len(names), figsize=(5.2 * len(names), 8.0), squeeze=False)
    floor = 1e-9
    for col, name in enumerate(names):
        r = results[name]
        for row, key in enumerate(("ppte_rel_error", "stress_rel_error")):
            ax = axes[row][col]
            series = ((f"positions (slices={REF_SLICES})", r["positions_sweep"], "positions", "o-"),
                      (f"slices (positions={REF_POSITIONS})", r["slices_sweep"], "slices", "s-"),
                      ("smooth width, numeric evaluate\n(vs exact, same discretisation)",
                       [s for s in r["smoothing_sweep"] if s.get(key) is not None], "smoothing_um", "^-"))
            for label, rows, knob, style in series:
                x = [s["time_s"] for s in rows]
                y = [max(s[key], floor) for s in rows]
                ax.loglog(x, y, style, label=label, ms=4)
                for s, xi, yi in zip(rows[::2], x[::2], y[::2]):
                    ax.annotate(f"{s[knob]:g}", (xi, yi), fontsize=6, textcoords="offset points", xytext=(3, 2))
            g = r["grid"]
            ax.loglog([s["time_s"] for s in g], [max(s[key], floor) for s in g], "x", color="grey",
                      label="grid positions x slices")
            d = r["library_default"]
            ax.loglog([d["time_s"]], [max(d[key], floor)], "*", ms=14, color="red",
                      label=f"library default (P={d['positions']}, J={d['slices']})")
            ax.axhline(TOLERANCE, color="k", lw=0.8, ls="--")
            ax.set_xlabel("run time per LTCA [s] (median)")
            ax.set_ylabel(("PPTE" if row == 0 else "max contact stress") + " relative error (0 at 1e-9)")
            ax.set_title(f"{name}, {TORQUE_NM:g} N m")
            ax.grid(True, which="both", alpha=0.3)
            if row == 0 and col == 0:
                ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main(argv=None):
    args = bench_args(__doc__, argv, globals(), QUICK)
    t_start = time.perf_counter()
    results = {name: study(name, pair, mods) for name, (pair, mods) in cases().items()}
    verdict = recommendation(results)
    # the per-knob thresholds combined, checked against the reference (the two discretisation errors can add up)
    check = {}
    for name, (pair, mods) in cases().items():
        ref = results[name]["reference"]
        J = verdict["slices_needed_with_lead_modification_or_helix"] if default_slices(pair, mods) > 1 else 1
        P = verdict["positions_needed"]
        if not (math.isfinite(P) and math.isfinite(J)):   # a sweep too short to converge (quick mode)
            continue
        check[name] = exact_row(pair, mods, int(P), int(J), ref)
    verdict["recommended_setting_check"] = check
    verdict["recommended_setting_within_tolerance"] = bool(check) and all(r["ppte_rel_error"] <= TOLERANCE
                                                                          for r in check.values())
    result = {
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "python": platform.python_version()},
        "versions": {"casadi": ca.__version__, "numpy": np.__version__, "scipy": scipy.__version__,
                     "gearopt": go.__version__},
        "repeats": REPEATS, "statistic": "median wall time (at least 3 repeats; fewer than REPEATS when a call "
                                         "takes > 1/3 s)",
        "torque_Nm": TORQUE_NM, "stiffness": "iso6336", "driving_gear": 1,
        "cases": results, "recommendation": verdict, "quick": args.quick,
        "run_time_s": time.perf_counter() - t_start,
    }
    (OUT / "ltca.json").write_text(json.dumps(result, indent=2, default=float) + "\n")
    plot(results, OUT / "ltca.png")
    for name, r in results.items():
        d = r["library_default"]
        ref = r["reference"]
        print(f"{name} ref PPTE {ref['ppte_um']:.5f} um, stress {ref['max_contact_stress_MPa']:.2f} MPa | default: "
              f"{1e3 * d['time_s']:.3f} ms, PPTE err {d['ppte_rel_error']:.3g}, stress err {d['stress_rel_error']:.3g}")
        print("  converged:", r["converged_within_1pct"])
        for s in r["symbolic"]:
            print("  symbolic", {k: (f"{v:.3g}" if isinstance(v, float) else v) for k, v in s.items()})
    print(json.dumps({k: v for k, v in verdict.items() if k != "recommended_setting_check"}, indent=1))
    for name, r in verdict["recommended_setting_check"].items():
        print(f"  recommended setting, {name}: P={r['positions']} J={r['slices']} {1e3 * r['time_s']:.2f} ms, "
              f"PPTE err {r['ppte_rel_error']:.3g}, stress err {r['stress_rel_error']:.3g}")
    print(f"total {result['run_time_s']:.1f} s")
    return result


if __name__ == "__main__":
    main()
