"""Co-design of the timing train: profile shift, helix angle, per-flank tip relief and walk-off margins in one NLP,
beside the sequential design (macro first, then micro) on the same limits.

Writes ``<out>/report.md``, ``<out>/result.json`` and ``<out>/codesign_summary.csv``. ``--quick``: the spur option
only, one load case, no refinement (a smoke run for the tests); ``--contact-stress-allowance 0.02`` lets the
contact stress exceed the unmodified meshes' maxima by 2 % (which frees the root profile shift). The logic is
:func:`gearopt.cases.timing_train.codesign_study`.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from gearopt.cli import run_script
from gearopt.data import load_system
from gearopt.cases.timing_train import CONTACT_STRESS_ALLOWANCE, CodesignStudy, codesign_study

DEFAULT_OUT = Path("out") / "codesign"


def run(quick: bool = False, data_file: Path | None = None,
        contact_stress_allowance: float = CONTACT_STRESS_ALLOWANCE) -> CodesignStudy:
    """The study on the packaged data, or on ``data_file`` (your own train)."""
    return codesign_study(load_system(data_file), quick=quick,
                          options=("spur",) if quick else ("spur", "low_helix"),
                          contact_stress_allowance=contact_stress_allowance)


def write(study: CodesignStudy, out: Path) -> dict:
    out.mkdir(parents=True, exist_ok=True)
    result = study.to_json()
    (out / "result.json").write_text(json.dumps(result, indent=2, default=_json) + "\n")
    study.summary().to_csv(out / "codesign_summary.csv", index=False)
    (out / "report.md").write_text("\n".join(["# Timing-train co-design", ""] + study.report_lines()) + "\n")
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
    parser.add_argument("--data", type=Path, default=None, metavar="FILE",
                        help="train data file (TOML in the format of the packaged default data; default: that data)")
    parser.add_argument("--contact-stress-allowance", type=float, default=CONTACT_STRESS_ALLOWANCE, metavar="F",
                        help="contact stress may exceed the unmodified mesh's maximum by this fraction (default "
                             f"{CONTACT_STRESS_ALLOWANCE:g}; 0.02 frees the root shift, see "
                             "gearopt.cases.timing_train.CONTACT_STRESS_ALLOWANCE)")
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    study = run(quick=args.quick, data_file=args.data, contact_stress_allowance=args.contact_stress_allowance)
    result = write(study, args.out)
    print(study.summary().to_string())
    rec = recommend_among(study, result, args.data, args.out)
    print(f"recommended design: {rec['design']} -- {rec['verdict']} ({rec['why']}); static requirements only (the "
          f"main job, problems/cam_gear_walkoff.py, adds the dynamic peaks)")
    print(f"wrote {args.out}/report.md, result.json, codesign_summary.csv in {time.perf_counter() - t0:.1f} s")
    return 1 if rec["verdict"] == "FAIL" else 0


def recommend_among(study: CodesignStudy, result: dict, data_file: Path | None, out: Path) -> dict:
    """The study's designs judged on every static requirement of the data's ``[requirements]`` (exact models; no
    dynamics here), the best recommended (:func:`gearopt.cases.timing_train.recommendation.timing_recommendation`);
    written to ``result.json["recommendation"]`` and the report."""
    from gearopt.cases.timing_train.recommendation import timing_recommendation
    from gearopt.cases.timing_train.summary import build_summary, summary_markdown

    rec = json.loads(json.dumps(timing_recommendation(load_system(data_file), result,
                                                      contact_meshes=tuple(study.flanks)).as_json(), default=_json))
    result["recommendation"] = rec
    (out / "result.json").write_text(json.dumps(result, indent=2, default=_json) + "\n")
    report = (out / "report.md").read_text()
    (out / "report.md").write_text(summary_markdown(build_summary(rec), rec) + "\n" + report)
    return rec


if __name__ == "__main__":
    sys.exit(run_script(main))
