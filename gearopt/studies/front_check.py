"""Exact-LTCA verification of a trade-off front: every solved point re-solved by the scene's own refinement.

:func:`~gearopt.studies.pareto.pareto_front` solves the ε-constraint NLP on the smooth LTCA at the scene's fixed
mesh positions and face slices; a minimiser then tends to put the TE's extremes between the samples, so the PPTE it
states can be too low (:mod:`gearopt.design.scene_refine`). :func:`verify_front` takes each solved point, fixes the
front's quantity at the point's value as a limit of the scene (``quantity <= value`` for a front that makes it
small, ``>=`` for one that makes it large), and solves that scene from the point's design with
:meth:`~gearopt.design.scene.BuiltScene.solve` -- the exact LTCA re-evaluates the optimum, adds the exact TE's peak
and trough positions (and face slices) and re-solves, at most ``max_refinements`` times, and returns the best
verified design. A point whose front solve failed, or whose verification solve fails, stays in the table with its
status. The solves are tasks of the :mod:`gearopt.executor` (one per point, results in point order).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping

import numpy as np
import pandas as pd

from ..design.scene import Limit, Scene
from ..design.scene_options import LTCAOptions
from ..design.scene_terms import quantity_kind
from ..errors import GearoptInputError, SolveError
from .epsilon import failure_record
from .executor import using_executor
from .pareto import OK, ParetoFront

SLACK = 1e-6
"""Relative slack of the verification limit (of the point's value, at least of the quantity's scale): the front
point itself is feasible for it."""


def verify_front(front: ParetoFront, scene: Scene, executor: Any = "serial", *,
                 ltca_options: Mapping[str, Any] | None = None, workers: int | None = None,
                 progress: bool | None = None, **ipopt: Any) -> pd.DataFrame:
    """One row per row of ``front.table`` (same order): the point's re-solve by the scene's exact-LTCA refinement
    (module docstring).

    Args:
        front: a front of ``scene`` (:func:`~gearopt.studies.pareto.pareto_front`).
        scene: the scene the front was traced on.
        ltca_options: overrides of the scene's ``ltca_options`` for the re-solves (e.g. ``{"max_refinements": 1,
            "helical_slices": 7}``; ``max_refinements: 0`` = one warm solve and the exact check only).
        **ipopt: Ipopt options of every re-solve.

    Returns a DataFrame: ``point``, ``status`` (the front's), ``verification`` (``"ok"``, the typed error's class
    name, or ``"front point failed"``), ``error``, ``verified`` (the exact and smooth PPTE agree within the
    refinement's tolerance), ``refinements``, ``exact_objective`` (for a single PPTE objective: the exact LTCA's PPTE
    of the verified design, aggregated like the objective, in um; else the verified objective of the NLP),
    ``smooth_objective`` (the NLP's value of it at the verified design), ``verified:<quantity column>`` (the front's
    quantity at the verified design: the exact LTCA's where it evaluates it), ``verified:<variable>`` per design
    variable and ``design_of_point``: each point reports the best verified design of the front that meets its bound
    (:func:`_exact_envelope`), so the exact objectives are monotone in the bound.
    """
    if not isinstance(front, ParetoFront):
        raise GearoptInputError(f"front={front!r} must be a ParetoFront (gearopt.studies.pareto_front)")
    if not isinstance(scene, Scene):
        raise GearoptInputError(f"scene={scene!r} must be a gearopt Scene")
    if front.scene != scene.name:
        raise GearoptInputError(f"front of scene {front.scene!r} does not belong to scene {scene.name!r}")
    options = {**dict(scene.ltca_options), **dict(ltca_options or {})}
    base = [lim for lim in scene.limits if (lim.quantity, lim.target) != (front.quantity, front.target)]
    tasks, rows = [], []
    for _, row in front.table.iterrows():
        if row["status"] != OK:
            rows.append({"point": int(row["point"]), "status": row["status"], "verification": "front point failed",
                         "error": row.get("error", ""), "verified": False})
            continue
        limit = _limit(front, float(row[front.quantity_column]))
        task_scene = replace(scene, limits=[*base, limit], ltca_options=options)
        values = {name: float(row[name]) for name in front.variables}
        tasks.append((len(rows), (task_scene, values, front.quantity, front.target, front.sense, dict(ipopt))))
        rows.append({"point": int(row["point"]), "status": OK})
    with using_executor(executor, workers=workers, progress=progress) as ex:
        results = ex.map(verify_point, [t for _, t in tasks], desc="front verification")
    for (i, _), result in zip(tasks, results):
        rows[i].update(result)
    bounds = dict(zip(front.table["point"].astype(int), front.table[front.quantity_column].astype(float)))
    tolerance = LTCAOptions.from_mapping(options).refinement.refine_stress_tolerance
    _exact_envelope(rows, bounds, front, scene, tolerance)
    return pd.DataFrame(rows)


def _exact_envelope(rows: list[dict], bounds: Mapping[int, float], front: ParetoFront, scene: Scene,
                    tolerance: float) -> None:
    """Each verified point reports the best verified design of the front that meets its bound (the exact envelope,
    issue 28: a front's exact values monotone in the bound). The re-solves run independently and may land on local
    optima of different quality; a design verified for a tighter bound meets a looser one too, so a point whose own
    re-solve is worse on the exact model than such a design reports that design (``design_of_point`` names the point
    it was verified for; itself otherwise). A design meets a bound when its verified front quantity does within
    ``tolerance`` (relative: the refinement's own acceptance of an exact lower limit). Only for a scene whose single
    objective is a PPTE to minimise (the exact objective the envelope compares)."""
    obj = _single_ppte(scene)
    column = f"verified:{front.quantity_column}"
    done = [r for r in rows if r.get("verification") == OK and np.isfinite(r.get("exact_objective", np.nan))]
    for r in done:
        r["design_of_point"] = r["point"]
    if obj is None or obj.sense != "min":
        return
    own = [dict(r) for r in done]

    def meets(design: dict, bound: float) -> bool:
        q = float(design[column])
        slack = tolerance * max(abs(bound), quantity_kind(front.quantity).scale)
        return q >= bound - slack if front.sense == "max" else q <= bound + slack
    for r, mine in zip(done, own):
        bound = bounds[int(r["point"])]
        best = min((d for d in own if d is mine or meets(d, bound)), key=lambda d: (d["exact_objective"],
                                                                                     d is not mine))
        if best is not mine:
            r.update({k: v for k, v in best.items() if k not in ("point", "status")})


def verify_point(task: tuple) -> dict[str, Any]:
    """Executor task: one point's re-solve (see :func:`verify_front`); failures are recorded."""
    scene, values, quantity, target, sense, ipopt = task
    try:
        result = scene.build(initial=values).solve(**ipopt)
    except SolveError as exc:
        rec = failure_record(exc)
        return {"verification": rec["status"], "error": rec["error"], "verified": False}
    ref = result.refinement
    q, ex = result.quantities, result.exact_check
    if quantity in ex.columns:      # the exact LTCA's value where it has one (the design may be polished on it)
        rows = ex.loc[ex["mesh"] == target, quantity].to_numpy(float)
    else:
        rows = q[(q["quantity"] == quantity) & (q["target"] == target)]["value"].to_numpy(float)
    out = {"verification": OK, "error": "",
           "verified": bool(ref.attrs.get("verified", False)) if ref is not None else False,
           "refinements": result.refinements,
           "exact_objective": _exact_objective(scene, result),
           "smooth_objective": _smooth_objective(scene, result),
           f"verified:{quantity}[{target}]": float(rows.max() if sense == "min" else rows.min())}
    out.update({f"verified:{name}": float(v) for name, v in result.values.items()})
    return out


def _limit(front: ParetoFront, value: float) -> Limit:
    slack = SLACK * max(abs(value), quantity_kind(front.quantity).scale)
    if front.sense == "min":
        return Limit(front.quantity, front.target, upper=value + slack)
    return Limit(front.quantity, front.target, lower=value - slack)


def _single_ppte(scene: Scene):
    if len(scene.objectives) == 1 and scene.objectives[0].quantity == "ppte_um":
        return scene.objectives[0]
    return None


def _aggregate(obj, values: np.ndarray) -> float:
    return float(values.mean() if obj.aggregate == "mean" else values.max())


def _exact_objective(scene: Scene, result) -> float:
    obj = _single_ppte(scene)
    if obj is None:
        ref = result.refinement
        return float(ref.attrs.get("verified_objective", np.nan)) if ref is not None else np.nan
    ex = result.exact_check
    rows = ex[ex["mesh"] == obj.target]
    if obj.load_cases is not None:
        rows = rows[rows["load_case"].isin(obj.load_cases)]
    return _aggregate(obj, rows["ppte_um"].to_numpy(float))


def _smooth_objective(scene: Scene, result) -> float:
    obj = _single_ppte(scene)
    if obj is None:
        return float(result.solve.objective)
    q = result.quantities
    rows = q[(q["role"] == "objective") & (q["quantity"] == "ppte_um") & (q["target"] == obj.target)]
    return _aggregate(obj, rows["value"].to_numpy(float))


__all__ = ["verify_front", "verify_point", "SLACK"]
