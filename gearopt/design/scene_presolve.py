"""Presolve of a scene's train variables: which values of a macro variable (the root profile shift, the helix
angle) the exact limits leave open at a given flank design, before an NLP is built over it.

:func:`scan_train_variable` evaluates the exact LTCA limits of a built micro-only scene (every limit on an exact-LTCA
quantity, :data:`~gearopt.design.scene_search.EXACT_LIMIT_COLUMNS`) and the geometry limits of every mesh on a grid
of one train variable, the flank design held; :func:`pinned_interval` reads the feasible interval around the start
from it. A variable whose feasible interval is narrower than a stated width is *pinned*: a co-design over it cannot
move it far, and the study may solve the flanks alone at its value and say why
(:func:`gearopt.cases.timing_train.codesign_study`). The scan holds the flanks at one design (an approximation:
other flanks could open other values; the report states the flank design it used).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np
import pandas as pd

from ..errors import GearoptError, GearoptInputError
from ..rating.stiffness import StiffnessValidityWarning
from .scene_search import EXACT_RANK_TOLERANCE, exact_limit_violations

TRAIN_VARIABLES = {"root_profile_shift": "root_profile_shift", "helix_angle_deg": "helix_angle_deg"}
"""Train variables a scan can move, by the :class:`~gearopt.geometry.GearTrain` field they set."""


def scan_train_variable(built, values: Mapping[str, float], variable: str, grid: Sequence[float], *,
                        geometry_limits: Mapping | None = None) -> pd.DataFrame:
    """One row per value of the train variable ``variable`` (:data:`TRAIN_VARIABLES`) on ``grid``: ``value``,
    ``violation`` (sum of the relative violations of the exact limits of ``built``, a solved micro-only scene, at
    its flank design ``values``), ``worst`` (the most violated limit, ``"<quantity> <target>"``), ``geometry`` (the
    first geometry limit the train's meshes break, :meth:`~gearopt.geometry.GearPair.check` with
    ``geometry_limits``; "" when none) and ``feasible``. The trial geometries' stiffness-validity warnings (ISO
    6336-1 method B outside its range) are not repeated per value: the scan explores, the design's own check warns.
    """
    if variable not in TRAIN_VARIABLES:
        raise GearoptInputError(f"variable={variable!r} must be one of {sorted(TRAIN_VARIABLES)}")
    grid = [float(x) for x in grid]
    if len(grid) < 2:
        raise GearoptInputError(f"grid needs at least 2 values (got {len(grid)})")
    train = built.scene.train
    rows = []
    for x in grid:
        row = {"value": x, "violation": math.inf, "worst": "", "geometry": ""}
        try:
            trial = dataclasses.replace(train, **{TRAIN_VARIABLES[variable]: x})
            for mesh, pair in trial.pairs.items():
                try:
                    pair.check(**dict(geometry_limits or {}))
                except GearoptError as exc:
                    row["geometry"] = f"{mesh}: {str(exc).splitlines()[0]}"
                    break
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", StiffnessValidityWarning)
                # without the relief variants of a toleranced PPTE limit (an exact LTCA each): a limit left out
                # can only widen the feasible interval, so it never pins a variable the NLP could move
                violations = exact_limit_violations(built, built.exact_check(values, train=trial, toleranced=False,
                                                                               fractions=False, table=False))
            row["violation"] = float(sum(violations.values()))
            worst = max(violations, key=violations.get) if violations else ""
            row["worst"] = worst if violations.get(worst, 0.0) > 0.0 else ""
        except GearoptError as exc:                 # geometry the models refuse at this value
            row["geometry"] = str(exc).splitlines()[0]
        row["feasible"] = bool(not row["geometry"] and row["violation"] <= EXACT_RANK_TOLERANCE)
        rows.append(row)
    return pd.DataFrame(rows)


@dataclass(frozen=True)
class PinnedVariable:
    """A train variable the exact limits pin: its ``value`` (the start), the feasible ``interval`` around it on
    the scan's grid (its ends widened to the neighbouring infeasible grid values), the limits that close it
    (``binding``: below, above) and the ``scan`` table."""

    name: str
    value: float
    interval: tuple[float, float]
    binding: tuple[str, str]
    scan: pd.DataFrame

    @property
    def reason(self) -> str:
        lo, hi = self.interval
        return (f"{self.name} pinned at {self.value:.4g}: with the flanks held, only {lo:.4g}..{hi:.4g} meets the "
                f"exact limits as well as the start does (below: {self.binding[0] or 'the bound'}; above: "
                f"{self.binding[1] or 'the bound'})")

    def as_json(self) -> dict:
        return {"name": self.name, "value": self.value, "interval": list(self.interval),
                "binding": list(self.binding), "reason": self.reason,
                "scan": self.scan.to_dict(orient="records")}


def pinned_interval(scan: pd.DataFrame, name: str, start: float, max_width: float) -> PinnedVariable | None:
    """The :class:`PinnedVariable` of a :func:`scan_train_variable` table when the run of grid values around
    ``start`` (the grid value nearest it) that are feasible -- or, if the start itself violates the exact limits (an
    unrefined flank design), no more violated than the start -- spans at most ``max_width`` (its ends widened to the
    neighbouring grid values outside it), else None (also when the start breaks a geometry limit)."""
    x = scan["value"].to_numpy(float)
    i = int(np.argmin(np.abs(x - start)))
    if "violation" in scan:
        geometry_ok = scan["geometry"].fillna("").eq("").to_numpy(bool)
        violation = scan["violation"].to_numpy(float)
        ok = geometry_ok & (violation <= max(EXACT_RANK_TOLERANCE, violation[i] * (1.0 + 1e-9)))
    else:
        ok = scan["feasible"].to_numpy(bool)
    if not ok[i]:
        return None
    lo, hi = i, i
    while lo > 0 and ok[lo - 1]:
        lo -= 1
    while hi < len(x) - 1 and ok[hi + 1]:
        hi += 1
    a, b = x[max(lo - 1, 0)], x[min(hi + 1, len(x) - 1)]
    if b - a > max_width:
        return None

    def why(k: int) -> str:                   # what closes the interval at grid index k ("" past the grid's end)
        if k < 0 or k >= len(x):
            return ""
        r = scan.iloc[k]
        return r["geometry"] or r["worst"]
    return PinnedVariable(name, float(start), (float(a), float(b)), (why(lo - 1), why(hi + 1)), scan)


__all__ = ["scan_train_variable", "pinned_interval", "PinnedVariable", "TRAIN_VARIABLES"]
