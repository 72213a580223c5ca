"""The verdict of a design against the system's requirements (:class:`gearopt.data.requirements.Requirements`),
computed by the exact models only, with what it would take to pass each failing requirement.

:func:`evaluate_requirements` judges a :class:`TrainDesign` -- a numeric gear train (teeth, profile shifts, helix
angle) and the flank microgeometry of its meshes -- on every requirement of ``system.requirements``:

- PPTE over each contact mesh's design range (``system.torque_range_Nm``): the exact LTCA (:func:`gearopt.ltca`,
  default resolution: PPTE within 1 % of converged) at every load case, against the limit of the chosen form
  (the unmodified flanks of the same macro design, or a value) and, optionally, load case by load case against the
  unmodified flanks;
- contact temperature (bulk + Blok flash) and loaded contact ratio: the same LTCA runs, worst over the load cases;
- worst-case transverse contact ratio of every mesh (largest centre distance, thinnest teeth);
- S_H, S_F (both gears) and S_B of every mesh with a design torque: :func:`gearopt.rating.rate_iso6336` with every
  factor computed, K_A of ``[design_loads]``, endurance;
- joint slip margin at the design load (weakest fit: minimum interference, DIN 7190 smoothing, highest nut factor)
  and hub yield safety (nominal fit) of every ``[joints]`` entry;
- optional inputs from a dynamics run: S_H/S_F at the largest dynamic mesh torques (K_A = K_v = 1) and the joint
  slip and walk-off margins over speed.

A requirement the design's variables cannot move is marked ``fixed`` (a check of the data, not a design outcome).
A failing row says what it would take: for a rating the largest torque and the smallest face width at which it
passes (bisection on the exact rating), for a joint the sizing that would hold (:func:`size_joint`), for a hub the
factor its stress must fall by.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Mapping, Sequence

import numpy as np
import pandas as pd

from ..contact.ltca import ltca
from ..contact.microgeometry import Microgeometry
from ..contact.relief_tolerances import ReliefTolerances, relief_variants
from ..data import System
from ..data.requirements import Requirements
from ..errors import GearoptInputError, SolveError
from ..validation import check_range
from ..geometry.train import GearTrain
from ..joints.catalogue import joint_capacity
from ..joints.walk_off import joint_margins, walk_off
from ..rating.train_rating import iso6336_train_table
from .joint_sizing import JointDemand, size_joint


@dataclass(frozen=True)
class TrainDesign:
    """A design to judge: ``train`` a numeric :class:`GearTrain` (teeth, profile shifts, helix angle), and
    ``microgeometry`` {mesh: :class:`Microgeometry`} its flank modifications (a mesh left out: unmodified);
    ``name`` labels it; ``variables`` names what the design process could move (``"macro"``, ``"flanks"``,
    ``"joints"``, ``"dynamics"``) -- a requirement no listed variable moves is reported as a fixed check;
    ``reference_train`` the unmodified baseline of the PPTE requirement (default ``train`` itself: the same macro
    design with unmodified flanks; a design study whose macro variables moved from a baseline passes the baseline,
    the train its NLP compared against)."""

    train: GearTrain
    microgeometry: Mapping[str, Microgeometry] = field(default_factory=dict)
    name: str = "design"
    variables: tuple[str, ...] = ("macro", "flanks")
    reference_train: GearTrain | None = None


@dataclass
class RequirementRow:
    """One requirement judged on one design: ``name`` (naming its mesh, gear or joint), ``quantity``, ``target``,
    the worst ``value`` over its instances, the ``limit``, ``unit``, ``sense`` (``">="``/``"<="``), ``verdict``
    (``"PASS"``/``"FAIL"``), ``worst_case`` (the instance), ``failing`` (every failing instance), ``basis`` (how
    it was computed), ``fixed`` (no design variable moves it), ``torques_Nm`` (the load cases of a PPTE row) and
    ``what_it_would_take`` (a failing row: the smallest change that would let it pass)."""

    name: str
    quantity: str
    target: str
    value: float
    limit: float
    unit: str
    sense: str
    verdict: str
    worst_case: str
    failing: list[str]
    basis: str
    fixed: bool = False
    torques_Nm: list[float] | None = None
    what_it_would_take: str | None = None
    detail: dict = field(default_factory=dict)

    def as_dict(self) -> dict:
        d = {"name": self.name, "quantity": self.quantity, "target": self.target, "value": _json(self.value),
             "limit": _json(self.limit), "unit": self.unit, "sense": self.sense, "verdict": self.verdict,
             "worst_case": self.worst_case, "failing": list(self.failing), "basis": self.basis,
             "fixed_check": self.fixed}
        if self.torques_Nm is not None:
            d["torques_Nm"] = [float(t) for t in self.torques_Nm]
        if self.verdict == "FAIL":
            d["what_it_would_take"] = self.what_it_would_take or "no design change identified"
        if self.detail:
            d["detail"] = self.detail
        return d


def _json(v: float) -> float | str:
    v = float(v)
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return v


@dataclass
class RequirementsCheck:
    """The rows of :func:`evaluate_requirements` for one design; ``verdict`` ``"PASS"`` when every row passes."""

    design: str
    rows: list[RequirementRow]

    @property
    def failed(self) -> list[RequirementRow]:
        return [r for r in self.rows if r.verdict == "FAIL"]

    @property
    def verdict(self) -> str:
        return "FAIL" if self.failed else "PASS"

    def row(self, quantity: str, target: str) -> RequirementRow:
        """The row of ``quantity`` on ``target`` (KeyError naming both when absent)."""
        for r in self.rows:
            if r.quantity == quantity and r.target == target:
                return r
        raise KeyError(f"no requirement row {quantity!r} on {target!r} ({[(r.quantity, r.target) for r in self.rows]})")

    def table(self) -> pd.DataFrame:
        """One row per requirement: name, worst case, value, limit, unit, verdict, fixed, what it would take."""
        return pd.DataFrame([{"requirement": r.name, "worst_case": r.worst_case, "value": r.value,
                              "sense": r.sense, "limit": r.limit, "unit": r.unit, "verdict": r.verdict,
                              "fixed_check": r.fixed, "what_it_would_take": r.what_it_would_take or ""}
                             for r in self.rows])

    def as_json(self) -> list[dict]:
        return [r.as_dict() for r in self.rows]


def _row(name: str, quantity: str, target: str, instances: Iterable[tuple[str, float]], limit: float, unit: str,
         sense: str, basis: str, *, fixed: bool = False, **extra) -> RequirementRow:
    items = [(label, float(v)) for label, v in instances]
    if not items:
        raise GearoptInputError(f"requirement {name!r} has no instance to judge")
    pick = min if sense == ">=" else max
    worst_label, worst = pick(items, key=lambda kv: kv[1])
    ok = (lambda v: v >= limit) if sense == ">=" else (lambda v: v <= limit)
    failing = [label for label, v in items if not ok(v)]
    return RequirementRow(name=name, quantity=quantity, target=target, value=worst, limit=float(limit), unit=unit,
                          sense=sense, verdict="FAIL" if failing else "PASS", worst_case=worst_label,
                          failing=failing, basis=basis, fixed=fixed, **extra)


# -- contact ---------------------------------------------------------------------------------------------------------


def contact_speed_rpm(system: System, train: GearTrain, mesh: str) -> float | None:
    """Speed [rpm] of ``mesh``'s driving gear when the train's root gear turns at ``[design_loads] speed_rpm``."""
    loads = system.design_loads
    if loads is None or loads.speed_rpm is None:
        return None
    return train.gear_speed_rpm(train.pairs[mesh].names[0], loads.speed_rpm)


def mesh_ltca_runs(system: System, design: TrainDesign, mesh: str, *, modified: bool = True,
                   ltca_options: Mapping[str, Any] | None = None) -> dict[float, Any]:
    """{torque [N m]: exact LTCA result} of ``mesh`` over its design range, with the design's flanks (``modified``)
    or unmodified ones (of ``design.reference_train`` when given), at the design speed and the data's lubrication
    (default LTCA resolution)."""
    train = design.train if modified or design.reference_train is None else design.reference_train
    pair = train.pairs[mesh]
    lub = system.lubrication
    opts = dict(speed_rpm=contact_speed_rpm(system, train, mesh))
    if lub is not None:
        opts.update(bulk_temperature_C=lub.oil_temperature_C, friction_coefficient=lub.mean_friction_coefficient)
    opts.update(ltca_options or {})
    mods = design.microgeometry.get(mesh) if modified else None
    return {float(t): ltca(pair, float(t), microgeometry=mods, **opts) for t in system.torque_range_Nm(mesh)}


def _contact_rows(system: System, design: TrainDesign, req: Requirements, meshes: Sequence[str],
                  ltca_options: Mapping[str, Any] | None) -> list[RequirementRow]:
    rows: list[RequirementRow] = []
    flanks_free = "flanks" in design.variables
    temps, lcrs = [], []
    for mesh in meshes:
        runs = mesh_ltca_runs(system, design, mesh, ltca_options=ltca_options)
        base = mesh_ltca_runs(system, design, mesh, modified=False, ltca_options=ltca_options) \
            if (req.ppte_form == "unmodified" or req.ppte_no_load_case_worse) else {}
        torques = sorted(runs)
        ppte = {t: float(runs[t].ppte_um) for t in torques}
        worst_t = max(ppte, key=ppte.get)
        base_ppte = {t: float(base[t].ppte_um) for t in torques} if base else {}
        if req.ppte_form == "unmodified":
            limit, form = max(base_ppte.values()), (
                "the unmodified flanks' largest PPTE over the range" + (" (of the baseline macro design)"
                                                                        if design.reference_train is not None else ""))
        else:
            limit, form = float(req.max_ppte_um), "the required value"
        row = _row(f"PPTE over {_span(torques)} N m, {mesh}", "ppte_um", mesh,
                   [(f"{mesh} at {worst_t:g} N m", ppte[worst_t])], limit, "um", "<=",
                   f"largest exact-LTCA PPTE over the load cases, against {form}", fixed=not flanks_free,
                   torques_Nm=torques)
        row.detail = {"ppte_um": {f"{t:g}": ppte[t] for t in torques}}
        if base_ppte:
            row.detail["unmodified_ppte_um"] = {f"{t:g}": base_ppte[t] for t in torques}
        if req.ppte_no_load_case_worse:
            worse = [t for t in torques if ppte[t] > base_ppte[t] * (1.0 + 1e-9)]
            row.detail["worse_than_unmodified_Nm"] = worse
            if worse:
                row.verdict = "FAIL"
                row.failing += [f"worse than unmodified at {t:g} N m ({ppte[t]:.3g} > {base_ppte[t]:.3g} µm)"
                                for t in worse]
        if row.verdict == "FAIL":
            row.what_it_would_take = _ppte_what_it_would_take(ppte, base_ppte, limit, row)
        rows.append(row)
        robust = _ppte_within_tolerances(system, design, mesh, req, ltca_options)
        if robust is not None:
            worst_t, worst_v, label, count = robust
            r = _row(f"PPTE over {_span(torques)} N m within the relief tolerances, {mesh}", "ppte_um_toleranced",
                     mesh, [(f"{mesh} at {worst_t:g} N m, {label}", worst_v)], limit, "um", "<=",
                     f"largest exact-LTCA PPTE over the load cases and {count} flank variants: relief amounts "
                     f"±{req.ppte_relief_tolerance_um:g} µm, starts ±{req.ppte_relief_start_tolerance_deg:g}° roll"
                     + (", start blended as designed or sharp" if req.ppte_sharp_start else "")
                     + f", against {form}", fixed=not flanks_free, torques_Nm=torques)
            if r.verdict == "FAIL":
                r.what_it_would_take = (f"the PPTE at {r.worst_case} must fall from {r.value:.3g} to {limit:.3g} µm: "
                                        "tighter relief tolerances, or a design NLP that holds this limit over them "
                                        "(a scene limit 'ppte_um_toleranced' with the same tolerances)")
            rows.append(r)
        temps += [(f"{mesh} at {t:g} N m", float(runs[t].max_flash_temperature_C)) for t in torques
                  if runs[t].max_flash_temperature_C is not None]
        lcrs += [(f"{mesh} at {t:g} N m", float(runs[t].loaded_contact_ratio)) for t in torques]
    if temps:
        r = _row("Contact temperature (bulk + Blok flash), exact LTCA", "max_contact_temperature_C",
                 ",".join(meshes), temps, req.max_contact_temperature_C, "degC", "<=",
                 "exact LTCA at every load case of each mesh's range", fixed=not flanks_free)
        if r.verdict == "FAIL":
            r.what_it_would_take = ("a cooler oil or a lower friction coefficient: the flash temperature must fall by "
                                    f"{r.value - r.limit:.3g} K at {r.worst_case}")
        rows.append(r)
    r = _row("Loaded contact ratio over the load range, exact LTCA", "loaded_contact_ratio", ",".join(meshes), lcrs,
             req.min_loaded_contact_ratio, "-", ">=", "exact LTCA at every load case of each mesh's range",
             fixed=not flanks_free)
    if r.verdict == "FAIL":
        r.what_it_would_take = (f"shorter tip reliefs at {r.worst_case}: they shorten the loaded path of contact "
                                f"(the unmodified flanks' ratio is the upper bound reliefs can keep)")
    rows.append(r)
    return rows


def _ppte_within_tolerances(system: System, design: TrainDesign, mesh: str, req: Requirements,
                            ltca_options: Mapping[str, Any] | None) -> tuple[float, float, str, int] | None:
    """(torque, PPTE, variant, variants) of the worst exact-LTCA PPTE of ``mesh`` over its range and the variants of
    its reliefs over the tolerances of ``req`` (:func:`~gearopt.contact.relief_tolerances.relief_variants`); None
    when there is nothing to vary."""
    mg = design.microgeometry.get(mesh)
    if mg is None:
        return None
    pair = design.train.pairs[mesh]
    g = pair.geometry()
    relieved = [i for i in (0, 1) if float(mg.tip_relief_um[i]) > 0.0]
    variants = relief_variants(mg, g, requirement_tolerances(req), relieved)
    if not variants:
        return None
    worst = (0.0, -math.inf, "", len(variants))
    for v in variants:
        m = v.microgeometry
        label = ", ".join(f"{pair.names[i]} {float(m.tip_relief_um[i]):.3g} µm from "
                          f"{float(m.tip_relief_start_roll_deg[i]):.2f}°" for i in relieved) + \
            (", sharp start" if v.sharp else "")
        runs = mesh_ltca_runs(system, dataclasses.replace(design, microgeometry={**design.microgeometry, mesh: m}),
                              mesh, ltca_options=ltca_options)
        for t, r in runs.items():
            if r.ppte_um > worst[1]:
                worst = (t, float(r.ppte_um), label, len(variants))
    return worst


def requirement_tolerances(req: Requirements) -> ReliefTolerances:
    """The relief tolerances the PPTE requirement of ``req`` is judged over."""
    return ReliefTolerances(req.ppte_relief_tolerance_um, req.ppte_relief_start_tolerance_deg, req.ppte_sharp_start)


def _span(torques: Sequence[float]) -> str:
    lo, hi = min(torques), max(torques)
    return f"{lo:g}-{hi:g}" if lo != hi else f"{lo:g}"


def _ppte_what_it_would_take(ppte: dict, base: dict, limit: float, row: RequirementRow) -> str:
    worst = max(ppte.values())
    parts = []
    if worst > limit:
        parts.append(f"the largest PPTE must fall from {worst:.3g} to {limit:.3g} µm "
                     f"({100 * (worst / limit - 1):.3g} % over)")
    for t in row.detail.get("worse_than_unmodified_Nm") or []:
        parts.append(f"at {t:g} N m the PPTE must fall by {ppte[t] - base[t]:.2g} µm to the unmodified flanks' "
                     f"{base[t]:.3g} µm (less tip relief: a relief sized for the top of the range adds transmission "
                     f"error at its light end)")
    return "; ".join(parts) or "no design change identified"


def _contact_ratio_rows(design: TrainDesign, req: Requirements) -> RequirementRow:
    items = [(m, float(p.geometry()["worst_case_transverse_contact_ratio"])) for m, p in design.train.pairs.items()]
    r = _row("Worst-case transverse contact ratio (tolerances)", "worst_case_transverse_contact_ratio", "all meshes",
             items, req.min_contact_ratio, "-", ">=", "largest centre distance, thinnest teeth, smallest tips",
             fixed="macro" not in design.variables)
    if r.verdict == "FAIL":
        r.what_it_would_take = (f"{r.worst_case}: tighter centre-distance or tip-diameter tolerances, or a profile "
                                "shift split that lengthens the path of contact")
    return r


# -- rating ----------------------------------------------------------------------------------------------------------


DYNAMIC_PEAK_RATING = {"application_factor": 1.0, "K_v": 1.0}
"""Rating keywords at a dynamic peak torque: the simulation already holds the external and internal dynamic loads
(ISO 6336-1 method A), so K_A = K_v = 1; the other factors are computed."""


def _grades(system: System) -> dict:
    return {g: v.accuracy_grade_iso1328 for g, v in system.gears.items() if v.accuracy_grade_iso1328 is not None}


def rating_table(system: System, train: GearTrain, torques_Nm: Mapping[str, float], root_speed_rpm: float, *,
                 application_factor: float, **options) -> pd.DataFrame:
    """:func:`iso6336_train_table` with every factor computed, the data's accuracy grades, endurance."""
    return iso6336_train_table(train, dict(torques_Nm), root_speed_rpm, application_factor=application_factor,
                               accuracy_grades=_grades(system), **options)


def safety_values(table: pd.DataFrame, key: str) -> list[tuple[str, float]]:
    """``[(instance, value)]`` of the safety ``key`` ("S_H", "S_F": one per gear, "mesh gear"; "S_B": one per mesh)
    in a rating table (:func:`rating_table`)."""
    out = []
    for _, r in table.iterrows():
        if key == "S_B":
            out.append((f"{r['mesh']}", float(r["S_B"])))
        else:
            for g in (1, 2):
                out.append((f"{r['mesh']} {r[f'gear_{g}']}", float(r[f"{key}_{g}"])))
    return out


def rating_headroom(system: System, train: GearTrain, mesh: str, torque_Nm: float, root_speed_rpm: float,
                    key: str, limit: float, *, application_factor: float, **options) -> dict:
    """What it would take for the safety ``key`` (``"S_H"``, ``"S_F"``, ``"S_B"``) of ``mesh`` to reach ``limit``:
    ``max_torque_Nm`` (the largest torque at which it does, same train) and ``min_face_width_mm`` (the smallest
    common face width of both gears at ``torque_Nm``; None beyond 4 x the present width), each bracketed on the
    exact rating (:func:`rating_table`) to 0.1 % (:func:`_boundary`)."""
    if key not in ("S_H", "S_F", "S_B"):
        raise GearoptInputError(f"rating_headroom: key={key!r} must be 'S_H', 'S_F' or 'S_B'")
    if mesh not in train.pairs:
        raise GearoptInputError(f"rating_headroom: mesh={mesh!r} is not a mesh of the train ({sorted(train.pairs)})")
    check_range("limit", limit, 0.0, None, low_inclusive=False)
    check_range("torque_Nm", torque_Nm, 0.0, None, low_inclusive=False, unit="N m")

    def ratio(tr: GearTrain, t: float) -> float:            # safety over the limit: >= 1 passes
        tab = rating_table(system, tr, {mesh: t}, root_speed_rpm, application_factor=application_factor, **options)
        return min(v for _, v in safety_values(tab, key)) / limit

    # the safety falls with the torque (S_H ~ T^-1/2, S_F ~ T^-1) and rises with the face width (S_H ~ b^1/2)
    present = ratio(train, torque_Nm)
    t_max = (_boundary(lambda t: ratio(train, t), float(torque_Nm), present, slope=-0.5)
             if present < 1.0 else float(torque_Nm))
    b0 = min(train.gears[g].face_width_mm for g in train.pairs[mesh].names)

    def widened(b: float) -> GearTrain:
        gears = {n: dataclasses.replace(g, face_width_mm=b) if n in train.pairs[mesh].names else g
                 for n, g in train.gears.items()}
        return dataclasses.replace(train, gears=gears)

    if present >= 1.0:
        return {"max_torque_Nm": t_max, "min_face_width_mm": b0, "face_width_mm": b0}
    wide = ratio(widened(4.0 * b0), torque_Nm)
    b_min = (_boundary(lambda b: ratio(widened(b), torque_Nm), b0, present, good=(4.0 * b0, wide))
             if wide >= 1.0 else None)
    return {"max_torque_Nm": t_max, "min_face_width_mm": b_min, "face_width_mm": b0}


def _boundary(ratio: Callable[[float], float], bad: float, bad_ratio: float, *, good: tuple | None = None,
              slope: float = -0.5, rtol: float = 1e-3, max_evaluations: int = 40) -> float:
    """Where a monotone ``ratio(x) > 0`` (>= 1 passes) crosses 1: the passing end of a bracket once its two ends lie
    within ``rtol`` of the larger. ``bad`` (> 0) fails with ``bad_ratio``; ``good`` an ``(x, ratio)`` that passes,
    else one is searched for from ``bad`` towards 0 along the power law ``ratio ~ x^slope`` (``slope < 0``: the
    passing side lies below ``bad``; then the slope the failing points show, aiming a tenth past the crossing,
    at most 16x per step), and 0.0 is returned if none is found within a factor 1e6 of ``bad`` (a safety that
    saturates: ISO 6336's K_v grows as the load falls) or ``max_evaluations``.

    Regula falsi in ``(ln x, ln ratio)``, exact for a power law, with the Illinois weighting (an end kept twice has
    its value halved), each estimate moved ``rtol / 2`` towards the end farther from it so that the bracket also
    closes from that side, and a geometric bisection after two steps that did not halve the bracket: about five
    evaluations of ``ratio`` (on the timing train's ratings) where bisecting the bracket to ``rtol`` takes about
    ten."""
    fail = (math.log(bad), math.log(bad_ratio))
    ok = None if good is None else (math.log(good[0]), math.log(good[1]))
    width, replaced, stalled, previous = None, None, 0, None
    for _ in range(max_evaluations):
        if ok is None:                  # aim a little past the crossing, on the slope seen so far
            if previous is not None and (fail[1] - previous[1]) * slope * (fail[0] - previous[0]) > 0.0:
                slope = (fail[1] - previous[1]) / (fail[0] - previous[0])
            target = 0.1 * abs(fail[1]) + rtol * abs(slope)
            x = fail[0] + float(np.clip((target - fail[1]) / slope, -math.log(16.0), math.log(16.0)))
            previous = fail
            if abs(x - math.log(bad)) > math.log(1e6):
                return 0.0
        else:
            lo, hi = sorted((fail[0], ok[0]))
            if math.exp(hi) - math.exp(lo) <= rtol * math.exp(hi):
                return math.exp(ok[0])
            if stalled >= 2:
                x, stalled = 0.5 * (lo + hi), 0
            else:
                x = fail[0] + (ok[0] - fail[0]) * fail[1] / (fail[1] - ok[1])
                x += math.copysign(0.5 * rtol, (ok[0] if abs(ok[0] - x) > abs(x - fail[0]) else fail[0]) - x)
                x = min(max(x, lo + 0.25 * rtol), hi - 0.25 * rtol)
        point = (x, math.log(ratio(math.exp(x))))
        if point[1] >= 0.0:
            side, ok = "ok", point
        else:
            side, fail = "fail", point
        if ok is None:
            continue
        if side == replaced:            # the same end replaced twice in a row: halve the kept end's value
            fail, ok = (fail, (ok[0], 0.5 * ok[1])) if side == "fail" else ((fail[0], 0.5 * fail[1]), ok)
        replaced = side
        new_width = abs(ok[0] - fail[0])
        stalled = stalled + 1 if width is not None and new_width > 0.5 * width else 0
        width = new_width
    return math.exp(ok[0]) if ok is not None else 0.0


def _rating_rows(system: System, design: TrainDesign, req: Requirements, torques: Mapping[str, float],
                 root_speed_rpm: float, *, application_factor: float, label: str, basis: str, fixed: bool,
                 keys: Sequence[str] = ("S_H", "S_F", "S_B"), speeds: Mapping[str, float] | None = None,
                 **options) -> list[RequirementRow]:
    tables = []
    for mesh, t in torques.items():
        speed = root_speed_rpm if speeds is None else speeds[mesh]
        tab = rating_table(system, design.train, {mesh: t}, speed, application_factor=application_factor, **options)
        tab["root_speed_rpm"] = speed
        tables.append(tab)
    table = pd.concat(tables, ignore_index=True)
    rows = []
    names = {"S_H": "Contact safety S_H (ISO 6336-2)", "S_F": "Root safety S_F (ISO 6336-3)",
             "S_B": "Scuffing safety S_B (ISO/TS 6336-20 flash temperature)"}
    for key in keys:
        limit = req.limit(f"min_{key}")
        r = _row(f"{names[key]}{label}", key if not label else f"{key}_dynamic_peak", "all rated meshes",
                 safety_values(table, key), limit, "-", ">=", basis, fixed=fixed)
        r.detail = {"torques_Nm": {m: float(t) for m, t in torques.items()},
                    "speeds_rpm": {m: float(root_speed_rpm if speeds is None else speeds[m]) for m in torques},
                    "rating_options": {"application_factor": float(application_factor),
                                       **{k: v for k, v in options.items() if isinstance(v, (int, float))}}}
        if r.verdict == "FAIL":
            mesh = r.worst_case.split(" ")[0]
            speed = float(table.loc[table["mesh"] == mesh, "root_speed_rpm"].iloc[0])
            head = rating_headroom(system, design.train, mesh, torques[mesh], speed, key, limit,
                                   application_factor=application_factor, **options)
            t = float(torques[mesh])
            text = (f"{mesh}: the torque must fall from {t:.4g} to {head['max_torque_Nm']:.4g} N m "
                    f"({100 * (1 - head['max_torque_Nm'] / t):.3g} % less"
                    + (": a torsional damper or less backlash)" if label else ")"))
            text += (f", or a face width of {head['min_face_width_mm']:.4g} mm instead of "
                     f"{head['face_width_mm']:.4g} mm" if head["min_face_width_mm"] is not None
                     else ", beyond 4 x the face width")
            r.what_it_would_take = text
            r.detail.update(head)
        rows.append(r)
    return rows


# -- joints ----------------------------------------------------------------------------------------------------------


def _joint_rows(system: System, design: TrainDesign, req: Requirements, torques: Mapping[str, float]
                ) -> list[RequirementRow]:
    if not system.joints:
        return []
    tr = design.train
    result = walk_off(tr, dict(torques))
    fixed = "joints" not in design.variables
    slip, axial, hub, demands, caps = [], [], [], {}, {}
    for name, joint in system.joints.items():
        if joint.gear not in tr.gears:
            raise GearoptInputError(f"{system.source}: [joints.{name}] gear={joint.gear!r} is not a gear of the train")
        weak = joint_capacity(system, name, interference="min", nut_factor="max", smoothing=True)
        nominal = joint_capacity(system, name)
        T, F = float(result.joint_torque_Nm[joint.gear]), float(result.axial_force_N[joint.gear])
        m = joint_margins(weak.type, T, F, weak.torque_capacity_Nm, weak.axial_capacity_N)
        slip.append((name, float(np.min(m["torque_margin"]))))
        # walk-off: a fit that slips under the torque walks under any thrust -- the combined margin where a thrust acts
        axial.append((name, float(np.min(m["combined_margin"])) if F != 0.0 else math.inf))
        hub.append((name, float(nominal.hub_yield_safety)))
        demands[name], caps[name] = (T, F), nominal
    rows = []
    r = _row("Joint slip margin at the design load, weakest fit", "slip_margin", "all joints", slip,
             req.min_slip_margin, "-", ">=", "minimum interference, DIN 7190 smoothing, highest nut factor; static "
             "design torques", fixed=fixed)
    if r.verdict == "FAIL":
        r.what_it_would_take = "; ".join(
            joint_what_it_would_take(system, j, [JointDemand(torque_Nm=demands[j][0], axial_force_N=demands[j][1],
                                                             name="design load")], req.min_slip_margin)
            for j in _failing_names(r))
    rows.append(r)
    if float(tr.helix_angle_deg) != 0.0:
        r = _row("Walk-off (axial) margin at the design load, weakest fit", "axial_margin", "all joints", axial,
                 req.min_axial_margin, "-", ">=", "combined slip margin of the joint torque and the helical thrust "
                 "at the design torques (a fit that slips under torque walks under any thrust)",
                 fixed=fixed and "macro" not in design.variables)        # the helix angle sets the thrust
        if r.verdict == "FAIL":
            r.what_it_would_take = "; ".join(
                joint_what_it_would_take(system, j, [JointDemand(torque_Nm=demands[j][0], axial_force_N=demands[j][1],
                                                                 name="design load")], req.min_axial_margin)
                for j in _failing_names(r)) + "; or a smaller helix angle (the thrust grows with tan(beta))"
        rows.append(r)
    r = _row("Hub yield safety (nominal fit)", "hub_yield_safety", "all joints", hub, req.min_hub_yield_safety, "-",
             ">=", "hub yield strength / von Mises stress at the bore (Lame)", fixed=fixed)
    if r.verdict == "FAIL":
        parts = []
        for j in _failing_names(r):
            s = dict(hub)[j]
            cap = caps[j]
            what = "the nut torque" if cap.type == "taper_nut" else "the interference"
            parts.append(f"{j}: the hub stress must fall by {100 * (1 - s / req.min_hub_yield_safety):.3g} % "
                         f"(the bore stress is linear in the contact pressure: {what} x {s / req.min_hub_yield_safety:.3g}"
                         f", which lowers the slip capacity alike), or a larger hub outer diameter / a stronger hub "
                         f"material")
        r.what_it_would_take = "; ".join(parts)
    rows.append(r)
    return rows


def _failing_names(row: RequirementRow) -> list[str]:
    return [f.split(" ")[0] for f in row.failing]


def joint_what_it_would_take(system: System, joint: str, demands: Sequence[JointDemand], margin: float) -> str:
    """The smallest joint change that holds ``demands`` with ``margin``: :func:`size_joint` at the weakest
    tolerance, its interference / ISO 286 fit or nut torque; when no admissible design of this joint type exists,
    the limits its elastic solve must move."""
    try:
        sized = size_joint(system, joint, list(demands), target_margin=margin, elastic_on_failure=True)
    except SolveError as exc:
        relax = getattr(exc, "relaxations", None)
        if relax is not None and len(relax):
            moves = ", ".join(f"{r['name']} by {r['relaxation']:.3g} {r['unit']}" for _, r in relax.head(3).iterrows())
            return (f"{joint}: no {system.joints[joint].joint_type.replace('_', ' ')} of this size holds it; its limits "
                    f"must move ({moves}): another joint type (a key or spline for torque, a retainer for thrust) or "
                    f"a larger shaft")
        return f"{joint}: no admissible {system.joints[joint].joint_type.replace('_', ' ')} holds it ({exc})"
    v = sized.values
    if sized.joint_type == "press_fit":
        fit = sized.fit["fit"] if sized.fit else None
        return (f"{joint}: interference >= {v['required_min_interference_um']:.3g} µm at the weakest tolerance"
                + (f" (ISO 286 fit {fit})" if fit else " (no ISO 286 fit: a selective assembly or a shrink fit beyond "
                                                     "ISO 286)"))
    return f"{joint}: nut torque {v['nut_torque_Nm']:.4g} N m"


# -- the whole check -------------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class DynamicPeaks:
    """Results of a dynamics run the requirements judge: ``mesh_torques_Nm`` {mesh: (largest dynamic mesh torque
    [N m], root-gear speed [rpm] where it occurs)}; ``joint_margins`` rows of ``{"joint", "speed_rpm",
    "torque_margin", "axial_margin", "peak_torque_Nm", "peak_axial_force_N", "joint_speed_rpm"}`` over a speed
    sweep; ``basis`` says how they were computed."""

    mesh_torques_Nm: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    joint_margins: Sequence[Mapping[str, Any]] = ()
    basis: str = "largest dynamic mesh torque with backlash"


GROUPS = ("contact", "geometry", "rating", "joints", "dynamics")
"""The requirement groups of :func:`evaluate_requirements` (all judged by default)."""


def with_capacities(dynamic: DynamicPeaks, system: System, joints: Sequence[str]) -> DynamicPeaks:
    """``dynamic`` with the over-speed margins of ``joints`` recomputed for the capacities of ``system`` (e.g. after
    sizing them): torque margin = torque capacity at the row's speed / peak joint torque (the capacity is constant
    over a cycle, so the smallest ratio over the cycle is this), axial margin = axial capacity / peak thrust (inf
    without thrust); the per-cycle spreads of those rows are dropped (they belonged to the old capacity)."""
    rows = []
    for e in dynamic.joint_margins:
        if e["joint"] not in joints:
            rows.append(e)
            continue
        cap = joint_capacity(system, e["joint"], speed_rpm=float(e["speed_rpm"]))
        t, f = abs(float(e["peak_torque_Nm"])), abs(float(e["peak_axial_force_N"]))
        rows.append({k: v for k, v in e.items() if "_margin_cycle_" not in k and k != "cycles"}
                    | {"torque_margin": cap.torque_capacity_Nm / t if t > 0 else math.inf,
                       "axial_margin": cap.axial_capacity_N / f if f > 0 else math.inf})
    return dataclasses.replace(dynamic, joint_margins=rows)


def size_free_joints(system: System, design: TrainDesign, dynamic: DynamicPeaks | None = None,
                     requirements: Requirements | None = None, *, sized: dict | None = None
                     ) -> tuple[System, dict[str, str]]:
    """Size every joint the data marks free (``[joints.<name>] free = true``) for the slip (and, with a thrust,
    walk-off) margin of the requirements at the weakest tolerance (:func:`size_joint`): against the design load of
    ``design``'s train and, given ``dynamic``, every over-speed peak of the joint; with the requirement's hub
    yield safety. Returns the system with the sized joints (a press fit's ISO 286 fit and interference band, a
    taper's nut torque) and ``{joint: what was chosen}``; a joint no admissible design holds keeps the data's and
    says why. ``sized``: a dict kept between calls on the same ``system`` (e.g. one per candidate of a
    recommendation) in which each sizing is stored by its joint, demands and margins, so that candidates with the
    same demands (the same tooth counts and dynamics) are sized once."""
    req = requirements or system.requirements
    free = [n for n, j in system.joints.items() if j.free]
    if not free:
        return system, {}
    torques = system.design_torques_Nm()
    load = walk_off(design.train, torques)
    changes: dict[str, dict] = {}
    notes: dict[str, str] = {}
    memo = sized if sized is not None else {}
    for name in free:
        joint = system.joints[name]
        demands = []
        t, f = float(load.joint_torque_Nm[joint.gear]), float(load.axial_force_N[joint.gear])
        if t != 0.0 or f != 0.0:
            demands.append(JointDemand(torque_Nm=t, axial_force_N=f, name="design load"))
        for e in (dynamic.joint_margins if dynamic is not None else ()):
            if e["joint"] == name and (float(e["peak_torque_Nm"]) or float(e["peak_axial_force_N"])):
                demands.append(JointDemand(torque_Nm=float(e["peak_torque_Nm"]),
                                           axial_force_N=float(e["peak_axial_force_N"]),
                                           speed_rpm=float(e["speed_rpm"]), name=f"{float(e['speed_rpm']):g} rpm"))
        if not demands:
            continue
        margin = max(req.min_slip_margin, req.min_axial_margin if any(d.axial_force_N for d in demands) else 0.0)
        sizing = dict(target_margin=max(1.0, margin), min_hub_yield_safety=max(0.5, req.min_hub_yield_safety))
        key = (name, tuple(demands), tuple(sorted(sizing.items())))      # (the sizing's own ranges)
        if key not in memo:
            try:
                memo[key] = size_joint(system, name, demands, **sizing)
            except SolveError as exc:
                memo[key] = exc
        outcome = memo[key]
        if isinstance(outcome, SolveError):
            notes[name] = (f"kept the data's: no admissible {joint.joint_type.replace('_', ' ')} holds the demands "
                           f"({type(outcome).__name__})")
            continue
        v = outcome.values
        if outcome.joint_type == "press_fit":
            fit = outcome.fit
            if fit is not None:
                changes[name] = {"fit": fit["fit"], "diametral_interference_um": fit["mean_um"],
                                 "diametral_interference_min_um": fit["min_um"],
                                 "diametral_interference_max_um": fit["max_um"],
                                 "hub_bore_lower_deviation_um": fit["hole_lower_um"],
                                 "hub_bore_upper_deviation_um": fit["hole_upper_um"],
                                 "shaft_lower_deviation_um": fit["shaft_lower_um"],
                                 "shaft_upper_deviation_um": fit["shaft_upper_um"]}
                notes[name] = (f"fit {fit['fit']} (interference {fit['min_um']:.0f}-{fit['max_um']:.0f} µm; needs "
                               f">= {v['required_min_interference_um']:.3g} µm at the weakest tolerance)")
            else:
                changes[name] = {"fit": "selective", "diametral_interference_um": v["interference_um"],
                                 "diametral_interference_min_um": v["interference_min_um"],
                                 "diametral_interference_max_um": v["interference_max_um"]}
                notes[name] = (f"interference {v['interference_min_um']:.3g}-{v['interference_max_um']:.3g} µm (no "
                               f"ISO 286 fit: selective assembly)")
        else:
            changes[name] = {"nut_torque_Nm": round(float(v["nut_torque_Nm"]), 1)}
            notes[name] = f"nut torque {changes[name]['nut_torque_Nm']:g} N m"
    return (system.with_joint_entries(changes) if changes else system), notes


def evaluate_requirements(system: System, design: TrainDesign, *, contact_meshes: Sequence[str] | None = None,
                          requirements: Requirements | None = None, dynamic: DynamicPeaks | None = None,
                          ltca_options: Mapping[str, Any] | None = None,
                          groups: Sequence[str] = GROUPS) -> RequirementsCheck:
    """Judge ``design`` on every requirement (module docstring) with the exact models.

    ``contact_meshes``: the meshes whose PPTE, contact temperature and loaded contact ratio are judged (default:
    the meshes with microgeometry in ``design``, else every mesh with a design torque); ``requirements``: default
    ``system.requirements``; ``dynamic``: results of a dynamics run (:class:`DynamicPeaks`) for the dynamic-peak
    rows; ``ltca_options``: resolution overrides of the LTCA runs; ``groups``: the requirement groups to judge
    (:data:`GROUPS`: the contact of ``contact_meshes``, the geometry of every mesh, the ISO rating, the joints, the
    dynamic results)."""
    req = requirements or system.requirements
    torques = system.design_torques_Nm()
    unknown = sorted(set(torques) - set(design.train.pairs))
    if unknown:
        raise GearoptInputError(f"{system.source}: design torques name meshes {unknown} the design's train lacks")
    meshes = list(contact_meshes if contact_meshes is not None
                  else [m for m in design.microgeometry if m in torques] or list(torques))
    unknown_groups = sorted(set(groups) - set(GROUPS))
    if unknown_groups:
        raise GearoptInputError(f"groups {unknown_groups} are not requirement groups ({GROUPS})")
    rows: list[RequirementRow] = []
    if meshes and "contact" in groups:
        rows += _contact_rows(system, design, req, meshes, ltca_options)
    if "geometry" in groups:
        rows.append(_contact_ratio_rows(design, req))
    loads = system.design_loads
    if "rating" in groups and torques and loads is not None and loads.speed_rpm is not None:
        rows += _rating_rows(system, design, req, torques, loads.speed_rpm,
                             application_factor=loads.application_factor_K_A, label="",
                             basis=f"ISO 6336 at the design torques, every factor computed, K_A "
                                   f"{loads.application_factor_K_A:g}, endurance",
                             fixed="macro" not in design.variables)
    if "joints" in groups and torques and system.joints:
        rows += _joint_rows(system, design, req, torques)
    if "dynamics" not in groups:
        dynamic = None
    if dynamic is not None and dynamic.mesh_torques_Nm:
        peaks = {m: float(t) for m, (t, _) in dynamic.mesh_torques_Nm.items()}
        speeds = {m: float(s) for m, (_, s) in dynamic.mesh_torques_Nm.items()}
        rows += _rating_rows(system, design, req, peaks, 0.0, label=" at the dynamic peak torque",
                             basis=f"{dynamic.basis}; K_A = K_v = 1, endurance",
                             fixed=not {"macro", "dynamics"} & set(design.variables), keys=("S_H", "S_F"),
                             speeds=speeds, **DYNAMIC_PEAK_RATING)
    if dynamic is not None and dynamic.joint_margins:
        rows += _joint_speed_rows(system, req, dynamic, variables=set(design.variables))
    return RequirementsCheck(design.name, rows)


def _joint_speed_rows(system: System, req: Requirements, dynamic: DynamicPeaks, *, variables: set[str]
                      ) -> list[RequirementRow]:
    rows = []
    for key, quantity, limit, name, movers in (
            ("torque_margin", "slip_margin_over_speed", req.min_slip_margin,
             "Joint slip margin over speed (dynamic peak, with backlash)", {"joints", "dynamics"}),
            ("axial_margin", "axial_margin_over_speed", req.min_axial_margin, "Walk-off (axial) margin over speed",
             {"joints", "dynamics", "macro"})):                            # the helix angle sets the thrust
        fixed = not movers & variables
        items = [(f"{e['joint']} at {float(e['speed_rpm']):g} rpm", float(e[key])) for e in dynamic.joint_margins]
        r = _row(name, quantity, "all joints", items, limit, "-", ">=", f"{dynamic.basis}; capacity at the joint's "
                 "speed over the sweep", fixed=fixed)
        worst = next(e for e in dynamic.joint_margins
                     if f"{e['joint']} at {float(e['speed_rpm']):g} rpm" == r.worst_case)
        if all(math.isinf(v) for _, v in items):    # no demand anywhere: no "worst" joint to name
            r.worst_case = ("no joint carries an axial tooth force (spur meshes)" if key == "axial_margin"
                            else "no joint carries a torque")
        if f"{key}_cycle_median" in worst and int(worst.get("cycles", 1)) > 1:
            r.detail["cycle_spread"] = {"cycles": int(worst["cycles"]),
                                        **{s: float(worst[f"{key}_cycle_{s}"]) for s in ("worst", "median", "best")}}
        if r.verdict == "FAIL":
            parts = []
            for j in dict.fromkeys(f.split(" ")[0] for f in r.failing):
                dem = [JointDemand(torque_Nm=float(e["peak_torque_Nm"]), axial_force_N=float(e["peak_axial_force_N"]),
                                   speed_rpm=float(e.get("joint_speed_rpm", 0.0)), name=f"{float(e['speed_rpm']):g} rpm")
                       for e in dynamic.joint_margins if e["joint"] == j
                       and (float(e["peak_torque_Nm"]) != 0.0 or float(e["peak_axial_force_N"]) != 0.0)]
                parts.append(joint_what_it_would_take(system, j, dem, limit) if dem else f"{j}: no demand recorded")
            r.what_it_would_take = "; ".join(parts) + "; or lower dynamic peaks (a torsional damper, less backlash)"
        rows.append(r)
    return rows


__all__ = ["DYNAMIC_PEAK_RATING", "GROUPS", "with_capacities", "size_free_joints", "TrainDesign", "RequirementRow", "RequirementsCheck", "DynamicPeaks", "evaluate_requirements",
           "mesh_ltca_runs", "rating_table", "safety_values", "rating_headroom", "joint_what_it_would_take", "contact_speed_rpm"]
