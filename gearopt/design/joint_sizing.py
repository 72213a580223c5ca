"""Sizing of one shaft-hub joint for a target slip margin: Ipopt NLPs (through :class:`~gearopt.design.Problem`)
over the press-fit interference (and optionally fit length and hub outer diameter) or the taper-fit nut torque.

Press fit (:func:`size_press_fit`; model :func:`gearopt.joints.press_fit.press_fit`, Lame/DIN 7190 elastic):

* variable ``interference_um``: the *nominal* diametral interference, the middle of a tolerance band of width
  ``tolerance_band_um`` (default the H7/x6 band IT7 + IT6 at the fit diameter, or the data's present fit band);
  optionally ``length_mm`` and ``hub_outer_diameter_mm`` within bounds;
* weakest case, for the capacity: interference ``nominal - band/2`` minus the DIN 7190 smoothing loss (data Rz,
  ``smoothing_rule``) minus the centrifugal loss at each demand's speed; the friction force ``mu p pi d l`` must hold
  ``target_margin`` times the demand. ``slip="combined"`` (default) imposes the friction-force resultant
  ``F_cap >= S sqrt((2000 T/d)^2 + F_a^2)`` (it implies both single margins >= S); ``slip="separate"`` imposes
  ``T_cap >= S |T|`` and ``F_cap >= S |F_a|`` (torque slip and axial walk-off margins) each on its own;
* strongest case, for the stresses: interference ``nominal + band/2`` minus the smoothing loss, at rest and at each
  demand's speed (the centrifugal hoop stress adds there while the pressure drops); the hub and shaft von Mises
  stresses at the fit must stay below ``yield / min_*_yield_safety``;
* objective ``"min_interference"`` (default: the lightest fit that meets the margin) or ``"max_margin"`` (the largest
  common margin the stress limits allow, a free margin variable >= ``target_margin``).

The nominal interference is kept above ``band/2 + smoothing + largest centrifugal loss`` (a variable bound), so the
weakest effective interference stays positive and the model's ``max(delta, 0)`` never switches inside the NLP.

Taper fit (:func:`size_taper_fit`; model :func:`gearopt.joints.taper_fit.taper_fit`, thesis Eqs. 3.48-3.49): variable
nut tightening torque; weakest case at the *largest* nut factor of the range (lowest preload W = T_n/(k d)),
strongest at the smallest. Capacity ``"thesis"`` (thesis Eq. 3.48, W = N sin(theta)) or ``"engagement_friction"``
(locked-in normal force reduced by the engagement friction, see :mod:`gearopt.joints.taper_fit`). Slip:
``combined`` = ``S (|T|/T_cap + |F_a|/W) <= 1`` (rigid cone-clutch model, axial load taken as pulling off the
taper), or ``separate`` torque and axial margins. Hub von Mises safety at the strongest preload; thread stress
``W_max / A_s <= max_proof_fraction x proof strength`` when the proof strength is given.

Every result is re-evaluated with the numeric joint models (:func:`press_fit_sizing_margins`,
:func:`taper_fit_sizing_margins`), and for press fits the ISO 286 hole-basis fits (H6/x5, H7/x6, H8/x7 with shafts
m..u, :func:`gearopt.joints.iso286.fit_interference_um`) whose whole band lies between the required minimum and the
allowed maximum interference are listed (:func:`suggest_fit`).

Units: mm, um (diametral interference), N, N m, MPa, rpm.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np
import pandas as pd

from ..data import System, joint_record, system_of
from ..errors import GearoptInputError
from ..validation import check_range
from ..joints.iso286 import fit_interference_um
from ..joints.press_fit import centrifugal_interference_loss_um
from ..nlp.problem import Problem
from .joint_specs import (_INTERFERENCE_FLOOR_UM, _as_demands, FIT_GRADES, JointSizing, SHAFT_LETTERS, SLIP_CRITERIA,
                          TAPER_CAPACITIES, PRESS_FIT_OBJECTIVES, press_fit_sizing_margins, smoothing_loss_of,
                          taper_fit_sizing_margins)
from .joint_specs import (JointDemand, PressFitSpec, TaperFitSpec,  # noqa: F401 (re-exported: the sizing API)
                          default_tolerance_band_um)

# ----------------------------------------------------------------------------------------------------------------
# press fit
# ----------------------------------------------------------------------------------------------------------------

def size_press_fit(spec: PressFitSpec, demands: JointDemand | Sequence[JointDemand], *, target_margin: float = 1.5,
                   slip: str = "combined", min_hub_yield_safety: float = 1.2, min_shaft_yield_safety: float = 1.2,
                   tolerance_band_um: float | None = None, smoothing: bool = True,
                   smoothing_rule: str = "din7190_2001", free: Sequence[str] = ("interference_um",),
                   bounds: dict | None = None, objective: str = "min_interference", verbose: bool = False,
                   **ipopt: Any) -> JointSizing:
    """Size a press fit for ``target_margin`` at every demand (module docstring: weakest/strongest cases).

    Args:
        spec: the joint (:meth:`PressFitSpec.from_data` for a data entry).
        demands: one or several :class:`JointDemand` (all are imposed).
        target_margin: required slip margin S (>= 1).
        slip: ``"combined"`` (friction-force resultant) or ``"separate"`` (torque and axial margins).
        min_hub_yield_safety, min_shaft_yield_safety: von Mises yield safeties at the largest interference.
        tolerance_band_um: interference band width [um]; default the spec's present band, else IT7 + IT6.
        smoothing: apply the DIN 7190 smoothing loss of the spec's roughness (``smoothing_rule``).
        free: variables: ``"interference_um"`` always, plus optionally ``"length_mm"``,
            ``"hub_outer_diameter_mm"``.
        bounds: {variable: (low, high)}; defaults: interference up to 400 um (its lower bound is always at least
            half the band + smoothing + centrifugal loss), length 0.5-1.5 x the spec's, hub outer diameter
            max(1.2 d, 0.8 x the spec's) to 1.5 x the spec's.
        objective: ``"min_interference"`` or ``"max_margin"``.
        ipopt: Ipopt options for :meth:`Problem.solve`.

    Raises:
        GearoptInputError: bad arguments. InfeasibleProblemError (a SolveError): no design meets the margin within
            the stress limits and bounds; the error names the violated constraints.
    """
    demands = _as_demands(demands)
    check_range("target_margin", target_margin, 1.0, 100.0)
    check_range("min_hub_yield_safety", min_hub_yield_safety, 0.5, 10.0)
    check_range("min_shaft_yield_safety", min_shaft_yield_safety, 0.5, 10.0)
    if slip not in SLIP_CRITERIA:
        raise GearoptInputError(f"slip={slip!r} must be one of {SLIP_CRITERIA}")
    if objective not in PRESS_FIT_OBJECTIVES:
        raise GearoptInputError(f"objective={objective!r} must be one of {PRESS_FIT_OBJECTIVES}")
    free = tuple(free)
    allowed = ("interference_um", "length_mm", "hub_outer_diameter_mm")
    if "interference_um" not in free or set(free) - set(allowed):
        raise GearoptInputError(f"free={free!r} must contain 'interference_um' and only names of {allowed}")
    band = spec.present_band_um if tolerance_band_um is None else float(tolerance_band_um)
    if band is None:
        band = default_tolerance_band_um(spec.shaft_diameter_mm)
    check_range("tolerance_band_um", band, 0.0, 500.0, unit="um")
    loss = smoothing_loss_of(spec, smoothing, smoothing_rule)
    d = float(spec.shaft_diameter_mm)
    bnd = {"interference_um": (None, 400.0), "length_mm": (0.5 * spec.length_mm, 1.5 * spec.length_mm),
           "hub_outer_diameter_mm": (max(1.2 * d, spec.hub_outer_diameter_mm * 0.8), 1.5 * spec.hub_outer_diameter_mm)}
    for key, val in (bounds or {}).items():
        if key not in allowed:
            raise GearoptInputError(f"bounds key {key!r} must be one of {allowed}")
        lo, hi = val
        if lo is not None and hi is not None and hi <= lo:
            raise GearoptInputError(f"bounds[{key!r}]=({lo}, {hi}): upper must exceed lower")
        bnd[key] = (lo, hi)
    if bnd["hub_outer_diameter_mm"][0] is not None and bnd["hub_outer_diameter_mm"][0] <= d:
        raise GearoptInputError(f"bounds['hub_outer_diameter_mm'] lower={bnd['hub_outer_diameter_mm'][0]:g} mm must "
                                f"exceed the shaft diameter {d:g} mm")
    # keep the weakest effective interference positive over the whole box (largest centrifugal loss at the largest
    # hub diameter): the model's max(delta, 0) then never switches inside the NLP
    do_max = bnd["hub_outer_diameter_mm"][1] if "hub_outer_diameter_mm" in free else spec.hub_outer_diameter_mm
    cf = max(float(centrifugal_interference_loss_um(x.speed_rpm, d, spec.shaft_bore_mm, do_max, spec.shaft_E_MPa,
                                                    spec.shaft_nu, spec.hub_E_MPa, spec.hub_nu,
                                                    spec.shaft_density_kg_m3, spec.hub_density_kg_m3))
             for x in demands)
    floor = 0.5 * band + loss + max(cf, 0.0) + _INTERFERENCE_FLOOR_UM
    lo_i = floor if bnd["interference_um"][0] is None else max(floor, bnd["interference_um"][0])
    hi_i = bnd["interference_um"][1]
    if hi_i is not None and hi_i <= lo_i:
        raise GearoptInputError(f"interference upper bound {hi_i:g} um must exceed {lo_i:g} um (half band + "
                                f"smoothing + centrifugal loss)")

    p = Problem(name=f"press-fit sizing {spec.name}")
    x0_len = spec.length_mm
    length = (p.variable("length_mm", init=x0_len, lower=bnd["length_mm"][0], upper=bnd["length_mm"][1],
                         scale=x0_len, unit="mm") if "length_mm" in free else None)
    x0_do = spec.hub_outer_diameter_mm
    hub_do = (p.variable("hub_outer_diameter_mm", init=x0_do, lower=bnd["hub_outer_diameter_mm"][0],
                         upper=bnd["hub_outer_diameter_mm"][1], scale=x0_do, unit="mm")
              if "hub_outer_diameter_mm" in free else None)
    init = max(lo_i + 10.0, spec.interference_um or 0.0)
    if hi_i is not None:
        init = min(init, 0.5 * (lo_i + hi_i))
    delta = p.variable("interference_um", init=init, lower=lo_i, upper=hi_i, scale=max(init, 10.0), unit="um")
    margin = None
    if objective == "max_margin":
        margin = p.variable("margin", init=target_margin, lower=target_margin, upper=100.0, scale=target_margin)
    S = target_margin if margin is None else margin
    for x in demands:
        e = press_fit_sizing_margins(spec, delta, x, length_mm=length, hub_outer_diameter_mm=hub_do,
                                     tolerance_band_um=band, smoothing=smoothing, smoothing_rule=smoothing_rule)
        T, Fa = abs(float(x.torque_Nm)), abs(float(x.axial_force_N))
        tag = x.name
        if slip == "combined":
            req = e["required_friction_force_N"]
            p.subject_to(f"{tag}:slip_reserve_N", e["axial_capacity_N"] - S * req, lower=0.0, scale=req, unit="N")
        else:
            if T > 0.0:
                p.subject_to(f"{tag}:torque_reserve_Nm", e["torque_capacity_Nm"] - S * T, lower=0.0, scale=T,
                             unit="N m")
            if Fa > 0.0:
                p.subject_to(f"{tag}:axial_reserve_N", e["axial_capacity_N"] - S * Fa, lower=0.0, scale=Fa,
                             unit="N")
        hub_lim = spec.hub_yield_MPa / min_hub_yield_safety
        shaft_lim = spec.shaft_yield_MPa / min_shaft_yield_safety
        for case in ("rest", "speed"):
            if case == "speed" and x.speed_rpm == 0.0:
                continue
            p.subject_to(f"{tag}:hub_von_mises_{case}_MPa", e[f"hub_von_mises_{case}_MPa"], upper=hub_lim,
                         scale=hub_lim, unit="MPa")
            p.subject_to(f"{tag}:shaft_von_mises_{case}_MPa", e[f"shaft_von_mises_{case}_MPa"], upper=shaft_lim,
                         scale=shaft_lim, unit="MPa")
    if margin is None:
        p.minimize(delta, scale=max(init, 10.0))
    else:
        p.maximize(margin, scale=target_margin)
    res = p.solve(verbose=verbose, **ipopt)

    vals = {"interference_um": float(res.values["interference_um"]),
            "length_mm": float(res.values.get("length_mm", spec.length_mm)),
            "hub_outer_diameter_mm": float(res.values.get("hub_outer_diameter_mm", spec.hub_outer_diameter_mm)),
            "tolerance_band_um": band, "smoothing_loss_um": loss}
    if margin is not None:
        vals["margin"] = float(res.values["margin"])
    vals["interference_min_um"] = vals["interference_um"] - 0.5 * band
    vals["interference_max_um"] = vals["interference_um"] + 0.5 * band
    opts = dict(length_mm=vals["length_mm"], hub_outer_diameter_mm=vals["hub_outer_diameter_mm"],
                smoothing=smoothing, smoothing_rule=smoothing_rule)
    required_min = _required_min_interference_um(spec, demands, target_margin, slip, opts)
    allowed_max = _allowed_max_interference_um(spec, demands, min_hub_yield_safety, min_shaft_yield_safety, opts)
    vals["required_min_interference_um"] = required_min
    vals["allowed_max_interference_um"] = allowed_max
    margins = press_fit_margin_table(spec, vals["interference_um"], demands, tolerance_band_um=band, **opts)
    best, fits = suggest_fit(spec.shaft_diameter_mm, required_min, allowed_max)
    return JointSizing(joint=spec.name, joint_type="press_fit", values=vals, margins=margins, solve=res,
                       target_margin=float(target_margin), fit=best, fits=fits)


def press_fit_margin_table(spec: PressFitSpec, interference_um: float, demands, *, tolerance_band_um: float = 0.0,
                           **options) -> pd.DataFrame:
    """Numeric margins (:func:`press_fit_sizing_margins`) of a nominal interference at every demand, one row each."""
    rows = []
    for x in _as_demands(demands):
        e = press_fit_sizing_margins(spec, float(interference_um), x, tolerance_band_um=tolerance_band_um, **options)
        rows.append({"demand": x.name, "torque_Nm": float(x.torque_Nm), "axial_force_N": float(x.axial_force_N),
                     "speed_rpm": float(x.speed_rpm), **{k: float(v) for k, v in e.items()}})
    return pd.DataFrame(rows).set_index("demand")


def _required_min_interference_um(spec, demands, S, slip, opts) -> float:
    """Smallest minimum interference of the band [um] meeting margin S at every demand (band 0, numeric).

    The weakest capacity is linear in the interference above the losses, so one evaluation per demand scales."""
    need = 0.0
    for x in demands:
        e = press_fit_sizing_margins(spec, 1e3, x, tolerance_band_um=0.0, **opts)
        effective = float(e["weakest_effective_interference_um"])   # 1000 um less smoothing and centrifugal loss
        ratios = [e["combined_margin"]] if slip == "combined" else [e["torque_margin"], e["axial_margin"]]
        worst = min(float(r) for r in ratios)              # margin given by `effective` um of effective interference
        need = max(need, (1e3 - effective) + effective * S / worst)
    return need


def _allowed_max_interference_um(spec, demands, s_hub, s_shaft, opts) -> float:
    """Largest maximum interference of the band [um] keeping both yield safeties (numeric root of the safeties)."""
    def slack(delta):
        worst = math.inf
        for x in demands:
            with np.errstate(divide="ignore"):             # a lost fit has zero stress: safety inf
                e = press_fit_sizing_margins(spec, delta, x, tolerance_band_um=0.0, **opts)
            worst = min(worst, float(e["hub_yield_safety"]) / s_hub - 1.0, float(e["shaft_yield_safety"]) / s_shaft
                        - 1.0)
        return worst
    lo, hi = 1e-3, 50.0
    if slack(lo) <= 0.0:
        return 0.0
    while slack(hi) > 0.0:
        hi *= 2.0
        if hi > 1e5:
            return math.inf
    from scipy.optimize import brentq   # imported here: scipy.optimize takes 0.2 s to import
    return float(brentq(slack, lo, hi, xtol=1e-9, rtol=1e-12))


def suggest_fit(diameter_mm: float, required_min_interference_um: float, allowed_max_interference_um: float,
                grades: Sequence[tuple[int, int]] = FIT_GRADES) -> tuple[dict | None, pd.DataFrame]:
    """ISO 286 hole-basis fits whose interference band lies in ``[required_min, allowed_max]`` [um].

    Candidates: H<h>/<letter><s> for the (hole, shaft) grades in ``grades`` and the tabulated shaft letters
    (m..u; a letter undefined at the diameter is skipped). Returns (best, table): best = the feasible fit with the
    smallest maximum interference (lowest assembly stress; ties: the coarser tolerance, cheaper), or None; the
    table lists every candidate with ``min_um``, ``max_um``, ``feasible``.
    """
    rows = []
    for hole, shaft in grades:
        for letter in SHAFT_LETTERS:
            fit = f"H{hole}/{letter}{shaft}"
            try:
                f = fit_interference_um(diameter_mm, fit)
            except GearoptInputError:
                continue
            ok = f["min_um"] >= required_min_interference_um and f["max_um"] <= allowed_max_interference_um
            rows.append({"fit": fit, "min_um": f["min_um"], "max_um": f["max_um"], "mean_um": f["mean_um"],
                         "band_um": f["max_um"] - f["min_um"], "feasible": bool(ok)})
    table = pd.DataFrame(rows)
    if table.empty:
        return None, table
    feasible = table[table["feasible"]].sort_values(["max_um", "band_um"], ascending=[True, False])
    if feasible.empty:
        return None, table
    return fit_interference_um(diameter_mm, str(feasible.iloc[0]["fit"])), table


# ----------------------------------------------------------------------------------------------------------------
# taper fit
# ----------------------------------------------------------------------------------------------------------------

def size_taper_fit(spec: TaperFitSpec, demands: JointDemand | Sequence[JointDemand], *, target_margin: float = 1.5,
                   slip: str = "combined", capacity: str = "thesis", min_hub_yield_safety: float = 1.2,
                   max_proof_fraction: float = 0.9, nut_torque_bounds_Nm: tuple[float, float] = (1.0, 2000.0),
                   verbose: bool = False, **ipopt: Any) -> JointSizing:
    """Minimum nut tightening torque of a taper joint for ``target_margin`` at every demand (module docstring).

    Constraints: slip (``combined``: ``S (|T|/T_cap + |F_a|/W) <= 1``; ``separate``: ``T_cap >= S|T|``,
    ``W >= S|F_a|``) at the largest nut factor; hub von Mises <= yield / ``min_hub_yield_safety`` and, with a proof
    strength, thread stress <= ``max_proof_fraction`` x proof strength at the smallest nut factor.
    """
    demands = _as_demands(demands)
    check_range("target_margin", target_margin, 1.0, 100.0)
    check_range("min_hub_yield_safety", min_hub_yield_safety, 0.5, 10.0)
    check_range("max_proof_fraction", max_proof_fraction, 0.0, 1.0, low_inclusive=False)
    if slip not in SLIP_CRITERIA:
        raise GearoptInputError(f"slip={slip!r} must be one of {SLIP_CRITERIA}")
    if capacity not in TAPER_CAPACITIES:
        raise GearoptInputError(f"capacity={capacity!r} must be one of {TAPER_CAPACITIES}")
    lo, hi = (float(v) for v in nut_torque_bounds_Nm)
    if not (0.0 < lo < hi):
        raise GearoptInputError(f"nut_torque_bounds_Nm=({lo:g}, {hi:g}) must satisfy 0 < low < high")
    p = Problem(name=f"taper-fit sizing {spec.name}")
    init = min(max(spec.nut_torque_Nm or 100.0, lo), hi)
    tn = p.variable("nut_torque_Nm", init=init, lower=lo, upper=hi, scale=init, unit="N m")
    first = None
    for x in demands:
        e = taper_fit_sizing_margins(spec, tn, x, capacity=capacity)
        first = first or e
        T, Fa = abs(float(x.torque_Nm)), abs(float(x.axial_force_N))
        if slip == "combined":
            p.subject_to(f"{x.name}:slip_utilisation", target_margin * e["slip_utilisation"], upper=1.0)
        else:
            if T > 0.0:
                p.subject_to(f"{x.name}:torque_reserve_Nm", e["torque_capacity_Nm"] - target_margin * T, lower=0.0,
                             scale=T, unit="N m")
            if Fa > 0.0:
                p.subject_to(f"{x.name}:axial_reserve_N", e["axial_capacity_N"] - target_margin * Fa, lower=0.0,
                             scale=Fa, unit="N")
    hub_lim = spec.hub_yield_MPa / min_hub_yield_safety
    p.subject_to("hub_von_mises_MPa", first["hub_von_mises_MPa"], upper=hub_lim, scale=hub_lim, unit="MPa")
    if spec.proof_strength_MPa is not None:
        lim = max_proof_fraction * spec.proof_strength_MPa
        p.subject_to("thread_stress_MPa", first["thread_stress_MPa"], upper=lim, scale=lim, unit="MPa")
    p.minimize(tn, scale=init)
    res = p.solve(verbose=verbose, **ipopt)
    t_opt = float(res.values["nut_torque_Nm"])
    margins = taper_margin_table(spec, t_opt, demands, capacity=capacity)
    vals = {"nut_torque_Nm": t_opt, "preload_min_N": float(margins["preload_N"].iloc[0]),
            "preload_max_N": float(margins["preload_max_N"].iloc[0]), "nut_factor_max": spec.nut_factor_max,
            "nut_factor_min": spec.nut_factor_min, "capacity": capacity}
    return JointSizing(joint=spec.name, joint_type="taper_nut", values=vals, margins=margins, solve=res,
                       target_margin=float(target_margin))


def taper_margin_table(spec: TaperFitSpec, nut_torque_Nm: float, demands, *, capacity: str = "thesis") -> pd.DataFrame:
    """Numeric margins (:func:`taper_fit_sizing_margins`) of a nut torque at every demand, one row each."""
    rows = []
    for x in _as_demands(demands):
        e = taper_fit_sizing_margins(spec, float(nut_torque_Nm), x, capacity=capacity)
        rows.append({"demand": x.name, "torque_Nm": float(x.torque_Nm), "axial_force_N": float(x.axial_force_N),
                     "speed_rpm": float(x.speed_rpm), **{k: float(v) for k, v in e.items()}})
    return pd.DataFrame(rows).set_index("demand")


# ----------------------------------------------------------------------------------------------------------------
# data entry point
# ----------------------------------------------------------------------------------------------------------------

def size_joint(system: System, joint: str, demands, *, proof_strength_MPa: float | None = None,
               **options: Any) -> JointSizing:
    """Size the joint ``joint`` of ``system`` (``system.joints[joint]``): :func:`size_press_fit` or
    :func:`size_taper_fit` by its type (``proof_strength_MPa`` for taper nuts; ``options`` go to the sizing
    function). ``system``: the :class:`~gearopt.data.System` of the data file; a joint the file lacks raises naming
    the file and ``joints.<joint>``."""
    system = system_of(system, "size_joint")
    kind = joint_record(system, joint, "size_joint").joint_type
    if kind == "press_fit":
        return size_press_fit(PressFitSpec.from_data(system, joint), demands, **options)
    if kind == "taper_nut":
        return size_taper_fit(TaperFitSpec.from_data(system, joint, proof_strength_MPa=proof_strength_MPa), demands,
                              **options)
    raise GearoptInputError(f"[joints.{joint}] joint_type={kind!r} must be 'press_fit' or 'taper_nut'")


__all__ = ["JointDemand", "PressFitSpec", "TaperFitSpec", "JointSizing", "press_fit_sizing_margins",
           "taper_fit_sizing_margins", "size_press_fit", "size_taper_fit", "size_joint", "suggest_fit",
           "press_fit_margin_table", "taper_margin_table", "default_tolerance_band_um", "smoothing_loss_of",
           "SLIP_CRITERIA", "TAPER_CAPACITIES", "FIT_GRADES"]
