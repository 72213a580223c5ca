"""Trade-off fronts of a scene: the scene's objective against a second quantity, by ε-constraint continuation.

:func:`pareto_front` finds the two ends -- the scene's own optimum (the quantity free) and the best value of the
quantity (then the best objective at that value: a lexicographic end, so both ends are Pareto optimal) -- and walks
from one to the other with ``quantity <= ε`` (``>=`` for a quantity to be made large) on an ε grid, each point
warm-started from its neighbour (:mod:`gearopt.studies.epsilon`). With ``refine`` half the points are spaced evenly
in ε and the rest are put, round by round, into the gaps of the front with the largest hypervolume gap: the
rectangle spanned by two neighbours in the two objectives normalised by their ranges, an upper bound of the
hypervolume a point between them can add (large where the front bends, small along a flat or a steep stretch). On
the benchmark scene this reaches NSGA-II's final hypervolume with 17 points where the widest arc-length gap needed
33 (``benchmarks/bench_studies.py``). A point whose solve fails stays in the table with
its typed failure (``status`` = the error class, ``error``, ``worst_violated``); the study goes on.

Segments of the ε grid and the refinement points are tasks of the :mod:`gearopt.studies.executor`; ``segments``
fixes the split, so the front is the same whichever executor runs it.

Example::

    front = pareto_front(scene, "max_contact_stress_MPa", "pinion-wheel", points=9)
    front.table[[front.quantity_column, front.objective_column, "status"]]
    front.plot()
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import pandas as pd

from ..design.scene import Scene
from ..design.scene_terms import quantity_kind
from ..errors import GearoptInputError, SolveError
from .epsilon import FrontSpec, epsilon_model, failure_record
from .executor import using_executor

OK = "ok"
"""``status`` of a point that solved."""


@dataclass
class ParetoFront:
    """A traced front. ``table``: one row per point, ordered from the objective's optimum to the quantity's
    (``point``, ``epsilon``, ``status``, ``error``, ``worst_violated``, ``iterations``, ``solve_time_s``, the two
    front columns ``objective_column`` and ``quantity_column``, ``front_slope`` (d objective / d ε from the ε
    multiplier, objective units per quantity unit; 0 at the objective's optimum, NaN at the quantity's), every
    design variable (``"target.name"``), every scene quantity per load case (``"quantity[target]@case"``) with
    ``margin:`` and the multiplier of every limit ``multiplier:``). ``ends``: the two single-objective optima
    (``objective``, ``quantity``); ``units`` of the two front columns; ``variables``: the design variables'
    columns."""

    scene: str
    quantity: str
    target: str
    sense: str
    objective_column: str
    quantity_column: str
    table: pd.DataFrame
    ends: dict[str, dict[str, float]] = field(default_factory=dict)
    units: dict[str, str] = field(default_factory=dict)
    variables: list[str] = field(default_factory=list)
    limit: float | None = None          # the scene's own limit on the quantity (the requirement the ε replaced)

    @property
    def feasible(self) -> pd.Series:
        """Per row: the point meets the scene's own limit on the quantity (the requirement the front's ε replaced;
        True for every point when the scene had none)."""
        q = self.table[self.quantity_column].astype(float)
        if self.limit is None:
            return pd.Series(True, index=self.table.index)
        return (q >= self.limit * (1 - 1e-9)) if self.sense == "max" else (q <= self.limit * (1 + 1e-9))

    def with_verification(self, verification: pd.DataFrame) -> "ParetoFront":
        """The front with the columns of :func:`~gearopt.studies.front_check.verify_front` merged by point:
        ``verified`` (the exact LTCA agrees with the smooth model at the re-solved point), ``exact_objective``
        (the verified design's exact objective) and ``verification``."""
        cols = [c for c in ("verified", "exact_objective", "verification") if c in verification.columns]
        table = self.table.drop(columns=[c for c in cols if c in self.table.columns])
        table = table.merge(verification[["point"] + cols], on="point", how="left")
        table["verified"] = table["verified"].fillna(False).astype(bool)
        return replace(self, table=table)

    @property
    def solved(self) -> pd.DataFrame:
        """The rows that solved."""
        return self.table[self.table["status"] == OK]

    def knee(self) -> pd.Series:
        """The solved point farthest from the straight line between the two ends, both axes normalised by their
        ranges (the point where the trade-off bends most), among the points that meet the scene's own limit on the
        quantity (all solved points when fewer than two do)."""
        s = self.solved
        inside = s[self.feasible.loc[s.index]]
        s = inside if len(inside) >= 2 else s          # the knee of the front that meets the requirement
        x, y = _normalised(s[self.quantity_column].to_numpy(float), s[self.objective_column].to_numpy(float))
        dist = np.abs((x[-1] - x[0]) * (y[0] - y) - (x[0] - x) * (y[-1] - y[0])) / max(
            math.hypot(x[-1] - x[0], y[-1] - y[0]), 1e-300)
        return s.iloc[int(np.argmax(dist))]

    def plot(self, ax=None, *, annotate: bool = True):
        """The front (objective against quantity), failed points marked at their ε, the knee annotated with its
        design. Returns the matplotlib Figure."""
        import matplotlib.pyplot as plt

        if ax is None:
            fig, ax = plt.subplots(figsize=(6.5, 5.5))
        else:
            fig = ax.figure
        solved, bad = self.solved, self.table[self.table["status"] != OK]
        ok = self.feasible.loc[solved.index]
        s, beyond = solved[ok], solved[~ok]
        ax.plot(s[self.quantity_column], s[self.objective_column], "o-", color="C0",
                label="ε-constraint front (smooth model)")
        if len(beyond):
            ax.plot(beyond[self.quantity_column], beyond[self.objective_column], "o", mfc="none", color="0.6",
                    label=f"beyond the requirement ({len(beyond)})")
        if self.limit is not None:
            ax.axvline(self.limit, color="C3", lw=1.0, ls="--", label=f"requirement {self.limit:g}")
        if "exact_objective" in solved.columns:
            v = solved[solved["verified"]]
            ax.plot(v[self.quantity_column], v["exact_objective"], "x", color="k", ms=7,
                    label=f"exact LTCA of the verified points ({len(v)} of {len(solved)})")
        ends = solved.iloc[[0, -1]]
        ax.plot(ends[self.quantity_column], ends[self.objective_column], "s", color="C3", ms=8, mfc="none",
                label="single-objective optima")
        for _, row in bad.iterrows():
            ax.axvline(row["epsilon"], color="C1", lw=0.8, ls=":")
        if len(bad):
            ax.plot([], [], color="C1", ls=":", label=f"failed points ({len(bad)})")
        if annotate and len(solved) >= 3:
            k = self.knee()
            text = "\n".join(_variable_label(n, float(k[n])) for n in self.variables)
            rising = s[self.objective_column].iloc[-1] > s[self.objective_column].iloc[0]
            corner = (0.03, 0.97) if rising == (s[self.quantity_column].iloc[-1] > s[self.quantity_column].iloc[0]) \
                else (0.97, 0.97)            # the empty upper corner, away from the front
            ax.annotate(f"knee\n{text}", (k[self.quantity_column], k[self.objective_column]), xytext=corner,
                        textcoords="axes fraction", ha="left" if corner[0] < 0.5 else "right", va="top", fontsize=7,
                        arrowprops={"arrowstyle": "->", "color": "0.4"})
        ax.set_xlabel(_axis(self.quantity_column, self.units.get(self.quantity_column, "")))
        ax.set_ylabel(_axis(self.objective_column, self.units.get(self.objective_column, "")))
        ax.set_title(f"{self.scene}: trade-off front")
        ax.grid(alpha=0.3)
        # below the axes: the knee's design annotation takes the empty upper corner inside
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
        fig.tight_layout()
        return fig


def pareto_front(scene: Scene, quantity: str, target: str, points: int = 11, executor: Any = "serial", *,
                 sense: str | None = None, refine: bool = True, segments: int = 1, starts: int = 1,
                 workers: int | None = None, progress: bool | None = None, **ipopt: Any) -> ParetoFront:
    """The front between the scene's objective and ``quantity`` of ``target`` (see the module docstring).

    Args:
        scene: a :class:`Scene` with its objective(s); a limit it sets on ``quantity`` is replaced by the front's ε.
        quantity, target: the second quantity (scene vocabulary) and its mesh/joint/gear; over several load cases
            the front bounds its largest value (smallest for ``sense="max"``).
        points: points of the front including the two ends (>= 3).
        executor: ``"serial"``, ``"processes"``, ``"dask"``, a ``dask.distributed.Client`` or an Executor.
        sense: ``"min"`` (the quantity is to be small) or ``"max"``; default: from the scene's limit on it (upper ->
            min), else from its shape (a largest value / PPTE -> min, a smallest value -> max, a scalar -> min).
        refine: put half the interior points where the front bends most, by hypervolume gap (else all evenly in
            ε).
        segments: contiguous pieces of the first ε grid run as separate tasks (each continued from the objective's
            optimum); the front does not depend on the executor.
        starts: solves of each end (the declared start and ``starts - 1`` Latin-hypercube starts of the design
            variables, seed 0; the best optimum): for scenes with several local optima.
        **ipopt: Ipopt options of every solve.

    A scene with ``ltca_options={"approach": "lifted"}`` (each position's contact approach an NLP variable) gives
    the front cheaper iterations; the lifted and the default nested form have the same optima but may reach
    different local optima of a multimodal scene.

    Raises:
        GearoptInputError: a quantity not in the vocabulary or not of the scene's targets, ``points`` < 3, a bad
            ``sense``, a quantity the design cannot change, or a front whose two ends coincide (the quantity does
            not conflict with the objective).
        SolveError: an end of the front does not solve (interior failures are recorded, not raised).
    """
    if not isinstance(scene, Scene):
        raise GearoptInputError(f"scene={scene!r} must be a gearopt Scene")
    kind = quantity_kind(quantity)
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or points < 3:
        raise GearoptInputError(f"points={points!r} must be an integer >= 3 (the two ends and one inside)")
    for name, v in (("segments", segments), ("starts", starts)):
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise GearoptInputError(f"{name}={v!r} must be an integer >= 1")
    sense = _sense(scene, quantity, target, kind, sense)
    spec = FrontSpec(scene, quantity, target, sense, dict(ipopt))
    model = epsilon_model(spec)
    ends, end_rows = _ends(model, int(starts))
    q_a, q_b = ends["objective"]["quantity"], ends["quantity"]["quantity"]
    if abs(q_a - q_b) <= 1e-6 * max(abs(q_a), abs(q_b), kind.scale):
        raise GearoptInputError(
            f"the front of {quantity!r} of {target!r} has coinciding ends ({quantity} = {q_a:.6g} {kind.unit} at "
            f"the objective's optimum and at its own): it does not conflict with the objective -- limit: the ends "
            f"must differ")
    rows = list(end_rows)
    interior = points - 2
    first = interior if not refine else max(1, interior // 2)
    grid = list(np.linspace(q_a, q_b, first + 2)[1:-1])
    chunks = [list(c) for c in np.array_split(np.asarray(grid), min(segments, len(grid))) if len(c)]
    # the first grid starts from the objective's optimum by its values only: that end's multipliers (front
    # constraint loose) led the nested contact form to a worse local optimum of the first points (measured)
    a_values = end_rows[0]["_values"]
    with using_executor(executor, workers=workers, progress=progress) as ex:
        for part in ex.map(run_segment, [(spec, chunk, a_values) for chunk in chunks], desc="front"):
            rows.extend(part)
        for _ in range(12):
            missing = points - len(rows)
            if missing <= 0:
                break
            tasks = _refinement_tasks(spec, rows, missing, sense)
            if not tasks:
                break
            for part in ex.map(run_segment, tasks, desc="front refinement"):
                rows.extend(part)
    return _front(model, rows, ends)


def run_segment(task: tuple) -> list[dict[str, Any]]:
    """Executor task ``(spec, eps_list, start[, warm_point])``: the ε values of one piece of a front, the first
    started from ``start`` (a neighbour's variable values) -- warm from ``warm_point`` (the neighbour's solve's
    :class:`~gearopt.nlp.WarmStartPoint`) where given --, the next ones warm-started from the previous point.
    Failures are recorded."""
    spec, eps_list, start = task[:3]
    model = epsilon_model(spec)
    rows, previous = [], start
    warm = task[3] if len(task) > 3 and task[3] is not None else False
    for eps in eps_list:
        rows.append(_point(model, float(eps), previous, warm))
        warm = rows[-1]["status"] == OK
        if warm:
            previous = rows[-1]["_values"]
    return rows


# -- internals --------------------------------------------------------------------------------------------------


def _sense(scene: Scene, quantity: str, target: str, kind, sense: str | None) -> str:
    if sense is not None:
        if sense not in ("min", "max"):
            raise GearoptInputError(f"sense={sense!r} must be 'min' or 'max'")
        return sense
    for lim in scene.limits:
        if (lim.quantity, lim.target) == (quantity, target):
            return "min" if lim.upper is not None else "max"
    return "max" if kind.shape == "min" else "min"


def _ends(model, starts: int) -> tuple[dict[str, dict[str, float]], list[dict[str, Any]]]:
    """The objective's optimum (front constraint loose) and the lexicographic optimum of the quantity."""
    a = model.solve(None, starts=starts)
    row_a = _record(model, a, None, warm=starts == 1)  # several starts: the last solve need not be the best
    b_only = model.solve(None, objective="quantity", start=a.values, starts=starts)
    q_b = model.quantity_value(b_only)
    slack = 1e-7 * max(abs(q_b), model.kind.scale)
    eps_b = q_b + slack if model.spec.sense == "min" else q_b - slack
    b = model.solve(eps_b, start=b_only.values)
    row_b = _record(model, b, eps_b)
    row_b["front_slope"] = np.nan      # ε at the quantity's own optimum: the constraint is degenerate there
    ends = {"objective": {"objective": row_a["_objective"], "quantity": row_a["_quantity"]},
            "quantity": {"objective": row_b["_objective"], "quantity": row_b["_quantity"]}}
    return ends, [row_a, row_b]


def _point(model, eps: float, start: dict[str, Any], warm) -> dict[str, Any]:
    """One ε point: warm-started (primal values and multipliers) from the previous solve when ``warm`` is True or
    from a neighbour's :class:`~gearopt.nlp.WarmStartPoint`, else from the neighbour's values ``start``; on failure
    one retry from ``start`` without multipliers."""
    try:
        return _record(model, model.solve(eps, warm=warm) if warm is not False else model.solve(eps, start=start),
                       eps)
    except SolveError as first:
        if warm:
            try:
                return _record(model, model.solve(eps, start=start), eps)
            except SolveError:
                pass
        row = {"epsilon": eps, **failure_record(first), "_values": None, "_objective": np.nan, "_quantity": np.nan}
        result = first.result
        if result is not None:
            row.update(iterations=result.iterations, solve_time_s=result.solve_time_s)
        return row


def _record(model, solved, eps: float | None, *, warm: bool = True) -> dict[str, Any]:
    """A point's row: status, front values, design variables, quantities, margins and limit multipliers; with
    ``warm`` (``solved`` is the model's last solve) also its warm-start point (``_warm``) for a neighbour."""
    built, spec = model.built, model.spec
    table = built.quantity_table(solved)
    row: dict[str, Any] = {"epsilon": np.nan if eps is None else eps, "status": OK, "error": "",
                           "worst_violated": "", "iterations": solved.iterations, "solve_time_s": solved.solve_time_s}
    for v in spec.scene.variables:
        name = f"{v.target}.{v.name}"
        row[name] = float(np.asarray(solved.values[name]).ravel()[0])
    for r in table.itertuples(index=False):
        label = f"{r.quantity}[{r.target}]" + (f"@{r.load_case}" if r.load_case else "")
        row[label] = r.value
        if r.role == "limit" and (r.quantity, r.target) != (spec.quantity, spec.target):
            row[f"margin:{label}"] = r.margin
            mult = solved.multipliers.get(label)
            if mult is not None:
                row[f"multiplier:{label}"] = float(np.sum(mult))
    objective, factor = _objective(spec.scene, table, solved)
    quantity = model.quantity_value(solved, table)
    mult = float(solved.multipliers["front.epsilon_limit"])
    slope = mult * (2.0 * eps if model.kind.squared and eps is not None else 1.0) * factor
    row.update(_objective=objective, _quantity=quantity, front_slope=slope if eps is not None else 0.0,
               _values={k: (np.array(v) if np.ndim(v) else float(v)) for k, v in solved.values.items()},
               _warm=model.problem.warm_start_point() if warm else None)
    return row


def _objective(scene: Scene, table: pd.DataFrame, solved) -> tuple[float, float]:
    """The objective in its quantity's unit (one objective: its largest/smallest/mean over the load cases) and the
    factor from the NLP's objective to it (the NLP minimises ``weight / scale * (±quantity)``)."""
    if len(scene.objectives) != 1:
        return float(solved.objective), 1.0
    obj = scene.objectives[0]
    kind = quantity_kind(obj.quantity)
    values = table[(table["role"] == "objective") & (table["quantity"] == obj.quantity)
                   & (table["target"] == obj.target)]["value"].to_numpy(float)
    if obj.aggregate == "mean":
        value = float(values.mean())
    else:
        value = float(values.max() if obj.sense == "min" else values.min())
    scale = obj.scale or kind.scale
    return value, (scale / obj.weight) * (1.0 if obj.sense == "min" else -1.0)


def _refinement_tasks(spec: FrontSpec, rows: list[dict[str, Any]], missing: int, sense: str) -> list:
    """New ε points in the gaps between solved neighbours with the largest normalised hypervolume gap (|Δx Δy|):
    one in each gap at least half the largest (at most ``missing``); the tasks of a round are independent (one
    executor batch)."""
    ok = sorted([r for r in rows if r["status"] == OK], key=lambda r: -r["_quantity"] if sense == "min"
                else r["_quantity"])
    tried = {round(float(r["epsilon"]), 12) for r in rows if not np.isnan(r["epsilon"])}
    if len(ok) < 2:
        return []
    x, y = _normalised(np.array([r["_quantity"] for r in ok]), np.array([r["_objective"] for r in ok]))
    gaps = np.abs(np.diff(x) * np.diff(y))
    if gaps.max() <= 1e-12:                           # a straight stretch in one objective: the widest arc gaps
        gaps = np.hypot(np.diff(x), np.diff(y))
    tasks = []
    for i in np.argsort(-gaps)[:missing]:
        if gaps[i] < max(1e-12, 0.5 * gaps.max()):    # this round: only the gaps at least half the largest
            break
        eps = 0.5 * (ok[i]["_quantity"] + ok[i + 1]["_quantity"])
        if round(eps, 12) in tried:
            continue
        tasks.append((spec, [eps], ok[i]["_values"], ok[i].get("_warm")))
    return tasks


def _front(model, rows: list[dict[str, Any]], ends: dict[str, dict[str, float]]) -> ParetoFront:
    spec, kind = model.spec, model.kind
    obj_col, unit_obj = _objective_column(spec.scene)
    q_col = f"{spec.quantity}[{spec.target}]"
    for r in rows:
        r[obj_col] = r.pop("_objective")
        r[q_col] = r.pop("_quantity")
        r.pop("_values", None)
        r.pop("_warm", None)
    table = pd.DataFrame(rows)
    order = np.where(table["status"] == OK, table[q_col], table["epsilon"])
    table = table.iloc[np.argsort(-order if spec.sense == "min" else order, kind="stable")].reset_index(drop=True)
    table.insert(0, "point", np.arange(len(table)))
    front_cols = ["point", "epsilon", "status", obj_col, q_col, "front_slope"]
    table = table[front_cols + [c for c in table.columns if c not in front_cols]]
    names = [f"{v.target}.{v.name}" for v in spec.scene.variables]
    units = {obj_col: unit_obj, q_col: kind.unit}
    own = [lim for lim in spec.scene.limits if (lim.quantity, lim.target) == (spec.quantity, spec.target)]
    limit = None
    if own:
        limit = own[0].lower if spec.sense == "max" else own[0].upper
    front = ParetoFront(spec.scene.name, spec.quantity, spec.target, spec.sense, obj_col, q_col, table, ends, units,
                        names, limit=None if limit is None else float(limit))
    front.table.insert(5, "meets_limit", front.feasible.to_numpy())
    return front


def _objective_column(scene: Scene) -> tuple[str, str]:
    if len(scene.objectives) != 1:
        return "objective", ""
    obj = scene.objectives[0]
    return f"{obj.quantity}[{obj.target}]", quantity_kind(obj.quantity).unit


def _normalised(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    def norm(v):
        span = np.ptp(v)
        return (v - v.min()) / span if span > 0 else np.zeros_like(v)
    return norm(x), norm(y)


def _variable_label(name: str, value: float) -> str:
    """``"pinion-wheel.tip_relief_1_um", 12.3`` -> ``"pinion-wheel tip relief 1 = 12.3 µm"`` (a figure's annotation)."""
    target, _, variable = name.rpartition(".")
    for suffix, unit in (("_start_roll_deg", " start roll [deg]"), ("_um", " [um]"), ("_deg", " [deg]"),
                         ("_mm", " [mm]"), ("_Nm", " [N*m]")):
        if variable.endswith(suffix):
            label, unit = variable[: -len(suffix)].replace("_", " ") + unit.split(" [")[0], unit.split(" [")[1][:-1]
            shown = _DISPLAY_UNITS.get(unit, unit)
            return f"{target} {label} = {value:.4g} {shown}".replace("  ", " ").strip()
    return f"{target} {variable.replace('_', ' ')} = {value:.4g}".strip()


_DISPLAY_UNITS = {"um": "µm", "C": "°C", "N*m": "N m", "kg*m^2": "kg m²"}


def _axis(name: str, unit: str) -> str:
    """Axis label of a front column: ``"ppte_um[pinion-wheel]"`` in ``um`` -> ``"ppte, pinion-wheel [µm]"``; a
    quantity of the vocabulary without a unit is a ratio (``[-]``); the weighted ``objective`` has none."""
    quantity, _, target = name.partition("[")
    if not target:
        return f"{name} [{_DISPLAY_UNITS.get(unit, unit)}]" if unit else name
    if unit and quantity.endswith(f"_{unit}"):
        quantity = quantity[:-len(unit) - 1]
    return f"{quantity.replace('_', ' ')}, {target.rstrip(']')} [{_DISPLAY_UNITS.get(unit, unit) or '-'}]"


__all__ = ["pareto_front", "ParetoFront", "run_segment", "OK"]
