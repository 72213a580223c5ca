"""Verdict first: the one-screen opening of the main job's report, built from its recommended design.

The verdict is the recommended design's (``result.json["recommendation"]``,
:func:`gearopt.design.recommendation.recommend`): each requirement of the data's ``[requirements]`` is one row
with the worst value over its instances (joints, meshes, speeds, load cases), the limit, the unit, PASS/FAIL and,
when it fails, what it would take. The same rows go to ``result.json["summary"]`` (numbers at engineering
precision, three significant figures) and to the top of ``report.md`` (:func:`summary_markdown`), after the
design sheet (:func:`design_sheet_markdown`).
"""

from __future__ import annotations

import math
from typing import Any, Iterable

from ...report.tables import eng

def _round(value: Any, digits: int = 3) -> Any:
    if isinstance(value, str) or value is None:
        return value
    v = float(value)
    if not math.isfinite(v):
        return "inf" if v > 0 else ("-inf" if v < 0 else "nan")
    return float(eng(v, digits)) if v != 0.0 else 0.0


def build_summary(recommendation: dict, *, load_basis: dict | None = None, figures: Iterable[str] = (),
                  quick: bool = False) -> dict:
    """The verdict of the recommended design (``result.json["recommendation"]``, built by
    :func:`gearopt.design.recommendation.recommend` from the data's ``[requirements]``): ``{"verdict", "design",
    "option", "why", "failed", "requirements": [...], "load_basis", "figures", "quick"}``; every requirement row
    as the recommendation holds it, numbers at engineering precision (three significant figures). The verdict is
    this list's and nothing else's."""
    rows = []
    for r in recommendation["requirements"]:
        row = {**r, "requirement": r["name"], "value": _round(r["value"]), "limit": _round(r["limit"])}
        rows.append(row)
    failed = [r["name"] for r in rows if r["verdict"] == "FAIL"]
    return {"verdict": recommendation["verdict"], "design": recommendation["design"],
            "option": recommendation["option"], "why": recommendation["why"], "failed": failed,
            "requirements": rows, "load_basis": dict(load_basis or {}), "figures": list(figures), "quick": quick}


QUICK_BANNER = ("> **Quick run (`--quick`): reduced settings** -- one load case and no refinement in the co-design, "
                "one recorded cycle in the dynamics, fewer Monte Carlo samples. Its numbers and its verdict are a "
                "smoke test, not the finding of the full run (run without `--quick` for that).")


def _unit(unit: str) -> str:
    return {"um": "µm", "degC": "°C", "C": "°C", "N m": "N·m", "-": "-"}.get(unit, unit)


def design_sheet_markdown(recommendation: dict) -> list[str]:
    """The design sheet: per flank (once) the tip relief with its start diameter and length, crown, shape and start
    transition; per gear the teeth, profile shift, tip diameter with tolerance and joint."""
    lines = ["### Design sheet: tip relief per flank (each flank once, however many meshes load it)", "",
             "| gear | flank | tip relief [µm] | start diameter [mm] | length to tip [mm] | crown [µm] | shape | "
             "start transition | meshes |", "|---|---|---:|---:|---:|---:|---|---|---|"]
    for f in recommendation["flanks"]:
        start = "-" if f["tip_relief_start_diameter_mm"] is None else f"{f['tip_relief_start_diameter_mm']:.2f}"
        length = "-" if f["tip_relief_length_mm"] is None else f"{f['tip_relief_length_mm']:.2f}"
        lines.append(f"| {f['gear']} | {f['flank']} | {eng(f['tip_relief_um'])} | {start} | {length} | "
                     f"{eng(f['crown_um'])} | {f['relief_shape']} | {f['start_transition']} | "
                     f"{', '.join(f['meshes'])} |")
    lines += ["", "### Design sheet: gears", "",
              "| gear | teeth | profile shift | tip diameter [mm] | tolerance [mm] | joint |",
              "|---|---:|---:|---:|---|---|"]
    for name, g in recommendation["gears"].items():
        j = g.get("joint") or {}
        joint = ("-" if not j else f"press fit {j.get('fit')}" if j["type"] == "press_fit"
                 else f"taper, nut torque {eng(j.get('nut_torque_Nm'))} N·m")
        if j and j.get("free"):
            joint += " (sized)"
        lo, hi = g["tip_diameter_tolerance_mm"]
        lines.append(f"| {name} | {g['teeth']} | {g['profile_shift']:+.4f} | {g['tip_diameter_mm']:.3f} | "
                     f"{lo:+.3f}/{hi:+.3f} | {joint} |")
    notes = recommendation.get("notes") or []
    joints = [n.removeprefix("joint ") for n in notes if n.startswith("joint ")]
    if joints:
        lines += ["", "Joints the data marks free, sized for this design's demands (design load and the dynamic peaks "
                      "over speed, weakest tolerance): " + "; ".join(joints) + "."]
    others = [n for n in notes if not n.startswith("joint ")]
    if others:
        lines += ["", "Notes: " + "; ".join(others) + "."]
    return lines + [""]


def summary_markdown(summary: dict, recommendation: dict) -> str:
    """The report's opening: the verdict, the recommended design and why it won, its design sheet, then every
    requirement with its worst value, limit, verdict and, when it fails, what it would take."""
    n_fail, n = len(summary["failed"]), len(summary["requirements"])
    macro = recommendation["macro"]
    lines = [f"## Verdict: {summary['verdict']}" + (f" ({n_fail} of {n} requirements fail)" if n_fail else
                                                    f" (all {n} requirements pass)"), "",
             f"**Recommended design: {summary['design']}** -- {macro['root_gear']} profile shift "
             f"{macro['root_profile_shift']:+.4f}, helix angle {macro['helix_angle_deg']:.3g}°. Why: {summary['why']}.",
             ""]
    lines += design_sheet_markdown(recommendation)
    lines += ["### Requirements of the recommended design (exact models; limits from the data's [requirements])", "",
              "| requirement | worst case | value | limit | unit | verdict | what it would take |",
              "|---|---|---:|---:|---|---|---|"]
    for r in summary["requirements"]:
        verdict = f"**{r['verdict']}**" + (" (fixed check)" if r.get("fixed_check") else "") \
            if r["verdict"] == "FAIL" else r["verdict"]
        others = [f for f in r["failing"] if f != r["worst_case"]]
        worst = r["worst_case"] + (f" (also: {', '.join(others)})" if others else "")
        spread = (r.get("detail") or {}).get("cycle_spread")
        if spread:
            worst += (f"; per-cycle worst over {spread['cycles']} cycles: median {eng(spread['median'])}, "
                      f"best {eng(spread['best'])}")
        lines.append(f"| {r['requirement']} | {worst} | {eng(r['value'])} | {r['sense']} {eng(r['limit'])} | "
                     f"{_unit(r['unit'])} | {verdict} | {r.get('what_it_would_take', '') if r['verdict'] == 'FAIL' else ''} |")
    lines.append("")
    lines += calibrated_verdict_lines(recommendation.get("on_calibrated_inputs"))
    cands = recommendation.get("candidates") or []
    if cands:
        lines += ["Candidates judged: " + "; ".join(
            f"{c['candidate']} {c['verdict']} ({c['failing_movable']} movable + {c['failing_fixed']} fixed failing, "
            f"largest PPTE {eng(c['largest_ppte_um'])} µm)" for c in cands) + ".", ""]
    if summary["load_basis"]:
        lines += ["Load basis: " + "; ".join(f"{k}: {v}" for k, v in summary["load_basis"].items()), ""]
    if summary["figures"]:
        lines += ["Key figures: " + " · ".join(f"[{f.rsplit('/', 1)[-1].removesuffix('.png')}]({f})"
                                              for f in summary["figures"]), ""]
    return "\n".join(lines)


def calibrated_verdict_lines(rows: list[dict] | None) -> list[str]:
    """One paragraph on the requirements judged again on the inputs calibrated to the field record: which FAILs
    remain, which were artefacts of the estimates, which are new."""
    if not rows:
        return []
    groups: dict[str, list[str]] = {}
    for r in rows:
        text = r["requirement"] if r["status"] in ("PASS", "not affected") else (
            f"{r['requirement']} ({r['worst_case_calibrated']}: {eng(r['value_calibrated'])}, was "
            f"{eng(r['value_estimates'])})")
        groups.setdefault(r["status"], []).append(text)
    order = ("FAIL remains", "FAIL remains (not affected by the calibrated inputs)",
             "FAIL was an artefact of the estimates", "new FAIL")
    parts = [f"{k}: {'; '.join(groups[k])}" for k in order if k in groups]
    return ["**On the inputs calibrated to the field record** (joint fits and friction; failure reproduction "
            "below): " + (". ".join(parts) if parts else "every requirement passes as before") + ".", ""]


def headlines_markdown(entry: dict) -> list[str]:
    """Report lines of one mesh's contact entry (``result.json["pairs"][mesh]``): the PPTE headline over the load
    range, load cases where the optimised design is worse than the unmodified one, the smooth-vs-exact gap, the tip
    relief as drawing dimensions and the verified constraint margins."""
    lines: list[str] = []
    rng = entry.get("ppte_over_range")
    if rng and "optimised" in rng["by_design"]:
        o, u = rng["by_design"]["optimised"], rng["by_design"].get("unmodified")
        text = (f"**PPTE, optimised spur: {eng(o['worst_ppte_um'])} um worst over {eng(min(rng['torques_Nm']))}-"
                f"{eng(max(rng['torques_Nm']))} N m (at {o['worst_torque_Nm']:g} N m); "
                f"{eng(o['design_torque_ppte_um'])} um at the design torque {rng['design_torque_Nm']:g} N m**")
        if u:
            text += f"; unmodified spur {eng(u['worst_ppte_um'])} um worst."
        lines += [text, ""]
        if rng["worse_than_unmodified_Nm"]:
            lines += ["**Warning:** the optimised design is worse than the unmodified one at "
                      + ", ".join(f"{t:g}" for t in rng["worse_than_unmodified_Nm"]) + " N m.", ""]
    gap = entry.get("smooth_exact_gap") or {}
    if gap.get("flagged"):
        lines += [f"**Warning:** the NLP's smooth model puts the worst PPTE at {eng(gap['smooth_worst_ppte_um'])} um, "
                  f"the exact LTCA at {eng(gap['exact_worst_ppte_um'])} um ({eng(gap['gap_percent'])} % apart, "
                  f"tolerance {eng(gap['tolerance_percent'])} %): refine the NLP's positions or smoothing.", ""]
    relief = entry.get("tip_relief_drawing") or {}
    if relief:
        lines += ["Tip relief for the drawing (linear, from the start diameter to the tip):", "",
                  "| gear | amount [um] | start diameter [mm] | relief length on the line of action [mm] | "
                  "radial height [mm] | start roll angle [deg] |", "|---|---:|---:|---:|---:|---:|"]
        for gear, d in relief.items():
            lines.append(f"| {gear.replace('_', ' ')} | {eng(d.get('amount_um', float('nan')))} | "
                         f"{d['start_diameter_mm']:.2f} | {d['relief_length_mm']:.2f} | {d['relief_height_mm']:.2f} | "
                         f"{d['start_roll_deg']:.2f} |")
        lines.append("")
    margins = entry.get("verified_margins") or {}
    if margins:
        lines += ["Constraint margins of the optimised design, exact LTCA, worst over load cases and positions:", "",
                  "| requirement | value | limit | margin | unit | worst load case [N m] | worst position (roll, gear 1) "
                  "[deg] |", "|---|---:|---:|---:|---|---:|---:|"]
        for name, m in margins.items():
            pos = "mean over cycle" if m["worst_position_roll_deg"] is None else f"{m['worst_position_roll_deg']:.1f}"
            lines.append(f"| {name} | {eng(m['value'])} | {eng(m['limit'])} | {eng(m['margin'])} | {m['unit'] or '-'} "
                         f"| {m['worst_torque_Nm']:g} | {pos} |")
        lines.append("")
    return lines


__all__ = ["build_summary", "summary_markdown", "design_sheet_markdown", "headlines_markdown", "eng", "QUICK_BANNER"]
