"""Honest contact headlines of a microgeometry design: the worst verified (exact-LTCA) PPTE over the load range
with the design-torque value beside it, the load cases where the "optimised" design is worse than the unmodified
one, the gap between the smooth model the NLP optimised and the exact LTCA, named constraint margins in their own
units aggregated per requirement (worst load case, worst position), and the tip relief as a drawing needs it.

Inputs are a :class:`~gearopt.design.microgeometry_nlp.MicrogeometryDesign` (its ``exact`` LTCA checks and its
``solve`` table); outputs are JSON-able dicts for ``result.json``.
"""

from __future__ import annotations

import logging
import math

import numpy as np
import pandas as pd

from ..contact.relief_dimensions import tip_relief_dimensions

log = logging.getLogger(__name__)

#: Largest accepted gap between the smooth-model PPTE the NLP saw and the exact LTCA, in percent of the exact worst
#: PPTE over the load range; a larger gap is flagged and logged as a warning.
SMOOTH_GAP_TOLERANCE_PERCENT = 2.0

#: Auxiliary epigraph constraints of the minimax PPTE NLP: bookkeeping, not requirements.
_AUXILIARY = ("te_below_max", "te_above_min", "ppte_below_max")

#: Constraint base name -> (requirement name with its unit, unit).
_REQUIREMENT_NAMES = {"contact_stress": ("contact_stress_MPa", "MPa"), "root_stress_1": ("root_stress_1_MPa", "MPa"),
                      "root_stress_2": ("root_stress_2_MPa", "MPa"), "loaded_contact_ratio": ("loaded_contact_ratio", ""),
                      "flash_temperature_rise": ("flash_temperature_rise_K", "K")}


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
    """Gap between the worst PPTE over the load range that the NLP's smooth LTCA model reports at its optimum and the
    worst exact-LTCA PPTE of the same design over the same load cases, in um and in percent of the exact value;
    ``flagged`` (and a logged warning) above ``tolerance_percent``.

    Only the worst load case is compared: in the minimax NLP the TE bounds of the other load cases are epigraph
    variables that need not be tight, so their smooth "PPTE" is only an upper bound."""
    values = design.solve.values
    if "te_max_um" not in values or "te_min_um" not in values or "optimised" not in design.exact:
        return {}
    smooth = np.atleast_1d(np.asarray(values["te_max_um"], float) - np.asarray(values["te_min_um"], float)).ravel()
    exact = max(float(r.ppte_um) for r in design.exact["optimised"].values())
    gap = abs(float(smooth.max()) - exact)
    percent = gap / max(exact, 1e-12) * 100.0
    flagged = percent > tolerance_percent
    if flagged:
        log.warning("smooth-model worst PPTE %.3g um differs from the exact LTCA's %.3g um by %.1f %% (tolerance "
                    "%.1f %%): refine the NLP's positions or smoothing width", smooth.max(), exact, percent,
                    tolerance_percent)
    return {"smooth_worst_ppte_um": float(smooth.max()), "exact_worst_ppte_um": exact, "gap_um": gap,
            "gap_percent": percent, "tolerance_percent": tolerance_percent, "flagged": bool(flagged)}


def nlp_constraint_margins(constraints: pd.DataFrame) -> dict[str, float]:
    """Smallest margin of every requirement of the NLP (its ``constraints`` table) over all positions and load
    cases, in the requirement's own unit: ``{"contact_stress_MPa": ..., "root_stress_1_MPa": ...,
    "loaded_contact_ratio": ..., "flash_temperature_rise_K": ...}``. Contact stress is constrained squared (MPa^2);
    its margin is returned in MPa (sqrt(limit^2) - sqrt(value))."""
    out = {}
    for base, rows in constraints.groupby("base", sort=False):
        if base in _AUXILIARY:
            continue
        name = _REQUIREMENT_NAMES.get(base, (base, ""))[0]
        if str(rows["unit"].iloc[0]) == "MPa^2":
            value = np.sqrt(np.maximum(rows["value"].to_numpy(float), 0.0))
            upper = np.sqrt(rows["upper"].to_numpy(float))
            out[name] = float(np.min(upper - value))
        else:
            out[name] = float(rows["margin"].min())
    return out


def _limits(constraints: pd.DataFrame) -> dict[str, tuple[float, float]]:
    """(lower, upper) bound of every requirement of the NLP in its own unit."""
    out = {}
    for base, rows in constraints.groupby("base", sort=False):
        if base in _AUXILIARY:
            continue
        lo, hi = float(rows["lower"].iloc[0]), float(rows["upper"].iloc[0])
        if str(rows["unit"].iloc[0]) == "MPa^2":
            hi = math.sqrt(hi) if math.isfinite(hi) else hi
        out[base] = (lo, hi)
    return out


def _worst(array: np.ndarray, roll_deg: np.ndarray) -> tuple[float, float]:
    idx = np.unravel_index(int(np.argmax(array)), array.shape)
    return float(array[idx]), float(roll_deg[idx[0]])


def verified_margins(design, which: str = "optimised") -> dict[str, dict]:
    """Margins of ``which`` design's exact LTCA at every load case against the NLP's limits, one entry per
    requirement in its own unit: ``{"margin", "value", "limit", "unit", "worst_torque_Nm", "worst_position_roll_deg"}``
    (the position as the roll angle of gear 1's contact point at the worst mesh position; ``None`` for the loaded
    contact ratio, a mean over the cycle). The limit is the requirement's (``design.limits``), not the NLP's bound
    the refinement may have tightened. Negative margin: the exact LTCA violates the requirement."""
    limits = _limits(design.solve.constraints)
    runs = design.exact[which]
    out: dict[str, dict] = {}
    required = getattr(design, "limits", {}) or {}     # the requirements' limits; the NLP may carry them tightened

    def upper(name):
        return required.get(name, limits[name][1])

    def keep(name, unit, value, limit, margin, torque, roll):
        prev = out.get(name)
        if prev is None or margin < prev["margin"]:
            out[name] = {"margin": float(margin), "value": float(value), "limit": float(limit), "unit": unit,
                         "worst_torque_Nm": float(torque), "worst_position_roll_deg": roll}

    for torque, r in runs.items():
        roll = np.asarray(r.position_roll_deg, float)
        if "contact_stress" in limits:
            v, at = _worst(np.asarray(r.contact_stress_MPa), roll)
            keep("contact_stress_MPa", "MPa", v, upper("contact_stress"), upper("contact_stress") - v, torque, at)
        for g in (1, 2):
            if f"root_stress_{g}" in limits:
                v, at = _worst(np.asarray(r.root_stress_MPa[g - 1]), roll)
                lim = required.get("root_stress", limits[f"root_stress_{g}"][1])
                keep(f"root_stress_{g}_MPa", "MPa", v, lim, lim - v, torque, at)
        if "flash_temperature_rise" in limits and r.speed_rpm is not None:
            v, at = _worst(np.asarray(r.flash_temperature_rise_K), roll)
            lim = limits["flash_temperature_rise"][1]
            keep("flash_temperature_rise_K", "K", v, lim, lim - v, torque, at)
        if "loaded_contact_ratio" in limits:
            v = r.loaded_contact_ratio
            lim = required.get("loaded_contact_ratio", limits["loaded_contact_ratio"][0])
            keep("loaded_contact_ratio", "", v, lim, v - lim, torque, None)
    return out


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
