"""One recommended design among candidate designs, chosen on the exact models, and its design sheet.

:func:`recommend` judges every candidate (:class:`~gearopt.design.requirements.TrainDesign`) on every requirement
of the system (:func:`~gearopt.design.requirements.evaluate_requirements`) and picks:

1. among the candidates that meet every requirement, the one with the smallest largest PPTE;
2. when none does, the one that fails the fewest requirements a design variable can move (a fixed check of the
   data fails for every candidate alike), then the fewest failing requirements, then the smallest largest PPTE.

With a ``design_space`` (:class:`~gearopt.design.requirement_reach.DesignSpace`), each ISO 6336 safety the chosen
design fails and a design variable moves gets the reach of the space in its "what it would take"
(:func:`~gearopt.design.requirement_reach.rating_reach`: the elastic mode on the exact rating): whether any design
of the space meets it, the best value reached and the bounds or limits that stop it (with their multipliers).

Joints the data marks free (``[joints.<name>] free = true``) are design variables: each candidate's are sized first
for its own demands (:func:`~gearopt.design.requirements.size_free_joints`) and judged as sized; the sheet gives
the sized fit or nut torque.

:func:`design_sheet` writes what a drawing needs: per gear the teeth, profile shift, tip diameter with its
tolerance and the joint (fit or nut torque); per loaded flank, once however many meshes load it, the tip relief
amount [um], its start diameter and its length along the line of action to the tip [mm], the crown [um], the
relief's shape and its start transition.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Mapping, Sequence

import pandas as pd

from ..data import System
from ..errors import GearoptInputError
from ..geometry import involute as inv
from .requirement_reach import DesignSpace, RequirementReach, rating_reach, reach_signature
from .requirements import (DynamicPeaks, RequirementsCheck, TrainDesign, evaluate_requirements, size_free_joints,
                           with_capacities)


def _largest_ppte(check: RequirementsCheck) -> float:
    values = [r.value for r in check.rows if r.quantity == "ppte_um"]
    return max(values) if values else math.inf


@dataclass
class Recommendation:
    """The chosen design (``design``, its ``check``), why it won (``why``), every candidate's check
    (``checks``) and its design sheet (``sheet``: ``{"gears": ..., "flanks": [...]}``)."""

    design: TrainDesign
    check: RequirementsCheck
    why: str
    checks: dict[str, RequirementsCheck]
    sheet: dict
    option: str = ""
    notes: list[str] = field(default_factory=list)
    system: System | None = None                   # the system the design was judged with (its joints as sized)
    dynamics_check: dict = field(default_factory=dict)
    calibrated: pd.DataFrame | None = None       # the requirements judged again on field-calibrated inputs

    @property
    def verdict(self) -> str:
        return self.check.verdict

    def candidates_table(self) -> pd.DataFrame:
        """One row per candidate: verdict, failing requirements (movable / fixed), largest PPTE [um]."""
        return pd.DataFrame([{"candidate": name, "verdict": c.verdict,
                              "failing_movable": sum(not r.fixed for r in c.failed),
                              "failing_fixed": sum(r.fixed for r in c.failed), "largest_ppte_um": _largest_ppte(c),
                              "chosen": name == self.design.name} for name, c in self.checks.items()])

    def as_json(self) -> dict:
        """``result.json["recommendation"]``: option, design, why, macro, verdict, gears, flanks, requirements,
        candidates."""
        tr = self.design.train
        return {"option": self.option or self.design.name, "design": self.design.name, "why": self.why,
                "macro": {"root_profile_shift": float(tr.profile_shifts[tr.root_gear]),
                          "root_gear": tr.root_gear, "helix_angle_deg": float(tr.helix_angle_deg)},
                "verdict": self.verdict, "gears": self.sheet["gears"], "flanks": self.sheet["flanks"],
                "requirements": self.check.as_json(),
                "candidates": self.candidates_table().to_dict(orient="records"), "notes": list(self.notes),
                **({"dynamics_check": self.dynamics_check} if self.dynamics_check else {}),
                **({"on_calibrated_inputs": self.calibrated.to_dict(orient="records")}
                   if self.calibrated is not None else {})}


def recommend(system: System, candidates: Sequence[TrainDesign], *, contact_meshes: Sequence[str] | None = None,
              dynamic: DynamicPeaks | Callable[[TrainDesign, System], DynamicPeaks | None] | None = None,
              options: Mapping[str, str] | None = None, size_joints: bool = True,
              ltca_options: Mapping[str, Any] | None = None,
              design_space: DesignSpace | None = None,
              known_reaches: Sequence[RequirementReach] = ()) -> Recommendation:
    """Judge every candidate and choose one (module docstring). ``dynamic``: the dynamic results of every
    candidate, or a function of the candidate and the system (its joints as sized) returning its own;
    ``options``: {candidate name: the train option it belongs to} for the sheet; ``size_joints``: size the joints
    the data marks free for each candidate first (:func:`size_free_joints`: its joints become design variables);
    ``design_space``: the macro design space whose reach toward a failing safety requirement is reported (module
    docstring; ``known_reaches``: reaches computed before, taken where their signature matches, :func:`add_reach`);
    the other arguments go to :func:`evaluate_requirements`."""
    if not candidates:
        raise GearoptInputError("recommend() needs at least one candidate design")
    names = [c.name for c in candidates]
    if len(set(names)) != len(names):
        raise GearoptInputError(f"candidate names must be unique: {names}")

    def dynamics_of(c: TrainDesign, sys: System):
        return dynamic(c, sys) if callable(dynamic) else dynamic

    checks, systems, sizing, judged, sized = {}, {}, {}, {}, {}
    for c in candidates:
        sys_c, notes = size_free_joints(system, c, dynamics_of(c, system), sized=sized) if size_joints \
            else (system, {})
        if sys_c is not system:
            c = replace(c, variables=tuple(dict.fromkeys((*c.variables, "joints"))))
        dyn = dynamics_of(c, sys_c)
        if sys_c is not system and isinstance(dynamic, DynamicPeaks):
            dyn = with_capacities(dynamic, sys_c, [n for n, j in sys_c.joints.items() if j.free])
        checks[c.name] = evaluate_requirements(sys_c, c, contact_meshes=contact_meshes, dynamic=dyn,
                                               ltca_options=ltca_options)
        systems[c.name], sizing[c.name], judged[c.name] = sys_c, notes, c

    def key(c: TrainDesign):
        chk = checks[c.name]
        return (chk.verdict != "PASS", sum(not r.fixed for r in chk.failed), len(chk.failed), _largest_ppte(chk))

    ranked = sorted(candidates, key=key)
    best = judged[ranked[0].name]
    chk = checks[best.name]
    if chk.verdict == "PASS":
        passing = [c.name for c in ranked if checks[c.name].verdict == "PASS"]
        why = (f"meets every requirement; the smallest largest PPTE ({_largest_ppte(chk):.3g} µm) of the "
               f"{len(passing)} passing candidate(s) ({', '.join(passing)})")
    else:
        movable = [r.name for r in chk.failed if not r.fixed]
        fixed = [r.name for r in chk.failed if r.fixed]
        why = (f"no candidate meets every requirement; this one fails the fewest the design can move "
               f"({len(movable)}{': ' + '; '.join(movable) if movable else ''}), then has the smallest largest "
               f"PPTE ({_largest_ppte(chk):.3g} µm); {len(fixed)} fixed check(s) of the data fail for every "
               f"candidate alike")
    if design_space is not None and chk.verdict == "FAIL":
        add_reach(systems[best.name], best, chk, design_space, known_reaches)
    rec = Recommendation(design=best, check=chk, why=why, checks=checks,
                         sheet=design_sheet(systems[best.name], best), option=(options or {}).get(best.name, ""),
                         system=systems[best.name])
    rec.notes += [f"joint {j} sized: {text}" for j, text in sizing[best.name].items()]
    return rec


SAFETY_ROWS = {"S_H": "S_H", "S_F": "S_F", "S_B": "S_B", "S_H_dynamic_peak": "S_H", "S_F_dynamic_peak": "S_F"}
"""Requirement quantities of the ISO 6336 safeties -> the safety they judge."""


def add_reach(system: System, design: TrainDesign, check: RequirementsCheck, space: DesignSpace,
              known: Sequence[RequirementReach] = ()) -> None:
    """Prefix the "what it would take" of every failing, movable safety row of ``check`` with the reach of
    ``space`` toward it (one scene per load basis: the design torques, the dynamic peaks); the reach goes to the
    row's ``detail["design_space_reach"]``. ``known``: reaches computed before (e.g. by the co-design study, for
    the same space): one whose :func:`reach_signature` matches is taken instead of solving again."""
    groups: dict[str, list] = {}
    for r in check.failed:
        if r.fixed or r.quantity not in SAFETY_ROWS or "torques_Nm" not in r.detail:
            continue
        groups.setdefault(r.quantity.removeprefix(SAFETY_ROWS[r.quantity]), []).append(r)
    for rows in groups.values():
        d = rows[0].detail
        limits = {SAFETY_ROWS[r.quantity]: r.limit for r in rows}
        reach = {}
        for key, limit in limits.items():
            sig = reach_signature(space, key, limit, d["torques_Nm"], d["speeds_rpm"], d["rating_options"])
            reach.update({key: k for k in known if k.signature == sig})
        missing = {k: v for k, v in limits.items() if k not in reach}
        if missing:
            reach.update(rating_reach(system, design.train, space, d["torques_Nm"], d["speeds_rpm"], missing,
                                      rating_options=d["rating_options"]))
        for r in rows:
            found = reach[SAFETY_ROWS[r.quantity]]
            r.what_it_would_take = found.text() + (f"; {r.what_it_would_take}" if r.what_it_would_take else "")
            r.detail["design_space_reach"] = found.as_json()


def _joint_sheet(system: System, gear: str) -> dict | None:
    joint = system.joint_of(gear)
    if joint is None:
        return None
    e = joint.entries
    if joint.joint_type == "press_fit":
        return {"joint": joint.name, "type": "press_fit", "fit": e.get("fit"), "free": joint.free,
                "diametral_interference_um": e.get("diametral_interference_um"),
                "diametral_interference_range_um": [e.get("diametral_interference_min_um"),
                                                    e.get("diametral_interference_max_um")],
                "shaft_diameter_mm": e.get("shaft_diameter_mm")}
    return {"joint": joint.name, "type": joint.joint_type, "nut_torque_Nm": e.get("nut_torque_Nm"), "free": joint.free,
            "taper": e.get("taper"), "taper_large_diameter_mm": e.get("taper_large_diameter_mm")}


def design_sheet(system: System, design: TrainDesign) -> dict:
    """``{"gears": {gear: {...}}, "flanks": [{...}, ...]}`` of ``design`` (module docstring). A flank loaded by
    several meshes appears once; its modifications must agree between those meshes (else an error names them)."""
    tr = design.train
    gears = {}
    for name, spec in tr.gears.items():
        lo, hi = system.gear(name).tip_diameter_allowance_mm if name in system.gears else (0.0, 0.0)
        d_a = float(tr.tip_diameters_mm[name])
        gears[name] = {"teeth": int(spec.teeth), "profile_shift": float(tr.profile_shifts[name]),
                       "tip_diameter_mm": d_a, "tip_diameter_tolerance_mm": [float(lo), float(hi)],
                       "face_width_mm": float(spec.face_width_mm), "joint": _joint_sheet(system, name)}
    flanks: dict[tuple[str, str], dict] = {}
    for mesh, mg in design.microgeometry.items():
        pair = tr.pairs[mesh]
        g = pair.geometry()
        for i, (gear, side) in enumerate(((pair.names[0], "driving"), (pair.names[1], "driven"))):
            amount = float(mg.tip_relief_um[i])
            d_b, d_a = float(g["base_diameter_mm"][i]), float(g["tip_diameter_mm"][i])
            start_roll = mg.tip_relief_start_roll_deg[i]
            start_d = mg.tip_relief_start_diameter_mm[i]
            if start_roll is not None:
                start_d = float(inv.diameter_at_roll_length(0.5 * d_b * math.radians(float(start_roll)), d_b))
            entry = {"gear": gear, "flank": side, "tip_relief_um": amount,
                     "tip_relief_start_diameter_mm": None if start_d is None else float(start_d),
                     "tip_relief_length_mm": (None if start_d is None else
                                              float(inv.roll_length_at(d_a, d_b) - inv.roll_length_at(start_d, d_b))),
                     "tip_relief_start_roll_deg": None if start_roll is None else float(start_roll),
                     "crown_um": float(mg.profile_crown_um[i]), "lead_crown_um": float(mg.lead_crown_um[i]),
                     "relief_shape": mg.relief_shape,
                     "start_transition": (f"blended over {mg.relief_smoothing_deg:g} deg of roll"
                                          if mg.relief_smoothing_deg > 0 else "sharp"),
                     "relief_smoothing_deg": float(mg.relief_smoothing_deg), "meshes": [mesh]}
            key = (gear, side)
            if key in flanks:
                other = flanks[key]
                for k in ("tip_relief_um", "tip_relief_start_diameter_mm", "crown_um"):
                    a, b = other[k], entry[k]
                    if (a is None) != (b is None) or (a is not None and abs(a - b) > 1e-6 * max(1.0, abs(a))):
                        raise GearoptInputError(
                            f"flank {gear}:{side} has {k} {a} in {other['meshes']} and {b} in {mesh}: a flank is "
                            f"ground one way (give the meshes one flank variable)")
                other["meshes"].append(mesh)
            else:
                flanks[key] = entry
    return {"gears": gears, "flanks": list(flanks.values())}


__all__ = ["Recommendation", "recommend", "design_sheet", "add_reach"]
