"""What does a smaller PPTE cost? Trade-off front, sensitivity report and tolerance robustness of one mesh's tip
relief over its torque range (``--mesh``; default the spur train's only or root mesh: crank-cam of the packaged
timing train).

Scene: the spur pair's four tip-relief variables (amounts and start roll angles of both gears), the largest PPTE
over the data's torque range (``[meshes.<mesh>] design_torque_Nm`` x ``[design_loads] torque_range_fractions``)
minimised, with the limits of the data (``[design_limits]``): loaded contact ratio >= ``min_loaded_contact_ratio``
at every torque, and the largest contact stress not above the unmodified pair's own maximum (exact LTCA).

1. Fronts (:func:`gearopt.studies.pareto_front`): PPTE against the loaded contact ratio; and PPTE against the
   contact-stress limit -- for this spur pair the largest stress sits in single-pair contact where tip relief does
   not act, so the two ends coincide and the script records that finding instead of a front.
2. Sensitivity report (:func:`gearopt.studies.sensitivity_report`) of the optimum with the data's limits.
3. Robustness (:func:`gearopt.studies.monte_carlo`) under the default tolerances (tip-relief amounts ±2 µm, starts
   ±0.5°, :mod:`gearopt.studies.tolerances`), and the robust design (:func:`gearopt.studies.robust_design`: limits
   held at the tolerance corners of the smooth model) on the same samples, each also re-checked on 200 of the
   samples (64 with ``--quick``) by the exact LTCA: the headline probabilities are the exact ones, the smooth
   model's beside them (``monte_carlo_summary.csv`` has both); Sobol indices (SALib) of every quantity over the
   tolerances.

Writes to ``out/ppte_trade_off/``: ``front.csv``, ``front.png``, ``sensitivity.csv``, ``sensitivity.md``,
``monte_carlo_summary.csv`` (nominal and robust design), ``sobol_indices.csv``, ``summary.json``.

Usage: ``python problems/ppte_trade_off.py [--mesh MESH] [--points 9] [--samples 2000] [--executor serial|processes|dask]
[--quick] [--out DIR]``.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import pandas as pd

from gearopt.cli import run_script
from gearopt.data import load_system
from gearopt.design.scene import Scene
from gearopt.errors import GearoptInputError
from gearopt.studies import (Tolerance, monte_carlo, pareto_front, relief_scene_from_data, robust_design,
                             sensitivity_report, sobol_indices)
from gearopt.studies.tolerances import MICROGEOMETRY_TOLERANCES

from gearopt.studies.scene_study import RELIEF  # noqa: E402  (the four relief variables of the scene)
DEFAULT_OUT = Path("out") / "ppte_trade_off"


def build_scene(quick: bool, data_file: Path | None = None, mesh: str | None = None) -> tuple[Scene, dict]:
    """The data's tip-relief scene of ``mesh`` (default :meth:`System.default_mesh <gearopt.System.default_mesh>`; ``quick``: 24 NLP positions instead
    of 40) and its data (``data_file``: your own train; default the packaged timing train)."""
    system = load_system(data_file)
    mesh = mesh or system.default_mesh("spur")
    system.mesh(mesh)
    scene = relief_scene_from_data(system, system.train("spur"), mesh, positions=24 if quick else None)
    return scene, {"mesh": mesh, "torques_Nm": [lc.torque_Nm for lc in scene.load_cases],
                   "max_contact_stress_limit_MPa": scene.limits[0].upper,
                   "min_loaded_contact_ratio": scene.limits[1].lower}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mesh", default=None, help="mesh of the spur train (default: its only mesh, else its root "
                                                      "mesh)")
    parser.add_argument("--points", type=int, default=9, help="points of the front (default 9)")
    parser.add_argument("--samples", type=int, default=2000, help="Monte Carlo samples (default 2000)")
    parser.add_argument("--executor", default="serial", help="serial, processes, dask or a scheduler address")
    parser.add_argument("--quick", action="store_true",
                        help="4 points (ends from one start), 256 samples, 24 NLP positions")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    args = parser.parse_args(argv)
    points, samples = (4, 256) if args.quick else (args.points, args.samples)
    if points < 3 or samples < 1:
        parser.error(f"--points {points} must be >= 3 and --samples {samples} >= 1")
    args.out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    scene, data = build_scene(args.quick, args.data, args.mesh)
    mesh = data["mesh"]

    front = pareto_front(scene, "loaded_contact_ratio", mesh, points=points, starts=1 if args.quick else 4,
                         executor=args.executor)
    front.table.to_csv(args.out / "front.csv", index=False)
    front.plot().savefig(args.out / "front.png", dpi=110)
    try:
        pareto_front(scene, "max_contact_stress_MPa", mesh, points=3)
        stress_front = "a front exists"
    except GearoptInputError as exc:
        stress_front = str(exc)

    # several local optima: the best of four starts; one NLP (no refinement) for the nominal and the robust design alike
    nominal = scene.build().solve(starts=4, refine=False)
    report = sensitivity_report(nominal)
    report.to_csv(args.out / "sensitivity.csv")
    (args.out / "sensitivity.md").write_text(report.markdown() + "\n")

    names = RELIEF[:2] if args.quick else RELIEF      # quick: the two amounts only (4 corners instead of 16)
    tolerances = [Tolerance.symmetric(f"{mesh}.{v}", MICROGEOMETRY_TOLERANCES[v]) for v in names]
    robust = robust_design(scene, tolerances, start=nominal)        # from the nominal optimum
    exact_samples = min(samples, 64 if args.quick else 200)
    mc = {name: monte_carlo(r, samples=samples, seed=0, executor=args.executor, tolerances=tolerances,
                            exact_samples=exact_samples) for name, r in (("nominal", nominal), ("robust", robust))}
    summary_table = pd.concat([m.summary.assign(design=name) for name, m in mc.items()], ignore_index=True)
    summary_table.to_csv(args.out / "monte_carlo_summary.csv", index=False)
    sobol = sobol_indices(nominal, samples=64 if args.quick else 512, seed=0, executor=args.executor,
                          tolerances=tolerances)
    sobol.to_csv(args.out / "sobol_indices.csv", index=False)
    lcr = sobol[sobol["quantity"].str.startswith("loaded_contact_ratio")].sort_values("ST", ascending=False)

    def ppte_of(r):  # the verified headline: the exact LTCA's PPTE of the design, worst load case
        return float(r.exact_check["ppte_um"].max())

    def worst_break(m, column="exact_probability_broken"):    # the exact re-check's, unless asked for the smooth
        return float(m.summary[column].max())

    knee = front.knee()
    summary = {
        "data": data,
        "front": {"points": len(front.table), "failed": int((front.table["status"] != "ok").sum()),
                  "ends": front.ends, "knee": {c: float(knee[c]) for c in
                                               [front.objective_column, front.quantity_column]}},
        "contact_stress_front": stress_front,
        "nominal": {"ppte_um": ppte_of(nominal), "values": nominal.values,
                    "top_sensitivities": report.table.head(5)[["name", "sensitivity", "log_sensitivity"]]
                    .to_dict("records"), "worst_probability_broken": worst_break(mc["nominal"]),
                    "worst_probability_broken_smooth": worst_break(mc["nominal"], "probability_broken")},
        "robust": {"ppte_um": ppte_of(robust), "values": robust.values,
                   "worst_probability_broken": worst_break(mc["robust"]),
                   "worst_probability_broken_smooth": worst_break(mc["robust"], "probability_broken")},
        "tolerances": [t.__dict__ for t in tolerances], "samples": samples, "exact_samples": exact_samples,
        "largest_total_sobol_index_of_loaded_contact_ratio": {k: (v if isinstance(v, str) else float(v))
                                                              for k, v in lcr.iloc[0][["quantity", "input", "ST"]]
                                                              .items()}, "elapsed_s": time.perf_counter() - t0,
    }
    (args.out / "summary.json").write_text(json.dumps(summary, indent=1, default=float))
    print(f"front: {len(front.solved)} points, PPTE {front.ends['objective']['objective']:.3f}-"
          f"{front.ends['quantity']['objective']:.3f} um; nominal PPTE {summary['nominal']['ppte_um']:.3f} um "
          f"(worst P(limit broken), exact LTCA of {exact_samples} samples: "
          f"{summary['nominal']['worst_probability_broken']:.2f}), robust "
          f"{summary['robust']['ppte_um']:.3f} um ({summary['robust']['worst_probability_broken']:.2f}); "
          f"{args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(run_script(main))
