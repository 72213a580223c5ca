"""Sensitivity report of a solved scene: which limit or datum holds the design back, and by how much.

For the objective at the optimum, :func:`sensitivity_report` tables

- every limit of the scene and every bound of a design variable (``kind="limit"``): ``sensitivity`` = d objective /
  d bound from the solve's multipliers (zero for an inactive one), in objective units per unit of the bound;
- every datum the scene's quantities use (``kind="parameter"``) -- the scene is rebuilt with them as NLP parameters
  (``Scene.build(parametric=True)``), re-solved from the optimum, and differentiated through its KKT system
  (:mod:`gearopt.studies.parametric`):

  - load cases: ``torque_Nm[mesh]@case``, joint demands ``joint_torque_Nm[joint]@case`` and
    ``joint_axial_force_N[joint]@case``, the driving gear's speed of a rating ``speed_rpm[mesh]@case`` and of an
    LTCA contact temperature ``speed_rpm[mesh]``;
  - materials and lubrication: ``sigma_Hlim_MPa[gear]``, ``sigma_Flim_MPa[gear]`` (ISO 6336 ratings),
    ``youngs_modulus_MPa[mesh]`` (LTCA contact stress and temperature), ``thermal_contact_coefficient_N_per_mm_sqrt_s_K
    [gear]``, ``oil_temperature_C[mesh]``, ``friction_coefficient[mesh]`` (flash temperature);
  - stiffness and fixed geometry: ``single_pair_stiffness_N_per_mm_um[mesh]`` (c' of the LTCA, its profile along
    the path kept), ``face_width_mm[mesh]`` (the contact face width of a spur mesh with one face slice);
  - joints: ``friction_coefficient[joint]``, the nominal ``diametral_interference_um[joint]``,
    ``fit_length_mm[joint]``, ``shaft_diameter_mm[joint]``, ``hub_outer_diameter_mm[joint]`` (press fits) or
    ``nut_torque_Nm``, ``nut_factor``, ``taper_length_mm`` (taper joints) -- unless a design variable frees them;

each also as a logarithmic sensitivity, ``d ln objective / d ln value`` -- the % change of the objective per % change
of the datum, as GPkit reports them (Burnell et al. 2020, "GPkit: a human-centered approach to convex optimization
in engineering design", CHI '20) -- sorted by its magnitude. ``quantity_table`` gives the same derivatives of every
reported quantity of the scene (a margin, a stress) with respect to every datum.

A datum appears only where a quantity of the scene depends on it. Not covered (built numbers of the models): the
rest of the gear geometry held fixed (a helical mesh's face width, tip diameters, centre distances -- free them as
design variables to see their multipliers), manufacturing tolerances (:func:`gearopt.studies.monte_carlo` spreads
them), the data of a mesh whose macro geometry is free (its macro-symbolic LTCA), and ISO 6336 factors
other than the endurance limits. A datum no objective or constraint uses (of a quantity only reported, or of a limit
no design variable moves) has zero objective sensitivity; its quantity sensitivities are the partial derivatives.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from ..design.scene import SceneResult
from ..design.scene_terms import quantity_kind
from ..errors import GearoptError, GearoptInputError
from ..nlp import WARM_START_IPOPT, InitialGuessWarning
from ..validation import check_range
from .parametric import kkt_sensitivity

COLUMNS = ["name", "kind", "value", "unit", "sensitivity", "log_sensitivity", "active", "of", "of_unit"]


@dataclass
class SensitivityReport:
    """Sensitivities of a solved scene (see the module docstring). ``table``: one row per limit, variable bound and
    datum: ``name``, ``kind`` ("limit"/"parameter"), ``value`` (the bound or datum), ``unit``, ``sensitivity``
    (d objective / d value, objective units per ``unit``), ``log_sensitivity`` (d ln objective / d ln value),
    ``active`` (a limit: at its bound with a multiplier; a datum: |log_sensitivity| > 1e-6), ``of`` (the objective's
    name) and ``of_unit``; sorted by |log_sensitivity|. ``quantity_table``:
    ``quantity`` x ``parameter`` rows with ``value``, ``sensitivity``, ``log_sensitivity``. ``objective``: the
    objective's value; ``kkt_residual``: relative residual of the KKT solve (0 at a regular optimum); ``note``:
    what is degenerate when the optimum is not regular."""

    scene: str
    objective_name: str
    objective_unit: str
    objective: float
    table: pd.DataFrame
    quantity_table: pd.DataFrame
    kkt_residual: float
    note: str = ""
    """Empty at a regular optimum; otherwise what is degenerate (a flat optimum: design variables that move at equal
    objective) and which numbers still hold, and how far the exact polish moved the reported design from the NLP's
    optimum (whose sensitivities these are)."""
    exact_objective: float = float("nan")
    """The reported design's objective on the exact model (the refinement's verified objective, after an exact
    polish; the NLP's where the scene has no exact refinement), in the objective's unit; ``objective`` is the NLP's
    at its optimum."""

    def markdown(self, rows: int | None = None) -> str:
        """The table as Markdown (the ``rows`` largest, default all): local first-order estimates, and for the
        entries re-solved at ±5 % the re-solved objective beside the estimate."""
        t = self.table if rows is None else self.table.head(rows)
        cols = ["name", "kind", "value", "unit", "sensitivity", "log_sensitivity", "active",
                "objective at -5 % (re-solve / first order)", "objective at +5 % (re-solve / first order)", "check"]
        lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]

        def pair(r, tag):
            got, est = getattr(r, f"objective_{tag}_5pct", np.nan), getattr(r, f"first_order_{tag}_5pct", np.nan)
            if not np.isfinite(est):
                return ""
            return f"{got:.4g} / {est:.4g}" if np.isfinite(got) else f"failed / {est:.4g}"

        for r in t.itertuples(index=False):
            lines.append(f"| {r.name} | {r.kind} | {r.value:.5g} | {r.unit} | {r.sensitivity:.4g} | "
                         f"{r.log_sensitivity:.4g} | {'yes' if r.active else ''} | {pair(r, 'minus')} | "
                         f"{pair(r, 'plus')} | {getattr(r, 'resolve_check', '')} |")
        return "\n".join(lines)

    def to_csv(self, path: str | Path) -> Path:
        """Write ``table`` as CSV; returns the path."""
        path = Path(path)
        self.table.to_csv(path, index=False)
        return path


RESOLVE_STEP = 0.05
"""Relative change of a datum at which :func:`sensitivity_report` re-solves the scene to check its first-order
estimate (``resolve_top`` entries)."""

RESOLVE_TOLERANCE = 0.10
"""A re-solved change of the objective that differs from the first-order one by more than this fraction of it is
flagged in ``resolve_check`` (issue 28: an active-set change or a second optimum nearby)."""


def sensitivity_report(result: SceneResult, *, active_tol: float = 1e-9, resolve_top: int = 3,
                       resolve_tolerance: float = RESOLVE_TOLERANCE, **ipopt: Any) -> SensitivityReport:
    """The sensitivity report of a solved scene (``scene.build().solve()``); see the module docstring.

    The sensitivities are local first-order estimates. For the ``resolve_top`` data with the largest logarithmic
    sensitivity the scene is re-solved with the datum at ±5 % (:data:`RESOLVE_STEP`, from the optimum): the columns
    ``objective_minus_5pct`` / ``objective_plus_5pct`` hold the re-solved objective and ``first_order_minus_5pct``
    / ``first_order_plus_5pct`` the estimate beside it (NaN for the other rows and for limits, whose
    sensitivities are the multipliers). ``resolve_discrepancy`` is the larger of the two sides' relative difference
    between the re-solved and the first-order change of the objective; ``resolve_check`` says ``"agrees"`` or, where
    the discrepancy exceeds ``resolve_tolerance`` (:data:`RESOLVE_TOLERANCE`), why the estimate does not hold that
    far: the limits that became active or inactive in the re-solve (an active-set change: the sensitivity holds
    only on one side of the step), or, with the same active set, the objective's curvature or another optimum
    nearby (how far the design moved is given); a failed re-solve is named.

    Raises:
        GearoptInputError: ``result`` is not a solved scene result, or the parametric re-solve lands on another
            optimum than ``result`` (another objective value: the report would describe a different design). A
            re-solve that only moves along a flat optimum is reported in ``note``.
    """
    check_range("resolve_tolerance", resolve_tolerance, 0.0, None, low_inclusive=False)
    built = _solved_build(result)
    scene = built.scene
    name, unit, factor = objective_meta(scene)
    objective = float(result.solve.objective) * factor
    rows = _limit_rows(built, result, factor, objective, name, unit)
    qrows: list[dict[str, Any]] = []
    residual, note = 0.0, ""
    pb = built.parametric_twin()
    if pb.data_parameters:
        solved, note = _resolve_at(pb, result, **ipopt)
        names = list(pb.problem.parameter_names)
        sens = kkt_sensitivity(pb.problem.opti, active_tol=active_tol,
                               parameters=[pb.data_parameters[n]["symbol"] for n in names])
        residual = sens.residual
        for i, pname in enumerate(names):
            entry = pb.data_parameters[pname]
            s = float(sens.df_dp[i]) * factor
            rows.append(_row(pname, "parameter", entry["value"], entry["unit"], s, objective,
                             abs(s * entry["value"]) > 1e-6 * abs(objective), name, unit))
        qrows = _quantity_rows(pb, solved, sens, names)
    table = pd.DataFrame(rows, columns=COLUMNS)
    table = table.iloc[np.argsort(-np.nan_to_num(np.abs(table["log_sensitivity"].to_numpy(float)), nan=-1.0),
                                  kind="stable")].reset_index(drop=True)
    for col in ("objective_minus_5pct", "first_order_minus_5pct", "objective_plus_5pct", "first_order_plus_5pct",
                "resolve_discrepancy"):
        table[col] = np.nan
    table["resolve_check"] = ""
    if pb.data_parameters and resolve_top > 0:
        _resolve_checks(pb, result, table, factor, objective, resolve_top, resolve_tolerance, **ipopt)
    return SensitivityReport(scene.name, name, unit, objective, table, pd.DataFrame(qrows), residual, note,
                             _exact_objective(result, factor))


LIMIT_STEP = 0.005
"""Relative move of a limit at which :func:`limit_move_check` re-solves the scene (issue 28: ±0.5 %)."""

LIMIT_ABS_TOLERANCE = 0.01
"""Absolute agreement [objective unit, e.g. um of PPTE] within which :func:`limit_move_check` counts a re-solved
change as the first-order one, whatever the relative miss (a change of a few nanometres is below the exact model's
resolution of a sub-micron optimum)."""


def limit_move_check(result: SceneResult, *, step: float = LIMIT_STEP, tolerance: float = RESOLVE_TOLERANCE,
                     abs_tolerance: float = LIMIT_ABS_TOLERANCE, every_limit: bool = False,
                     **solve: Any) -> pd.DataFrame:
    """Check the limits' sensitivities of a solved scene on the exact model: each active declared limit (every
    limit with ``every_limit``) moved by ``step`` (relative) either way, the scene re-solved warm from the optimum
    (``scene.build(initial=optimum, positions=optimum's)``: the same branch of optima, refined and polished like the
    first solve), and the change of the *exact* objective (the refinement's verified objective; the NLP's for a
    scene without one) compared with the reported sensitivity (:func:`sensitivity_report`: the multipliers, summed
    over the limit's load cases) times the move.

    Returns one row per (limit, side): ``limit`` (``quantity[target] (side)``, with its load cases), ``bound``,
    ``unit``, ``sensitivity`` (objective units per unit of the bound), ``active``, ``exact_objective`` (at the
    optimum), and per side ``exact_objective_minus`` / ``_plus`` (re-solved), ``first_order_minus`` / ``_plus``,
    then ``worst_miss`` (the larger absolute difference of re-solved and first-order change, objective units) and
    ``check``: ``"agrees"`` when each miss is within ``tolerance`` of the first-order change or ``abs_tolerance``,
    else what differs (a failed re-solve is named)."""
    check_range("step", step, 0.0, 0.5, low_inclusive=False)
    check_range("tolerance", tolerance, 0.0, None, low_inclusive=False)
    check_range("abs_tolerance", abs_tolerance, 0.0, None)
    built = _solved_build(result)
    scene = built.scene
    name, unit, factor = objective_meta(scene)
    f0 = _exact_objective(result, factor)
    sens = {r["name"]: r for r in _limit_rows(built, result, factor, f0, name, unit)}
    records = {r["label"]: r for r in built.records if r["role"] == "limit"}
    rows = []
    for j, lim in enumerate(scene.limits):
        kind = quantity_kind(lim.quantity)
        for side in ("lower", "upper"):
            bound = getattr(lim, side)
            if bound is None or kind.shape == "named":
                continue
            mine = [sens[f"{label} ({side})"] for label, rec in records.items()
                    if rec["quantity"] == lim.quantity and rec["target"] == lim.target
                    and (lim.load_cases is None or rec["load_case"] in lim.load_cases)
                    and f"{label} ({side})" in sens]
            s = float(sum(r["sensitivity"] for r in mine))
            active = any(r["active"] for r in mine)
            if not (active or every_limit):
                continue
            where = "" if lim.load_cases is None else f" @ {'/'.join(lim.load_cases)}"
            row = {"limit": f"{lim.quantity}[{lim.target}] ({side}){where}", "bound": float(bound),
                   "unit": kind.unit, "sensitivity": s, "active": active, "exact_objective": f0}
            worst, causes = 0.0, []
            for sign, tag in ((-1.0, "minus"), (1.0, "plus")):
                moved = bound * (1.0 + sign * step)
                predicted = s * (moved - bound)
                row[f"first_order_{tag}"] = f0 + predicted
                limits = [dataclasses.replace(lim, **{side: moved}) if k == j else other
                          for k, other in enumerate(scene.limits)]
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", InitialGuessWarning)
                        again = dataclasses.replace(scene, limits=limits).build(
                            initial=result.values, positions=result.positions).solve(**solve)
                except GearoptError as exc:
                    row[f"exact_objective_{tag}"] = np.nan
                    causes.append(f"re-solve at {sign * 100 * step:+g} % failed ({type(exc).__name__})")
                    continue
                got = _exact_objective(again, factor)
                row[f"exact_objective_{tag}"] = got
                miss = abs((got - f0) - predicted)
                worst = max(worst, miss)
                if miss > max(tolerance * abs(predicted), abs_tolerance):
                    causes.append(f"at {sign * 100 * step:+g} % the exact optimum moved by {got - f0:.4g} "
                                  f"{unit} against {predicted:.4g} {unit} first order")
            row["worst_miss"] = worst
            row["check"] = "; ".join(causes) if causes else "agrees"
            rows.append(row)
    return pd.DataFrame(rows, columns=["limit", "bound", "unit", "sensitivity", "active", "exact_objective",
                                       "exact_objective_minus", "first_order_minus", "exact_objective_plus",
                                       "first_order_plus", "worst_miss", "check"])


def _solved_build(result):
    """The build that solved ``result``; a :class:`GearoptInputError` when it is not a solved scene's result."""
    built = getattr(result, "source", None)
    if not isinstance(result, SceneResult) or built is None:
        raise GearoptInputError(f"result={type(result).__name__} must be the SceneResult of a solved scene "
                                f"(scene.build().solve())")
    return built


def _exact_objective(result: SceneResult, factor: float) -> float:
    """The objective of a solved scene on the exact model (the refinement's verified objective, else the NLP's), in
    the objective quantity's unit."""
    ref = getattr(result, "refinement", None)
    verified = ref.attrs.get("verified_objective") if ref is not None else None
    value = verified if verified is not None and np.isfinite(verified) else float(result.solve.objective)
    return float(value) * factor


def _resolve_checks(pb, result: SceneResult, table: pd.DataFrame, factor: float, objective: float, top: int,
                    tolerance: float, **ipopt: Any) -> None:
    """Re-solve the parametric scene with each of the ``top`` most influential data at ±:data:`RESOLVE_STEP` (from
    the optimum, the datum restored after), write the objective beside the first-order estimate and flag the
    entries whose re-solve disagrees by more than ``tolerance`` (:func:`sensitivity_report`)."""
    p = pb.problem
    base_active = _active_limits(result.solve)
    base_values = {n: np.asarray(v, dtype=float) for n, v in result.solve.values.items() if n in p.variable_names}
    rows = table[(table["kind"] == "parameter") & table["active"]].head(top)
    for i, r in rows.iterrows():
        entry = pb.data_parameters[r["name"]]
        base = entry["value"]
        worst, causes = 0.0, []
        for sign, tag in ((-1.0, "minus"), (1.0, "plus")):
            p.set_parameter(r["name"], base * (1.0 + sign * RESOLVE_STEP))
            estimate = objective + r["sensitivity"] * base * sign * RESOLVE_STEP
            table.loc[i, f"first_order_{tag}_5pct"] = estimate
            try:
                solved = _warm_resolve(p, result, **ipopt)   # the optimum's branch, as the estimate is
            except GearoptError as exc:                          # a failed re-solve leaves NaN and says why
                causes.append(f"re-solve at {sign * 100 * RESOLVE_STEP:+g} % failed ({type(exc).__name__})")
                continue
            got = float(solved.objective) * factor
            table.loc[i, f"objective_{tag}_5pct"] = got
            change, first_order = got - objective, estimate - objective
            discrepancy = abs(change - first_order) / max(abs(first_order), 1e-9 * max(abs(objective), 1.0))
            worst = max(worst, discrepancy)
            if discrepancy > tolerance:
                causes.append(_disagreement_cause(sign, discrepancy, base_active, _active_limits(solved),
                                                  base_values, solved))
        p.set_parameter(r["name"], base)
        table.loc[i, "resolve_discrepancy"] = worst
        table.loc[i, "resolve_check"] = "; ".join(causes) if causes else "agrees"


def _active_limits(solved) -> set[str]:
    """Names of the constraints active at a solve (declared names, not elements)."""
    cons = solved.constraints
    return set(cons.loc[cons["active"], "base"])


def _disagreement_cause(sign: float, discrepancy: float, before: set[str], after: set[str], values: dict,
                        solved) -> str:
    """Why a re-solve at ``sign`` x :data:`RESOLVE_STEP` differs from the first-order estimate by ``discrepancy``."""
    step = f"at {sign * 100 * RESOLVE_STEP:+g} % the re-solve differs by {100 * discrepancy:.0f} %"
    gained, lost = sorted(after - before), sorted(before - after)
    if gained or lost:
        what = ", ".join(([f"{n} became active" for n in gained] if gained else [])
                         + ([f"{n} became inactive" for n in lost] if lost else []))
        return f"{step}: active-set change ({what}); the sensitivity holds on one side only"
    moved = max((float(np.max(np.abs(np.asarray(solved.values[n], dtype=float) - v) / np.maximum(np.abs(v), 1.0)))
                 for n, v in values.items()), default=0.0)
    return (f"{step} with the same active set: the objective curves over the step or another optimum lies near "
            f"(the design moved by up to {100 * moved:.1f} % of its values)")


def objective_meta(scene) -> tuple[str, str, float]:
    """Name, unit and factor from the NLP objective to the objective quantity (one objective: the NLP minimises
    ``weight / scale * (±quantity)``; several: the NLP's weighted sum itself, factor 1)."""
    if len(scene.objectives) != 1:
        return "objective", "", 1.0
    obj = scene.objectives[0]
    kind = quantity_kind(obj.quantity)
    scale = obj.scale or kind.scale
    return f"{obj.quantity}[{obj.target}]", kind.unit, (scale / obj.weight) * (1.0 if obj.sense == "min" else -1.0)


def _row(name, kind, value, unit, sens, objective, active, of, of_unit) -> dict[str, Any]:
    log = sens * value / objective if objective != 0.0 else np.nan
    return {"name": name, "kind": kind, "value": float(value), "unit": unit, "sensitivity": float(sens),
            "log_sensitivity": float(log), "active": bool(active), "of": of, "of_unit": of_unit}


def _limit_rows(built, result: SceneResult, factor: float, objective: float, of: str, of_unit: str) -> list:
    """Scene limits and design-variable bounds from the solve's multipliers (d objective / d bound)."""
    cons = result.solve.constraints
    rows = []
    seen = set()
    for r in built.records:
        if r["role"] != "limit" or r["label"] in seen:
            continue
        seen.add(r["label"])
        block = cons[cons["base"] == r["label"]]
        if block.empty:          # a constant limit, never handed to the solver
            continue
        kind = r["kind"]
        mults = block["multiplier"].to_numpy(float)
        two_sided = r["lower"] is not None and r["upper"] is not None
        for side in ("lower", "upper"):
            bound = r[side]
            if bound is None:
                continue
            # the NLP minimises: an active lower bound has a positive multiplier, an active upper one a negative
            mult = float(mults.sum()) if not two_sided else float(
                mults[mults > 0].sum() if side == "lower" else mults[mults < 0].sum())
            # a squared quantity is imposed as elements <= bound^2: d f / d bound = multiplier * 2 bound
            s = mult * (2.0 * bound if kind.squared else 1.0) * factor
            unit = kind.unit if kind.shape != "named" else ""
            rows.append(_row(f"{r['label']} ({side})", "limit", bound, unit, s, objective,
                             bool(block["active"].any()) and (not two_sided or mult != 0.0), of, of_unit))
    design = {f"{v.target}.{v.name}" for v in built.scene.variables}
    for v in result.solve.variables.itertuples(index=False):
        if v.base not in design:
            continue
        for side in ("lower", "upper"):
            bound = getattr(v, side)
            if not np.isfinite(bound):
                continue
            on_side = abs(v.value - bound) <= 1e-6 * v.scale
            s = float(v.multiplier) * factor if on_side else 0.0
            rows.append(_row(f"{v.name} ({side} bound)", "limit", bound, v.unit, s, objective, on_side and s != 0,
                             of, of_unit))
    return rows


#: Relative agreement of the re-solved and the given objective below which a moved design is the same optimum.
FLAT_OBJECTIVE_RTOL = 1e-6


def _warm_resolve(p, result: SceneResult, **ipopt):
    """Solve the parametric problem ``p`` warm from the NLP optimum of ``result``: its variables and multipliers
    (:meth:`~gearopt.design.scene.SceneResult.warm_start_point`) with :data:`~gearopt.nlp.WARM_START_IPOPT` under
    ``ipopt``. A re-solve from the primal point alone starts Ipopt's barrier far from the optimum's complementarity
    and can leave for another local optimum of a multimodal scene (measured on the packaged data's root-mesh
    tip-relief scene: 47 iterations to a worse optimum, against 3 back to the same one warm)."""
    for name, value in result.solve.values.items():
        if name in p.variable_names:
            p.set_initial(name, value)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InitialGuessWarning)
        return p.solve(warm_start=result.warm_start_point(), **{**WARM_START_IPOPT, **ipopt})


def _resolve_at(pb, result: SceneResult, **ipopt):
    """Re-solve the parametric build warm from the result's NLP optimum (:func:`_warm_resolve`). Returns the solve
    and a note: empty when it lands on the same design; when design variables move at the same objective (a flat
    optimum: the objective does not depend on them there), the note names them -- the objective's data
    sensitivities still hold (they are the Lagrangian's parameter gradient, the envelope theorem), the quantities'
    are the minimum-norm KKT solution. A re-solve that changes the objective is another optimum: a
    :class:`GearoptInputError`. Where the exact polish moved the reported design off the NLP's optimum, the note
    says by how much (the sensitivities are the NLP optimum's)."""
    solved = _warm_resolve(pb.problem, result, **{"tol": 1e-10, **ipopt})
    scales = result.solve.variables.set_index("name")["scale"]
    optimum = {name: float(np.asarray(result.solve.values[name]).ravel()[0]) for name in result.values}
    moved = []
    for name, value in optimum.items():
        new = float(np.asarray(solved.values[name]).ravel()[0])
        if abs(new - value) > 1e-4 * float(scales.loc[name]):
            moved.append(f"{name} {value:.6g} -> {new:.6g}")
    polish = _polish_note(result, optimum, scales)
    if not moved:
        return solved, polish
    f0, f1 = float(result.solve.objective), float(solved.objective)
    if abs(f1 - f0) > FLAT_OBJECTIVE_RTOL * max(abs(f0), 1e-12):
        raise GearoptInputError(f"the parametric re-solve moved {', '.join(moved)} and the objective from {f0:.8g} "
                                f"to {f1:.8g}: the result is not a regular local optimum of its scene (limit: "
                                f"variables within 1e-4 x their scale, or the objective within "
                                f"{FLAT_OBJECTIVE_RTOL:g} relative)")
    flat = (f"flat optimum: {', '.join(moved)} at the same objective ({f0:.8g}); the objective's data "
            f"sensitivities hold (envelope theorem), the quantities' are minimum-norm")
    return solved, "; ".join(n for n in (flat, polish) if n)


def _polish_note(result: SceneResult, optimum: dict, scales) -> str:
    """Where the reported design is not the NLP's optimum (the exact polish moved it), which variables moved and
    how far in units of their scale; empty otherwise."""
    moved = {name: (optimum[name], float(value)) for name, value in result.values.items()
             if abs(float(value) - optimum[name]) > 1e-4 * float(scales.loc[name])}
    if not moved:
        return ""
    worst = max(abs(b - a) / float(scales.loc[n]) for n, (a, b) in moved.items())
    return (f"sensitivities of the NLP's optimum; the exact polish moved the reported design from it "
            f"({', '.join(f'{n} {a:.6g} -> {b:.6g}' for n, (a, b) in moved.items())}; up to {worst:.3g} x a "
            f"variable's scale)")


def _quantity_rows(pb, solved, sens, names: list[str]) -> list[dict[str, Any]]:
    """d quantity / d datum of every reported quantity (the element that sets a largest/smallest value)."""
    opti = pb.problem.opti
    rows = []
    table = pb.quantity_table(solved)
    for rec, (_, qrow) in zip(pb.records, table.iterrows()):
        kind, expr = rec["kind"], rec["expr"]
        if kind.shape == "named" or isinstance(expr, (int, float, np.floating)):
            continue
        values = np.atleast_1d(np.asarray(solved.value(expr), dtype=float)).ravel()
        d = sens.expression_derivative(opti, expr)
        if kind.shape == "ppte":
            grad = d[int(np.argmax(values))] - d[int(np.argmin(values))]
        elif kind.shape in ("max", "min"):
            i = int(np.argmax(values) if kind.shape == "max" else np.argmin(values))
            grad = d[i] / (2.0 * np.sqrt(values[i])) if kind.squared else d[i]
        else:
            grad = d[0]
        label = rec["label"]
        for j, pname in enumerate(names):
            value = float(qrow["value"])
            pval = pb.data_parameters[pname]["value"]
            rows.append({"quantity": label, "value": value, "unit": kind.unit, "parameter": pname,
                         "parameter_value": pval, "sensitivity": float(grad[j]),
                         "log_sensitivity": float(grad[j] * pval / value) if value != 0 else np.nan})
    return rows


__all__ = ["sensitivity_report", "SensitivityReport", "objective_meta", "limit_move_check", "LIMIT_STEP",
           "LIMIT_ABS_TOLERANCE"]
