"""Co-design of the timing train: profile shift, helix angle, per-flank tip relief and walk-off margins in one NLP,
beside the sequential design (macro first, then micro) on the same limits.

Writes ``<out>/report.md``, ``<out>/result.json`` and ``<out>/codesign_summary.csv``. ``--quick``: the spur option
only, one load case, no refinement (a smoke run for the tests). The logic is
:func:`gearopt.design.scene_codesign.codesign_study`.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from gearopt.design.scene_codesign import CodesignStudy, codesign_study

DEFAULT_OUT = Path("out") / "codesign"


def run(quick: bool = False) -> CodesignStudy:
    return codesign_study(quick=quick, options=("spur",) if quick else ("spur", "low_helix"))


def report_lines(study: CodesignStudy) -> list[str]:
    """Markdown lines of the study (also the main job's report section)."""
    s = study.settings
    lines = ["Minimise the largest PPTE of " + ", ".join(study.flanks) + " over the load cases "
             + ", ".join(f"{k} ({', '.join(f'{m} {t:g}' for m, t in v.items())} N m)" for k, v in s["load_cases"].items())
             + f" at {s['speed_rpm']:g} rpm; LTCA contact stress (the unmodified spur meshes' own maxima), root stress, "
             "contact temperature, loaded contact ratio, every mesh's geometry limits and, for a helical option, the "
             f"joints' axial margins >= {s['min_axial_margin']:g} at {s['overspeed_rpm']:g} rpm. Sequential = macro "
             "first (the data's root shift; the largest helix angle meeting the walk-off margins), then the flank "
             "reliefs; co-design = all in one NLP, started from the sequential answer. PPTE and stresses from the "
             "exact LTCA of each optimum.", "",
             "| option | design | root shift | helix [deg] | max PPTE [um] | min axial margin | refinements | time [s] |",
             "|---|---|---|---|---|---|---|---|"]
    for _, r in study.summary().iterrows():
        if isinstance(r.get("failed"), str) and r["failed"]:
            lines.append(f"| {r['option']} | {r['design']} | failed: {r['failed'].splitlines()[0]} ||||||")
            continue
        lines.append(f"| {r['option']} | {r['design']} | {r['root_profile_shift']:.4f} | "
                     f"{r.get('helix_angle_deg', 0.0):.3f} | {r['max_ppte_um']:.3f} | {r['min_axial_margin']:.3g} | "
                     f"{r['refinements']:.0f} | {r['time_s']:.1f} |")
    lines += ["", "Tip relief per gear flank (one tooth form per flank, shared by every mesh that loads it):", ""]
    for name, opt in study.options.items():
        for design, res in (("sequential", opt.sequential), ("codesign", opt.codesign)):
            if res is None:
                continue
            entry = study.to_json()["options"][name][design]
            lines.append(f"- {name} {design}: " + "; ".join(
                f"{m['gear']}:{m['flank']} {m['tip_relief_um']:.2f} um from {m['tip_relief_start_roll_deg']:.2f} deg "
                f"({', '.join(m['meshes'])})" for m in entry["flank_modifications"]))
    return lines + [""]


def write(study: CodesignStudy, out: Path) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    result = study.to_json()
    (out / "result.json").write_text(json.dumps(result, indent=2, default=_json) + "\n")
    study.summary().to_csv(out / "codesign_summary.csv", index=False)
    (out / "report.md").write_text("\n".join(["# Timing-train co-design", ""] + report_lines(study)) + "\n")
    return result


def _json(v):
    if isinstance(v, (np.floating, np.integer)):
        return v.item()
    if isinstance(v, float) and not np.isfinite(v):
        return str(v)
    return str(v)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="spur option, one load case, no refinement (tests)")
    parser.add_argument("--out", type=Path, default=DEFAULT_OUT, help=f"output directory (default {DEFAULT_OUT})")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    study = run(quick=args.quick)
    write(study, args.out)
    print(study.summary().to_string())
    print(f"wrote {args.out}/report.md, result.json, codesign_summary.csv in {time.perf_counter() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
