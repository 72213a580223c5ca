"""Honest contact headlines of a microgeometry design: the worst verified (exact-LTCA) PPTE over the load range
with the design-torque value beside it, the load cases where the "optimised" design is worse than the unmodified
one, the gap between the smooth model the NLP optimised and the exact LTCA, named constraint margins in their own
units aggregated per requirement (worst load case, worst position), and the tip relief as a drawing needs it.

Inputs are a :class:`~gearopt.design.microgeometry_nlp.MicrogeometryDesign` (its ``exact`` LTCA checks, its
``limits`` and its scene's quantities); outputs are JSON-able dicts for ``result.json``.
"""

from __future__ import annotations

import logging

import numpy as np
import pandas as pd

from ..contact.relief_dimensions import tip_relief_dimensions

log = logging.getLogger(__name__)

#: Largest accepted gap between the smooth-model PPTE the NLP saw and the exact LTCA, in percent of the exact worst
#: PPTE over the load range; a larger gap is flagged and logged as a warning.
SMOOTH_GAP_TOLERANCE_PERCENT = 2.0

#: Limit quantity of the design's scene -> requirement name with its unit.
_REQUIREMENT_NAMES = {"max_contact_stress_MPa": "contact_stress_MPa", "loaded_contact_ratio": "loaded_contact_ratio",
                      "max_root_stress_MPa": "root_stress_MPa", "max_contact_temperature_C": "contact_temperature_C"}


def ppte_over_range(design) -> dict:
    """PPTE of every design the microgeometry study checked (exact LTCA) at every load case, the worst over the range
    and the design-torque value, plus the load cases where ``optimised`` is worse than ``unmodified``.

    Returns ``{"design_torque_Nm", "torques_Nm", "by_design": {name: {"ppte_um_by_torque": {T: um},
    "worst_ppte_um", "worst_torque_Nm", "design_torque_ppte_um"}}, "worse_than_unmodified_Nm": [T...]}``."""
    torques = [float(t) for t in design.torques_Nm]
    out = {"design_torque_Nm": torques[0], "torques_Nm": sorted(torques), "by_design": {}}
    for name, runs in design.exact.items():
        by_t = {float(t): float(r.ppte_um) for t, r in sorted(runs.items())}
        worst_t = max(by_t, key=by_t.get)
        out["by_design"][name] = {"ppte_um_by_torque": {f"{t:g}": v for t, v in by_t.items()},
                                  "worst_ppte_um": by_t[worst_t], "worst_torque_Nm": worst_t,
                                  "design_torque_ppte_um": by_t.get(torques[0], float("nan"))}
    worse = []
    if "optimised" in design.exact and "unmodified" in design.exact:
        opt, base = design.exact["optimised"], design.exact["unmodified"]
        worse = [float(t) for t in sorted(opt) if t in base and opt[t].ppte_um > base[t].ppte_um]
    out["worse_than_unmodified_Nm"] = worse
    return out


def smooth_exact_gap(design, tolerance_percent: float = SMOOTH_GAP_TOLERANCE_PERCENT) -> dict:
    """Gap between the worst PPTE over the load range that the NLP's smooth LTCA model gives at the optimum (the
    scene's quantities: the true peak-to-peak at its positions) and the exact LTCA's worst over the range, in um and
    percent of the exact value; ``flagged`` (and a logged warning) above ``tolerance_percent``. ``{}`` for a design
    without its scene or exact check."""
    q = _quantities(design)
    if q is None or "optimised" not in design.exact:
        return {}
    rows = q[(q["quantity"] == "ppte_um") & (q["role"] == "objective")]
    if rows.empty:
        return {}
    smooth = float(rows["value"].max())
    exact = max(float(r.ppte_um) for r in design.exact["optimised"].values())
    gap = abs(smooth - exact)
    percent = gap / max(exact, 1e-12) * 100.0
    flagged = percent > tolerance_percent
    if flagged:
        log.warning("smooth-model worst PPTE %.3g um differs from the exact LTCA's %.3g um by %.1f %% (tolerance "
                    "%.1f %%): refine the NLP's positions or smoothing width", smooth, exact, percent,
                    tolerance_percent)
    return {"smooth_worst_ppte_um": smooth, "exact_worst_ppte_um": exact, "gap_um": gap,
            "gap_percent": percent, "tolerance_percent": tolerance_percent, "flagged": bool(flagged)}


def nlp_constraint_margins(design) -> dict[str, float]:
    """Smallest margin of every limit of the design's NLP on its smooth model at the optimum, over all load cases
    (the scene's quantities: true maxima at its positions), in the requirement's own unit:
    ``{"contact_stress_MPa": ..., "loaded_contact_ratio": ..., "root_stress_MPa": ..., "contact_temperature_C": ...}``
    (``{}`` for a design without its scene). The exact values are :func:`verified_margins`."""
    q = _quantities(design)
    if q is None:
        return {}
    rows = q[q["role"] == "limit"]
    return {_REQUIREMENT_NAMES.get(name, name): float(group["margin"].min())
            for name, group in rows.groupby("quantity", sort=False)}


def _quantities(design) -> pd.DataFrame | None:
    scene = getattr(design, "scene", None)
    return None if scene is None else scene.quantities


def verified_margins(design, which: str = "optimised") -> dict[str, dict]:
    """Margins of ``which`` design's exact LTCA at every load case against the requirements' limits
    (``design.limits``), one entry per requirement in its own unit: ``{"margin", "value", "limit", "unit",
    "worst_torque_Nm", "worst_position_roll_deg"}`` (the position as the roll angle of gear 1's contact point at the
    worst mesh position; ``None`` for the loaded contact ratio, a mean over the cycle). Negative margin: the exact
    LTCA violates the requirement."""
    runs = design.exact[which]
    limits = getattr(design, "limits", {}) or {}
    out: dict[str, dict] = {}

    def keep(name, unit, value, limit, margin, torque, roll):
        prev = out.get(name)
        if prev is None or margin < prev["margin"]:
            out[name] = {"margin": float(margin), "value": float(value), "limit": float(limit), "unit": unit,
                         "worst_torque_Nm": float(torque), "worst_position_roll_deg": roll}

    for torque, r in runs.items():
        roll = np.asarray(r.position_roll_deg, float)
        if "contact_stress" in limits:
            v, at = _worst(np.asarray(r.contact_stress_MPa), roll)
            keep("contact_stress_MPa", "MPa", v, limits["contact_stress"], limits["contact_stress"] - v, torque, at)
        if "root_stress" in limits:
            for g in (1, 2):
                v, at = _worst(np.asarray(r.root_stress_MPa[g - 1]), roll)
                keep(f"root_stress_{g}_MPa", "MPa", v, limits["root_stress"], limits["root_stress"] - v, torque, at)
        if "flash_temperature" in limits and r.speed_rpm is not None:
            v, at = _worst(np.asarray(r.flash_temperature_rise_K), roll)
            v += float(r.bulk_temperature_C)
            keep("contact_temperature_C", "C", v, limits["flash_temperature"], limits["flash_temperature"] - v,
                 torque, at)
        if "loaded_contact_ratio" in limits:
            v = r.loaded_contact_ratio
            lim = limits["loaded_contact_ratio"]
            keep("loaded_contact_ratio", "", v, lim, v - lim, torque, None)
    return out


def _worst(array: np.ndarray, roll_deg: np.ndarray) -> tuple[float, float]:
    idx = np.unravel_index(int(np.argmax(array)), array.shape)
    return float(array[idx]), float(roll_deg[idx[0]])


def tip_relief_drawing(pair, values: dict) -> dict[str, dict]:
    """The optimised tip relief of each gear as a drawing needs it (start diameter, relief length along the line of
    action, radial height, amount), from the NLP's ``values`` (``tip_relief_{g}_um``,
    ``tip_relief_{g}_start_roll_deg``); gears without a tip-relief start are left out."""
    out = {}
    for g in (1, 2):
        start = values.get(f"tip_relief_{g}_start_roll_deg")
        if start is None:
            continue
        out[f"gear_{g}"] = tip_relief_dimensions(pair, g, float(start), values.get(f"tip_relief_{g}_um"))
    return out


__all__ = ["ppte_over_range", "smooth_exact_gap", "nlp_constraint_margins", "verified_margins",
           "tip_relief_drawing", "SMOOTH_GAP_TOLERANCE_PERCENT"]
