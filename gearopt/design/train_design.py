"""Helpers of train-level designs: the loaded flanks of a train's meshes (the flank targets of per-flank
modifications) and the ranking of tooth-count candidates by their co-design."""

from __future__ import annotations

import time
from typing import Callable, Sequence

import numpy as np
import pandas as pd

from ..errors import SolveError
from ..geometry.train import GearTrain
from .scene import Scene
from .tooth_counts import _train_with_teeth


def loaded_flanks(train: GearTrain, meshes: Sequence[str]) -> dict[str, list[str]]:
    """Mesh -> its loaded flanks (``"gear:driving"`` of the first-named, driving gear, ``"gear:driven"`` of the
    other)."""
    return {m: [f"{train.meshes[m].gears[0]}:driving", f"{train.meshes[m].gears[1]}:driven"] for m in meshes}



def rank_tooth_counts(enumeration, make_scene: Callable[[GearTrain], Scene], *, limit: int | None = None,
                      warm_start: bool = True) -> pd.DataFrame:
    """Co-design every admissible tooth-count candidate of ``enumeration``
    (:func:`gearopt.design.tooth_counts.enumerate_tooth_counts`) and rank them by the verified objective.

    ``make_scene(train)`` returns the co-design scene of a candidate's train (the enumeration's train with the
    candidate's teeth; its root shift starts in the middle of the candidate's admissible interval). Candidates are
    solved in enumeration order (at most ``limit``), each warm-started from the previous optimum (the values of the
    variables both scenes share, clipped into the new bounds, and the previous refined positions) when
    ``warm_start``. A failed solve stays in the table with its typed error. Columns: the teeth, ``objective``
    (exact-LTCA PPTE terms, :mod:`gearopt.design.scene_refine`), ``max_ppte_um`` (largest exact PPTE of the
    objective meshes), ``root_profile_shift``, ``refinements``, ``time_s``, ``status``; best first."""
    rows, prev = [], None
    table = enumeration.admissible if limit is None else enumeration.admissible.head(limit)
    for idx, cand in table.iterrows():
        teeth = enumeration.teeth(cand)
        x0 = 0.5 * (float(cand["root_shift_min"]) + float(cand["root_shift_max"]))
        scene = make_scene(_train_with_teeth(enumeration.train, teeth, x0))
        kw = {}
        if warm_start and prev is not None:
            kw = {"initial": prev.values, "positions": prev.positions}
        row = {f"teeth_{g}": z for g, z in teeth.items()}
        t0 = time.perf_counter()
        try:
            res = scene.build(**kw).solve()
        except SolveError as exc:
            rows.append({**row, "objective": np.inf, "status": f"{type(exc).__name__}: {exc.status}",
                         "time_s": time.perf_counter() - t0})
            continue
        ppte = [o.target for o in scene.objectives if o.quantity == "ppte_um"]
        ex = res.exact_check
        verified = res.refinement.attrs.get("verified_objective") if res.refinement is not None else None
        rows.append({**row, "objective": float(verified if verified is not None and np.isfinite(verified)
                                               else res.solve.objective),
                     "max_ppte_um": float(ex[ex["mesh"].isin(ppte)]["ppte_um"].max()) if len(ex) else np.nan,
                     "root_profile_shift": res.values.get("train.root_profile_shift", x0),
                     "refinements": res.refinements, "time_s": time.perf_counter() - t0, "status": "solved"})
        prev = res
    out = pd.DataFrame(rows).sort_values("objective", kind="stable").reset_index(drop=True)
    out.insert(0, "rank", np.arange(1, len(out) + 1))
    return out


__all__ = ["loaded_flanks", "rank_tooth_counts"]
