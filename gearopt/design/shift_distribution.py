"""Profile-shift distribution of a pair at a fixed centre distance, solved with Ipopt.

At a fixed centre distance the sum x1 + x2 is fixed (ISO 21771 eq. 44); only the split is free. ISO/TR 4467 gives a
rule of thumb (lambda); here the split is optimised for a stated goal with exact derivatives:

- ``"max_min_tip_thickness"``: maximise the smaller normal tip thickness of the two gears (epigraph ``t <= s_an,i``);
- ``"balance_specific_sliding"``: minimise the larger magnitude of the specific sliding at the two roots
  (epigraph ``t >= -zeta_i``), which balances them when neither limit is active;

subject to the pair's design limits (:meth:`GearPair.constraints`): worst-case transverse contact ratio >= a minimum
(maximum centre distance, minimum tip diameters), undercut, pointed tip, tip/root interference, bottom clearance and
the ISO/TR 4467 shift limits.
"""

from __future__ import annotations

from dataclasses import replace

import pandas as pd

from ..errors import GearoptInputError
from ..geometry.pair import GearPair
from ..nlp.problem import Problem

OBJECTIVES = ("max_min_tip_thickness", "balance_specific_sliding")


def _split_pair(pair: GearPair, x1) -> GearPair:
    """``pair`` with gear 1's shift replaced by ``x1`` at the same centre distance (so x2 = sum - x1, same k)."""
    sum_x = pair.profile_shifts[0] + pair.profile_shifts[1]
    return replace(pair, profile_shifts=(x1, sum_x - x1), tip_diameters_mm=None)


def _summary(pair: GearPair) -> dict:
    g = pair.geometry()
    return {
        "profile_shift_1": g["profile_shifts"][0], "profile_shift_2": g["profile_shifts"][1],
        "tip_thickness_1_mm": g["tip_thickness_mm"][0], "tip_thickness_2_mm": g["tip_thickness_mm"][1],
        "specific_sliding_root_1": g["specific_sliding_root"][0],
        "specific_sliding_root_2": g["specific_sliding_root"][1],
        "transverse_contact_ratio": g["transverse_contact_ratio"],
        "worst_case_transverse_contact_ratio": g["worst_case_transverse_contact_ratio"],
    }


def shift_split_problem(pair: GearPair, *, objective: str = "max_min_tip_thickness", min_contact_ratio: float = 1.2,
                        min_tip_thickness_ratio: float = 0.2, iso_tr_4467_limits: bool = True,
                        init: float | None = None) -> Problem:
    """The split NLP of ``pair`` as a :class:`Problem` (variable ``profile_shift_1``; epigraph variable
    ``min_tip_thickness_mm`` or ``max_root_specific_sliding``), unsolved, so that Problem-level tools
    (``multistart``, ``solve_elastic``) apply to it. ``init``: start of x1 (default: the pair's own)."""
    if objective not in OBJECTIVES:
        raise GearoptInputError(f"objective={objective!r} must be one of {OBJECTIVES}")
    p = Problem(name=f"profile-shift split {pair.names[0]}-{pair.names[1]}")
    x1 = p.variable("profile_shift_1", init=float(pair.profile_shifts[0]) if init is None else init, lower=-1.0,
                    upper=2.0, scale=0.5)
    trial = _split_pair(pair, x1)
    g = trial.geometry()
    margins = trial.constraints(min_tip_thickness_ratio=min_tip_thickness_ratio, min_contact_ratio=min_contact_ratio,
                                worst_case=True, iso_tr_4467_limits=iso_tr_4467_limits, min_backlash_mm=None)
    for name, expr in margins.items():
        p.subject_to(name, expr, lower=0.0, unit="mm" if name.endswith("_mm") else "")
    m = float(pair.module_mm)
    if objective == "max_min_tip_thickness":
        t = p.variable("min_tip_thickness_mm", init=0.5 * m, lower=0.0, upper=2.0 * m, scale=m, unit="mm")
        for i in range(2):
            p.subject_to(f"epigraph_tip_thickness_{i + 1}_mm", g["tip_thickness_mm"][i] - t, lower=0.0, unit="mm")
        p.maximize(t, scale=m)
    else:
        t = p.variable("max_root_specific_sliding", init=2.0, lower=0.0, upper=100.0, scale=1.0)
        for i in range(2):
            p.subject_to(f"epigraph_specific_sliding_{i + 1}", t + g["specific_sliding_root"][i], lower=0.0)
        p.minimize(t)
    return p


def optimise_shift_split(pair: GearPair, *, objective: str = "max_min_tip_thickness", min_contact_ratio: float = 1.2,
                         min_tip_thickness_ratio: float = 0.2, iso_tr_4467_limits: bool = True,
                         shift_split: float = 0.5, verbose: bool = False, **ipopt) -> dict:
    """Optimise the split of ``pair``'s (fixed) sum of profile shifts; returns a plain dict.

    Keys: ``objective``, ``status``, ``iterations``, ``profile_shifts`` (optimised), ``iso_tr_4467_profile_shifts``
    (the ISO/TR 4467 split with ``shift_split`` = lambda, also the initial guess), ``objective_value`` (mm for tip
    thickness, dimensionless for sliding), ``active_constraints`` (names), ``table`` (DataFrame comparing the two
    splits). Raises a :class:`~gearopt.errors.SolveError` subclass naming the violated limits if Ipopt fails
    (``elastic_on_failure=True`` among ``ipopt`` attaches the least relaxation of the limits to it).
    """
    if objective not in OBJECTIVES:
        raise GearoptInputError(f"objective={objective!r} must be one of {OBJECTIVES}")
    if pair.is_symbolic:
        raise GearoptInputError("optimise_shift_split needs a numeric pair (its centre distance fixes x1 + x2)")
    iso_pair = GearPair.from_centre_distance(
        teeth=pair.teeth, centre_distance_mm=pair.centre_distance_mm, module_mm=pair.module_mm,
        pressure_angle_deg=pair.pressure_angle_deg, helix_angle_deg=pair.helix_angle_deg,
        face_width_mm=pair.face_width_mm, shift_split=shift_split,
        addendum_coefficient=pair.addendum_coefficient, dedendum_coefficient=pair.dedendum_coefficient,
        root_radius_coefficient=pair.root_radius_coefficient, tip_shortening=pair.tip_shortening,
        tolerances=pair.tolerances, names=pair.names, helix_hands=pair.helix_hands)
    x1_iso = float(iso_pair.profile_shifts[0])

    p = shift_split_problem(pair, objective=objective, min_contact_ratio=min_contact_ratio,
                            min_tip_thickness_ratio=min_tip_thickness_ratio, iso_tr_4467_limits=iso_tr_4467_limits,
                            init=x1_iso)
    res = p.solve(verbose=verbose, **ipopt)
    x1_opt = float(res.values["profile_shift_1"])
    best = _split_pair(pair, x1_opt)
    table = pd.DataFrame({"iso_tr_4467": _summary(iso_pair), "ipopt": _summary(best)})
    table.index.name = "quantity"
    active = [str(n) for n in res.constraints.loc[res.constraints["active"], "name"]
              if not str(n).startswith("epigraph")]
    return {
        "objective": objective,
        "status": res.status,
        "iterations": int(res.iterations),
        "profile_shifts": [float(v) for v in best.profile_shifts],
        "iso_tr_4467_profile_shifts": [float(v) for v in iso_pair.profile_shifts],
        "objective_value": float(res.values["min_tip_thickness_mm" if objective == "max_min_tip_thickness"
                                            else "max_root_specific_sliding"]),
        "active_constraints": active,
        "solve_time_s": float(res.solve_time_s),
        "table": table,
    }
