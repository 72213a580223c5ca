"""The continuous NLP of each admissible tooth-count candidate (Ipopt over the root gear's profile shift, warm
started along the candidates) and the ranking. Part of :mod:`gearopt.design.tooth_counts`."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any, Mapping

import casadi as ca
import numpy as np
import pandas as pd

from ... import numerics as nm
from ...errors import GearoptInputError, SolveError
from ...validation import check_range
from ...geometry.shift import shift_split_iso_tr_4467
from ...geometry.train import GearTrain
from ...nlp.problem import Problem
from .bonmin import bonmin_cross_check
from .candidates import (CandidateModel, OBJECTIVES, _train_with_teeth, _tree_order, gear_shift_limits,
                         mesh_sum_of_shifts)
from .enumeration import ToothCountEnumeration, _interval, enumerate_tooth_counts


# ----------------------------------------------------------------------------------------------------------------
# continuous NLP per candidate, ranking
# ----------------------------------------------------------------------------------------------------------------

@dataclass
class ToothCountStudy:
    """Result of :func:`tooth_count_study` (plain data except ``best``).

    ``table``: the admissible candidates ranked by ``objective_value`` (best first; failed solves last): the
    enumeration columns plus ``rank``, ``status`` (Ipopt's, or ``not_solved`` beyond ``top``), ``iterations``,
    ``solve_time_s``, ``start`` ("previous"/"precheck"/"iso"), ``start_root_shift``, ``objective_value`` (the
    smallest worst-case
    contact ratio, or the smallest tip thickness [mm]), ``profile_shift_<gear>``, ``worst_case_contact_ratio_<mesh>``,
    ``tip_thickness_<gear>_mm``, ``min_worst_case_contact_ratio``, ``min_tip_thickness_mm``, ``limiting`` (the
    meshes or gears that set the objective), ``active`` (active constraints and bounds), ``violated`` (names of
    violated constraints of a failed solve). ``rejected``: the enumeration's
    rejections. ``best``: the best candidate as a numeric :class:`GearTrain` (``None`` if no solve succeeded).
    ``solves``: one dict per NLP in solve order. ``bonmin``: :func:`bonmin_cross_check`'s result or ``None``.
    """

    objective: str
    table: pd.DataFrame
    rejected: pd.DataFrame
    best: GearTrain | None = field(repr=False)
    solves: list[dict]
    enumeration: ToothCountEnumeration = field(repr=False)
    bonmin: dict | None = None
    elapsed_s: float = 0.0


def _iso_start(train: GearTrain, teeth: Mapping[str, int], lo: float, hi: float) -> float:
    """The train's own ISO/TR 4467 split of the root mesh (lambda = root_shift_split), clipped into [lo, hi]."""
    mesh = train.meshes[train.root_mesh]
    z = (teeth[mesh.gears[0]], teeth[mesh.gears[1]])
    sum_x, _ = mesh_sum_of_shifts(train, train.root_mesh, z)
    split = train.root_shift_split if nm.is_numeric(train.root_shift_split) else 0.5
    x = shift_split_iso_tr_4467(z, sum_x, float(split))
    x_root = float(x[mesh.gears.index(train.root_gear)])
    return _clip(x_root, lo, hi)


def _clip(x: float, lo: float, hi: float) -> float:
    return float(min(max(x, lo), hi))


def _element_name(name: str, model: CandidateModel, objective_terms) -> str:
    """``limits[i]`` -> the margin's name, ``epigraph[i]`` -> the mesh/gear of objective term i."""
    base, _, rest = name.partition("[")
    if not rest:
        return name
    i = int(rest.rstrip("]"))
    if base == "limits":
        return model.margin_names[i]
    if base == "epigraph":
        return str(objective_terms[i])
    return name


def solve_candidate(enumeration: ToothCountEnumeration, teeth: Mapping[str, int], *,
                    objective: str = "max_min_worst_case_contact_ratio", root_shift_start: float | None = None,
                    root_shift_bounds: tuple[float, float] | None = None, verbose: bool = False, **ipopt) -> dict:
    """Optimise the root gear's profile shift of one candidate (module docstring, step 2); returns a plain dict
    (``status``, ``iterations``, ``solve_time_s``, ``root_profile_shift``, ``objective_value``, ``active``,
    ``violated``, ``error`` (the typed :class:`SolveError` or ``None``)). ``root_shift_start`` defaults to the
    ISO/TR 4467 split; ``root_shift_bounds`` to the candidate's admissible interval."""
    if objective not in OBJECTIVES:
        raise GearoptInputError(f"objective={objective!r} must be one of {OBJECTIVES}")
    train = enumeration.train
    model = enumeration.model(teeth)
    if root_shift_bounds is None:
        sums = {m: mesh_sum_of_shifts(train, m, tuple(teeth[g] for g in train.meshes[m].gears))[0]
                for m in train.meshes}
        limits = {teeth[g]: gear_shift_limits(train, teeth[g],
                                              iso_tr_4467_limits=enumeration.limits["iso_tr_4467_limits"])
                  for g in train.gears}
        lo, hi = _interval(train, _tree_order(train), teeth, sums, limits)[:2]
    else:
        lo, hi = root_shift_bounds
    if lo > hi:
        lo = hi = 0.5 * (lo + hi)  # no admissible split: Ipopt reports the violated limits at the compromise
    x0 = _iso_start(train, teeth, lo, hi) if root_shift_start is None else _clip(root_shift_start, lo, hi)
    label = "/".join(str(teeth[g]) for g in train.gears)
    p = Problem(name=f"tooth counts {label}")
    x = p.variable(f"{train.root_gear}:profile_shift", init=x0, lower=lo, upper=hi, scale=0.5)
    margins, eps, tips = model.function(x)
    # one vector constraint (declaring ~60 scalar ones costs more than the solve); element i is margin_names[i]
    p.subject_to("limits", margins, lower=0.0, source="gearopt.design.tooth_counts")
    start = model.evaluate(x0)
    m = float(train.rack.module_mm)
    if objective == "max_min_worst_case_contact_ratio":
        terms, names, scale, unit = eps, model.meshes, 1.0, ""
        t0 = float(start["worst_case_contact_ratio"].min())
    else:
        terms, names, scale, unit = tips, model.gears, m, "mm"
        t0 = float(start["tip_thickness_mm"].min())
    t = p.variable(objective, init=t0, scale=scale, unit=unit)
    p.subject_to("epigraph", terms - t, lower=0.0, scale=scale, unit=unit, source="gearopt.design.tooth_counts")
    p.maximize(t, scale=scale)
    options = {"bound_relax_factor": 0.0, **ipopt}
    try:
        res = p.solve(verbose=verbose, **options)
        err = None
    except SolveError as exc:
        res, err = exc.result, exc
    out = {"teeth": dict(teeth), "status": res.status if res is not None else getattr(err, "status", "error"),
           "iterations": int(res.iterations) if res is not None else -1,
           "solve_time_s": float(res.solve_time_s) if res is not None else float("nan"),
           "start_root_shift": x0, "root_shift_bounds": (lo, hi), "error": err,
           "violated": [_element_name(v.name, model, names) for v in err.violated] if err is not None else [],
           "root_profile_shift": float(res.values[f"{train.root_gear}:profile_shift"]) if res is not None else None,
           "objective_value": float(res.values[objective]) if err is None else float("nan"),
           "active": [], "limiting": []}
    if err is None:
        active = [str(n) for n in res.constraints.loc[res.constraints["active"], "name"]]
        out["active"] = [_element_name(n, model, names) for n in active if not n.startswith("epigraph")]
        out["limiting"] = [_element_name(n, model, names) for n in active if n.startswith("epigraph")]
        x_opt, tol = out["root_profile_shift"], 1e-6
        if hi > lo and x_opt <= lo + tol:
            out["active"].append(f"{train.root_gear}:profile_shift at its lower bound {lo:.6g}")
        elif hi > lo and x_opt >= hi - tol:
            out["active"].append(f"{train.root_gear}:profile_shift at its upper bound {hi:.6g}")
    return out


STARTS = ("previous", "precheck", "iso")


def solve_chain(task: tuple) -> list[dict]:
    """Executor task of :func:`tooth_count_study`: the candidates of one piece in order, each warm-started from the
    previous optimum of the piece when ``start == "previous"`` (the first at its ISO/TR 4467 split). Returns the
    :func:`solve_candidate` dicts plus ``start``, the typed error replaced by its message (plain data)."""
    enumeration, chunk, objective, start, verbose = task
    out, previous = [], None
    for _, teeth, bounds, x0, kind in chunk:
        if start == "previous" and previous is not None:
            x0, kind = previous, "previous"
        r = solve_candidate(enumeration, teeth, objective=objective, root_shift_start=x0, root_shift_bounds=bounds,
                            verbose=verbose)
        r["start"] = kind
        if r["error"] is None:
            previous = r["root_profile_shift"]
        else:
            r["error"] = str(r["error"])
        out.append(r)
    return out


def _bounds(n: int, pieces: int) -> list[tuple[int, int]]:
    """Contiguous index ranges of ``n`` items in ``pieces`` near-equal pieces (numpy's array_split sizes)."""
    if n == 0:
        return []
    sizes = [len(a) for a in np.array_split(np.arange(n), pieces)]
    ends = np.cumsum(sizes)
    return [(int(e - k), int(e)) for e, k in zip(ends, sizes)]


def tooth_count_study(train: GearTrain, *, objective: str = "max_min_worst_case_contact_ratio",
                      top: int | None = None, start: str = "previous", bonmin: bool = False,
                      enumeration: ToothCountEnumeration | None = None, verbose: bool = False,
                      executor: Any = "serial", segments: int = 1, workers: int | None = None,
                      progress: bool | None = None, **enumerate_options) -> ToothCountStudy:
    """Enumerate (unless ``enumeration`` is given), optimise each admissible candidate, rank (module docstring).

    Args:
        train: the train; ``enumerate_options`` go to :func:`enumerate_tooth_counts`.
        objective: one of :data:`OBJECTIVES` (smallest worst-case transverse contact ratio of all meshes, or
            smallest normal tip thickness of all gears [mm], maximised).
        top: solve only the ``top`` candidates with the best precheck value of the objective (the others get
            status ``not_solved``); ``None``: all.
        start: initial root shift of each NLP: ``"previous"`` (warm start: the previous candidate's optimum,
            clipped into this candidate's interval; the first candidate starts at the ISO/TR 4467 split),
            ``"precheck"`` (the best precheck sample of the objective) or ``"iso"`` (cold: the train's ISO/TR 4467
            split of the root mesh, ``root_shift_split``).
        bonmin: also run :func:`bonmin_cross_check` (raises ``GearoptInputError`` if CasADi has no Bonmin).
        executor: who solves the candidates: ``"serial"`` (default), ``"processes"``, ``"dask"``, a
            ``dask.distributed.Client`` or a :class:`gearopt.executor.Executor` (``workers``, ``progress`` as
            there). With ``start="previous"`` the warm-started chain is split into ``segments`` contiguous pieces
            (each a task, its first candidate started cold); with ``"precheck"``/``"iso"`` every candidate is a task.
            The split does not depend on the executor, so neither does the table (``solve_time_s`` aside).
        segments: pieces of the warm-started chain (``start="previous"``; default 1: one chain, as serially).
    """
    t_start = time.perf_counter()
    if objective not in OBJECTIVES:
        raise GearoptInputError(f"objective={objective!r} must be one of {OBJECTIVES}")
    if top is not None:
        check_range("top", top, 1, None)
    if start not in STARTS:
        raise GearoptInputError(f"start={start!r} must be one of {STARTS}")
    if bonmin and not ca.has_nlpsol("bonmin"):
        raise GearoptInputError("bonmin=True: this CasADi build has no Bonmin plugin (casadi.has_nlpsol('bonmin') "
                                "is False); install a CasADi wheel with Bonmin or use bonmin=False")
    if enumeration is None:
        enumeration = enumerate_tooth_counts(train, **enumerate_options)
    elif enumerate_options:
        raise GearoptInputError(f"enumeration is given: options {sorted(enumerate_options)} would be ignored")
    train = enumeration.train
    adm = enumeration.admissible.copy()
    pre_col = ("precheck_min_worst_case_contact_ratio" if objective == "max_min_worst_case_contact_ratio"
               else "precheck_min_tip_thickness_mm")
    chosen = list(adm.index)
    if top is not None and len(chosen) > top:
        chosen = list(adm[pre_col].sort_values(ascending=False, na_position="last").index[:top])
        chosen.sort()
    if isinstance(segments, bool) or not isinstance(segments, (int, np.integer)) or segments < 1:
        raise GearoptInputError(f"segments={segments!r} must be an integer >= 1")
    items = []
    for idx in chosen:
        x0, kind = None, "iso"
        if start == "precheck":
            col = ("precheck_root_shift_contact_ratio" if objective == "max_min_worst_case_contact_ratio"
                   else "precheck_root_shift_tip_thickness")
            if col in adm and math.isfinite(float(adm.at[idx, col])):
                x0, kind = float(adm.at[idx, col]), "precheck"
        items.append((idx, enumeration.teeth(idx), (float(adm.at[idx, "root_shift_min"]),
                                                    float(adm.at[idx, "root_shift_max"])), x0, kind))
    pieces = min(int(segments), len(items)) if start == "previous" else len(items)
    chunks = [items[a:b] for a, b in _bounds(len(items), pieces)]
    from ...executor import using_executor   # imported here: keeps multiprocessing out of `import gearopt`

    with using_executor(executor, workers=workers, progress=progress) as ex:
        # a worker process rebuilds the candidate models (CasADi functions) instead of receiving the cache
        shipped = enumeration if ex.kind == "serial" else replace(enumeration, models={})
        parts = ex.map(solve_chain, [(shipped, chunk, objective, start, verbose) for chunk in chunks],
                       desc="tooth-count candidates")
    solves = []
    results: dict[Any, dict] = {}
    for chunk, part in zip(chunks, parts):
        for (idx, *_), r in zip(chunk, part):
            solves.append({k: v for k, v in r.items() if k != "error"})
            results[idx] = r
    rows = []
    best_idx, best_x = None, None
    for idx in adm.index:
        row = adm.loc[idx].to_dict()
        r = results.get(idx)
        if r is None:
            row.update(status="not_solved", iterations=np.nan, solve_time_s=np.nan, start="", objective_value=np.nan)
            rows.append(row)
            continue
        row.update(status=r["status"], iterations=r["iterations"], solve_time_s=r["solve_time_s"], start=r["start"],
                   start_root_shift=r["start_root_shift"], objective_value=r["objective_value"],
                   limiting=", ".join(r["limiting"]), active=", ".join(r["active"]),
                   violated=", ".join(r["violated"]))
        x_root = r["root_profile_shift"]
        if x_root is not None and math.isfinite(x_root):
            tr = _train_with_teeth(train, enumeration.teeth(idx), x_root)
            for g, x in tr.profile_shifts.items():
                row[f"profile_shift_{g}"] = float(x)
            out = enumeration.model(enumeration.teeth(idx)).evaluate(x_root)
            for i, mname in enumerate(train.meshes):
                row[f"worst_case_contact_ratio_{mname}"] = float(out["worst_case_contact_ratio"][i, 0])
            for i, g in enumerate(train.gears):
                row[f"tip_thickness_{g}_mm"] = float(out["tip_thickness_mm"][i, 0])
            row["min_worst_case_contact_ratio"] = float(out["worst_case_contact_ratio"].min())
            row["min_tip_thickness_mm"] = float(out["tip_thickness_mm"].min())
        rows.append(row)
    table = pd.DataFrame(rows, index=adm.index)
    if not table.empty:
        solved = table["objective_value"].notna()
        table["_solved"] = ~solved
        table = table.sort_values(["_solved", "objective_value", "max_abs_ratio_error_percent"],
                                  ascending=[True, False, True], kind="mergesort").drop(columns="_solved")
        table.insert(0, "rank", np.arange(1, len(table) + 1))
        if solved.any():
            best_idx = table.index[0]
            best_x = results[best_idx]["root_profile_shift"]
    table = table.reset_index(drop=True)
    for g in train.gears:
        if f"teeth_{g}" in table:
            table[f"teeth_{g}"] = table[f"teeth_{g}"].astype(int)
    best = _train_with_teeth(train, enumeration.teeth(enumeration.admissible.loc[best_idx]), best_x) \
        if best_idx is not None else None
    study = ToothCountStudy(objective=objective, table=table, rejected=enumeration.rejected, best=best,
                            solves=solves, enumeration=enumeration)
    if bonmin:
        study.bonmin = bonmin_cross_check(enumeration)
    study.elapsed_s = time.perf_counter() - t_start
    return study
