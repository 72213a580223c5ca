"""The result of a solved scene (:class:`SceneResult`): the design, its quantities, the exact check, the build and
the refinement, and the :class:`~gearopt.design.scene.BuiltScene` solved (``source``), from which the studies of
:mod:`gearopt.studies` start."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd

from ..contact.microgeometry import Microgeometry
from ..nlp.problem import WarmStartPoint
from ..nlp.result import ProblemResult


@dataclass
class SceneResult:
    """The solved scene: ``values`` (``"target.variable"`` -> value in the variable's unit), ``quantities`` (every
    objective and limit quantity at the optimum: value, bounds, margin, unit -- the true maximum/PPTE, not the
    epigraph bound), ``exact_check`` (exact LTCA of the optimum), ``microgeometry`` per LTCA mesh, ``solve``
    (:class:`ProblemResult`: constraint and variable tables, multipliers), ``built`` (the build table) and
    ``starts`` (the multi-start table, when ``solve(starts=n)``), ``refinement`` (one row per solve of the
    semi-infinite refinement: positions, worst smooth-vs-exact PPTE error, Ipopt iterations and times; its
    ``attrs["polish"]`` the exact polish), ``screen`` (the exact screen that picked the starts, ranked:
    :mod:`gearopt.design.scene_search`) and
    ``positions`` (per LTCA mesh, the final mesh positions as fractions of a base pitch), ``source`` (the
    :class:`BuiltScene` solved; the studies of :mod:`gearopt.studies` start from it)."""

    scene: str
    values: dict[str, float]
    solve: ProblemResult
    quantities: pd.DataFrame
    exact_check: pd.DataFrame
    microgeometry: dict[str, Microgeometry]
    built: pd.DataFrame
    starts: pd.DataFrame | None = None
    refinement: pd.DataFrame | None = None
    screen: pd.DataFrame | None = None
    positions: dict[str, np.ndarray] = field(default_factory=dict)
    source: Any = field(default=None, repr=False, compare=False)

    @property
    def refinements(self) -> int:
        """Re-solves the semi-infinite refinement needed (0: the first solve agreed with the exact model)."""
        return 0 if self.refinement is None else int(len(self.refinement) - 1)

    @property
    def success_rate(self) -> float:
        """Fraction of the multi-start solves that converged (1.0 for a single successful solve)."""
        return 1.0 if self.starts is None else float(self.starts["success"].mean())

    def warm_start_point(self) -> WarmStartPoint:
        """The multipliers of the solve this design came from, by constraint name
        (:meth:`~gearopt.nlp.WarmStartPoint.from_result`): a related scene built at this design (``initial``) and
        sharing its constraints -- more limits, the same positions -- starts from them
        (``BuiltScene.solve(warm_start=...)``)."""
        return WarmStartPoint.from_result(self.solve)


__all__ = ["SceneResult"]
