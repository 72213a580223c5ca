"""Verdict first: the one-screen summary of a design study, built from its JSON-able result dict.

Each requirement is one row: the worst value over its instances (joints, meshes, speeds, load cases), the limit,
the unit and PASS/FAIL, with the worst case named and every failing instance listed. The same rows go to
``result.json["summary"]`` (numbers at engineering precision, three significant figures) and to the top of
``report.md`` (:func:`summary_markdown`).

The result dict is the one ``problems/cam_gear_walkoff.py`` writes; a requirement whose inputs are absent (a stage
not run) is left out, and the summary says which were left out.
"""

from __future__ import annotations

import math
from typing import Any, Iterable

from ...report.tables import eng

#: Default limits of the requirements (overridden by the caller, e.g. from the data's ``[design_limits]``).
#: ISO 6336-2/-3 leave the minimum safety factors to the user; S_H >= 1.0 and S_F >= 1.4 are conventional minima for
#: gears of normal reliability (a bending failure is worse than pitting). Slip, walk-off and hub yield margins below 1
#: mean the joint slips, walks or yields.
DEFAULT_LIMITS = {"min_slip_margin": 1.0, "min_axial_margin": 1.0, "min_hub_yield_safety": 1.0, "min_S_H": 1.0,
                  "min_S_F": 1.4, "max_contact_temperature_C": 150.0, "min_contact_ratio": 1.2,
                  "min_loaded_contact_ratio": 1.2}


def _round(value: Any, digits: int = 3) -> Any:
    if isinstance(value, str) or value is None:
        return value
    v = float(value)
    if not math.isfinite(v):
        return "inf" if v > 0 else ("-inf" if v < 0 else "nan")
    return float(eng(v, digits)) if v != 0.0 else 0.0


def _num(value: Any) -> float:
    return float("inf") if value == "inf" else float(value)


def requirement(name: str, instances: Iterable[tuple[str, Any]], limit: float, unit: str, sense: str,
                basis: str) -> dict | None:
    """One requirement row from ``(instance label, value)`` pairs: the worst value (smallest for ``sense`` ``">="``,
    largest for ``"<="``), its instance, PASS/FAIL against ``limit`` and every failing instance."""
    items = [(label, _num(v)) for label, v in instances if v is not None]
    if not items:
        return None
    pick = min if sense == ">=" else max
    worst_label, worst = pick(items, key=lambda kv: kv[1])
    ok = (lambda v: v >= limit) if sense == ">=" else (lambda v: v <= limit)
    failing = [label for label, v in items if not ok(v)]
    return {"requirement": name, "value": _round(worst), "limit": _round(limit), "sense": sense, "unit": unit,
            "verdict": "PASS" if not failing else "FAIL", "worst_case": worst_label, "failing": failing,
            "basis": basis}


def cycle_spread(over_speed: dict, train: str, label: str, key: str) -> dict | None:
    """The per-cycle spread of the worst instance ``label`` ("<joint> at <speed> rpm") of a margin over speed: the
    number of recorded cycles and the worst, median and best of the per-cycle worst margins (None when the sweep
    did not record them)."""
    joint, _, speed = label.partition(" at ")
    for e in over_speed.get(joint, {}).get(train, []):
        if f"{e['speed_rpm']:g} rpm" == speed and f"{key}_cycle_median" in e:
            return {"cycles": e.get("cycles"), **{s: _round(e[f"{key}_cycle_{s}"]) for s in ("worst", "median",
                                                                                                  "best")}}
    return None


def build_summary(result: dict, *, train: str = "spur", limits: dict | None = None,
                  load_basis: dict | None = None, figures: Iterable[str] = ()) -> dict:
    """The summary of ``result`` (the main job's result dict) for the design ``train`` (``"spur"``, the redesign):
    ``{"verdict", "failed", "requirements": [...], "ppte_headlines": {...}, "load_basis", "figures", "left_out"}``."""
    lim = {**DEFAULT_LIMITS, **(limits or {})}
    rows: list[dict | None] = []
    left_out: list[str] = []

    over_speed = (result.get("dynamics") or {}).get("joint_margins_over_speed") or {}
    if over_speed:
        def by_speed(key):
            return [(f"{j} at {e['speed_rpm']:g} rpm", e[key]) for j, kinds in over_speed.items()
                    for e in kinds.get(train, [])]
        for name, key, limit, basis in (
                ("Joint slip margin over speed (dynamic peak, with backlash)", "torque_margin", "min_slip_margin",
                 "capacity / peak joint torque of the speed sweep"),
                ("Walk-off (axial) margin over speed", "axial_margin", "min_axial_margin",
                 "axial capacity / peak thrust of the speed sweep")):
            row = requirement(name, by_speed(key), lim[limit], "-", ">=", basis)
            rows.append(row)
            if row is not None:
                row["cycle_spread"] = cycle_spread(over_speed, train, row["worst_case"], key)
    else:
        left_out.append("joint margins over speed (no dynamics stage)")
    joints = result.get("joints") or {}
    if joints:
        weakest = [(g, k[train]["weakest"]["torque_margin"]) for g, k in joints.items() if train in k]
        rows.append(requirement("Joint slip margin at design load, weakest fit", weakest, lim["min_slip_margin"], "-",
                                ">=", "min interference, DIN 7190 smoothing, max nut factor; static design torque"))
        yield_ = [(g, k[train]["nominal"].get("hub_yield_safety")) for g, k in joints.items() if train in k]
        rows.append(requirement("Hub yield safety (nominal fit)", yield_, lim["min_hub_yield_safety"], "-", ">=",
                                "hub yield strength / von Mises stress at the bore"))
    else:
        left_out.append("joints at the design load")
    computed = (result.get("rating") or {}).get(f"{train}_computed_factors") or {}
    rating = (result.get("rating") or {}).get(train) or {}
    if computed:  # every load factor computed (rate_iso6336): the rating an engineer would sign
        rows.append(requirement("Contact safety S_H (ISO 6336-2, computed factors)",
                                [(f"{m} gear {g}", r[f"S_H_{g}"]) for m, r in computed.items() for g in (1, 2)],
                                lim["min_S_H"], "-", ">=", "see load basis"))
        rows.append(requirement("Root safety S_F (ISO 6336-3, computed factors)",
                                [(f"{m} gear {g}", r[f"S_F_{g}"]) for m, r in computed.items() for g in (1, 2)],
                                lim["min_S_F"], "-", ">=", "see load basis"))
    elif rating:
        rows.append(requirement("Contact safety S_H (ISO 6336-2 method B)", [(m, r["S_H"]) for m, r in rating.items()],
                                lim["min_S_H"], "-", ">=", "see load basis"))
        rows.append(requirement("Root safety S_F (ISO 6336-3 method B)",
                                [(f"{m} gear {g}", r[f"S_F_{g}"]) for m, r in rating.items() for g in (1, 2)],
                                lim["min_S_F"], "-", ">=", "see load basis"))
    else:
        left_out.append("ISO 6336 rating")
    dynamic = (result.get("rating") or {}).get(f"{train}_dynamic_peak") or {}
    if dynamic:  # the loads that occur: the largest dynamic mesh torque with backlash, K_A = K_v = 1
        basis = "largest dynamic mesh torque with backlash, K_A = K_v = 1, endurance"
        rows.append(requirement("Contact safety S_H at the dynamic peak torque",
                                [(f"{m} gear {g}", r[f"S_H_{g}"]) for m, r in dynamic.items() for g in (1, 2)],
                                lim["min_S_H"], "-", ">=", basis))
        rows.append(requirement("Root safety S_F at the dynamic peak torque",
                                [(f"{m} gear {g}", r[f"S_F_{g}"]) for m, r in dynamic.items() for g in (1, 2)],
                                lim["min_S_F"], "-", ">=", basis))
    pairs = result.get("pairs") or {}
    design = f"{train}_optimised"
    if pairs:
        temps = [(m, p["max_flash_temperature_C"].get(design)) for m, p in pairs.items()
                 if "max_flash_temperature_C" in p]
        rows.append(requirement("Contact temperature (bulk + Blok flash), optimised flanks", temps,
                                lim["max_contact_temperature_C"], "C", "<=", "exact LTCA at the design torque"))
        lcr = [(f"{m} at {p['verified_margins']['loaded_contact_ratio']['worst_torque_Nm']:g} N m",
                p["verified_margins"]["loaded_contact_ratio"]["value"]) for m, p in pairs.items()
               if "loaded_contact_ratio" in p.get("verified_margins", {})]
        rows.append(requirement("Loaded contact ratio over the load range, optimised flanks", lcr,
                                lim["min_loaded_contact_ratio"], "-", ">=", "exact LTCA at every load case"))
    else:
        left_out.append("contact temperature, loaded contact ratio and PPTE (no contact study)")
    meshes = (result.get("meshes") or {}).get(train) or {}
    if meshes:
        rows.append(requirement("Worst-case transverse contact ratio (tolerances)",
                                [(m, g["worst_case_transverse_contact_ratio"]) for m, g in meshes.items()],
                                lim["min_contact_ratio"], "-", ">=", "max centre distance, thinnest teeth"))
    headlines = {}
    for mesh, p in pairs.items():
        rng = p.get("ppte_over_range")
        if not rng:
            continue
        opt, base = rng["by_design"].get("optimised"), rng["by_design"].get("unmodified")
        if not opt or not base:
            continue
        worse = rng.get("worse_than_unmodified_Nm", [])
        row = requirement(f"PPTE over {eng(min(rng['torques_Nm']))}-{eng(max(rng['torques_Nm']))} N m, {mesh}",
                          [(f"at {opt['worst_torque_Nm']:g} N m", opt["worst_ppte_um"])], base["worst_ppte_um"],
                          "um", "<=", "worst exact-LTCA PPTE, optimised vs unmodified spur (limit)")
        if worse:
            row["verdict"] = "FAIL"
            row["failing"] = [f"worse than unmodified at {t:g} N m" for t in worse]
        rows.append(row)
        headlines[mesh] = {"worst_ppte_um": _round(opt["worst_ppte_um"]), "worst_torque_Nm": opt["worst_torque_Nm"],
                           "design_torque_ppte_um": _round(opt["design_torque_ppte_um"]),
                           "design_torque_Nm": rng["design_torque_Nm"],
                           "unmodified_worst_ppte_um": _round(base["worst_ppte_um"]),
                           "worse_than_unmodified_Nm": worse,
                           "smooth_exact_gap_percent": _round(p.get("smooth_exact_gap", {}).get("gap_percent")),
                           "smooth_exact_gap_flagged": p.get("smooth_exact_gap", {}).get("flagged")}
        if "helical" in p.get("ppte_um", {}):
            headlines[mesh]["helical_design_torque_ppte_um"] = _round(p["ppte_um"]["helical"])
    reqs = [r for r in rows if r is not None]
    failed = [r["requirement"] for r in reqs if r["verdict"] == "FAIL"]
    return {"train": train, "verdict": "FAIL" if failed else "PASS", "failed": failed, "requirements": reqs,
            "ppte_headlines": headlines, "load_basis": dict(load_basis or {}), "figures": list(figures),
            "left_out": left_out}


def summary_markdown(summary: dict, title: str = "Summary") -> str:
    """The summary as Markdown: verdict line, requirement table, PPTE headlines, load basis, key figures."""
    n_fail = len(summary["failed"])
    lines = [f"## {title}: {summary['verdict']}"
             + (f" ({n_fail} of {len(summary['requirements'])} requirements fail)" if n_fail else ""), "",
             f"Design: the {summary['train']} train. Worst case over every joint, mesh, speed and load case; "
             "limits from the data's design limits or the defaults of `gearopt.report.summary`.", "",
             "| requirement | worst case | value | limit | unit | verdict |", "|---|---|---:|---:|---|---|"]
    for r in summary["requirements"]:
        verdict = f"**{r['verdict']}**" if r["verdict"] == "FAIL" else r["verdict"]
        others = [f for f in r["failing"] if f != r["worst_case"]]
        also = "also fails" if r["worst_case"] in r["failing"] else "fails"
        worst = r["worst_case"] + (f" ({also}: {', '.join(others)})" if others else "")
        spread = r.get("cycle_spread")
        if spread and spread.get("cycles", 1) > 1:
            worst += (f"; per-cycle worst over {spread['cycles']} cycles: median {eng(spread['median'])}, "
                      f"best {eng(spread['best'])}")
        lines.append(f"| {r['requirement']} | {worst} | {eng(r['value'])} | {r['sense']} {eng(r['limit'])} | "
                     f"{r['unit']} | {verdict} |")
    lines.append("")
    if summary["ppte_headlines"]:
        lines += ["PPTE headlines (exact LTCA; worst over the load range, design-torque value beside it):", ""]
        for mesh, h in summary["ppte_headlines"].items():
            text = (f"- {mesh}: optimised spur {eng(h['worst_ppte_um'])} um worst (at {h['worst_torque_Nm']:g} N m), "
                    f"{eng(h['design_torque_ppte_um'])} um at the design torque {h['design_torque_Nm']:g} N m; "
                    f"unmodified spur {eng(h['unmodified_worst_ppte_um'])} um worst")
            if "helical_design_torque_ppte_um" in h:
                text += f"; helical {eng(h['helical_design_torque_ppte_um'])} um at the design torque"
            if h["worse_than_unmodified_Nm"]:
                text += (" -- **worse than unmodified at " + ", ".join(f"{t:g}" for t in h["worse_than_unmodified_Nm"])
                         + " N m**")
            if h.get("smooth_exact_gap_flagged"):
                text += f" -- smooth model off the exact LTCA by {eng(h['smooth_exact_gap_percent'])} % (> 2 %)"
            lines.append(text)
        lines.append("")
    if summary["load_basis"]:
        lines += ["Load basis: " + "; ".join(f"{k}: {v}" for k, v in summary["load_basis"].items()), ""]
    if summary["left_out"]:
        lines += ["Not checked: " + "; ".join(summary["left_out"]), ""]
    if summary["figures"]:
        lines += ["Key figures: " + " · ".join(f"[{f.rsplit('/', 1)[-1].removesuffix('.png')}]({f})"
                                              for f in summary["figures"]), ""]
    return "\n".join(lines)


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


__all__ = ["build_summary", "summary_markdown", "headlines_markdown", "requirement", "eng", "DEFAULT_LIMITS"]
