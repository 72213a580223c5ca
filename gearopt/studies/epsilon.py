"""The ε-constraint NLP of a trade-off front: a scene with one more quantity bounded by a parameter ε.

:class:`EpsilonModel` builds the scene once (per process: :func:`epsilon_model` caches it, so a worker of the
executor builds it for its first task only), aggregates the second quantity ``q`` of the front over the scene's load
cases with an epigraph variable ``z`` (``z >= q`` elements for a quantity to be made small, ``z <= q`` for one to be
made large; the peak-to-peak of a TE column through two more epigraph variables per load case), and adds
``z <= ε`` (or ``z >= ε``) with ε a :class:`~gearopt.nlp.problem.Problem` parameter: moving along the front changes a
parameter, never the NLP, and each point starts from its neighbour's solution (Ipopt warm start of primal values and
multipliers).

Source of the method: Haimes, Lasdon & Wismer (1971), "On a bicriterion formulation of the problems of integrated
system identification and system optimization", IEEE Trans. SMC 1(3) -- the ε-constraint method; Miettinen (1999),
*Nonlinear Multiobjective Optimization*, sec. 3.2.
"""

from __future__ import annotations

import hashlib
import warnings
import pickle
from dataclasses import dataclass, field, replace
from typing import Any, Mapping

import numpy as np
import pandas as pd

from .. import numerics as nm
from ..design.scene import Limit, Scene
from ..design.scene_terms import quantity_kind
from ..errors import GearoptInputError, SolveError
from ..nlp import WARM_START_IPOPT, InitialGuessWarning, WarmStartPoint

LOOSE = 1e6
"""|ε| that leaves the front constraint inactive (the objective's own optimum), in the quantity's unit."""


@dataclass(frozen=True)
class FrontSpec:
    """What a worker needs to rebuild the ε-constraint NLP: the scene, the quantity, its target and sense
    (``"min"``: the front trades a smaller quantity for a worse objective), and Ipopt options."""

    scene: Scene
    quantity: str
    target: str
    sense: str
    ipopt: Mapping[str, Any] = field(default_factory=dict)

    def key(self) -> str:
        return hashlib.sha1(pickle.dumps(self)).hexdigest()


class EpsilonModel:
    """The built ε-constraint NLP of a :class:`FrontSpec` (see the module docstring)."""

    def __init__(self, spec: FrontSpec):
        self.spec = spec
        kind = quantity_kind(spec.quantity)
        self.kind = kind
        loose = Limit(spec.quantity, spec.target, **({"upper": LOOSE} if spec.sense == "min" else {"lower": -LOOSE}))
        # the quantity keeps a (never active) limit so that the scene builds what it needs and tables it per case
        limits = [lim for lim in spec.scene.limits if (lim.quantity, lim.target) != (spec.quantity, spec.target)]
        self.built = replace(spec.scene, limits=[*limits, loose]).build()
        p = self.built.problem
        self.problem = p
        self.objective_expr = p.opti.f
        self.z = self._aggregate()
        scale = kind.scale ** 2 if kind.squared else kind.scale
        self.epsilon = p.parameter("front.epsilon", LOOSE if spec.sense == "min" else -LOOSE, unit=kind.unit)
        bound = self.epsilon ** 2 if kind.squared else self.epsilon
        if spec.sense == "min":
            p.subject_to("front.epsilon_limit", self.z - bound, upper=0.0, scale=scale, unit=_unit(kind))
        else:
            p.subject_to("front.epsilon_limit", self.z - bound, lower=0.0, scale=scale, unit=_unit(kind))
        # one objective for both ends: the scene's (weight 1) or the quantity's own (weight 0), switched by a
        # parameter -- a new objective would make CasADi build a new NLP solver, which costs as much as a short solve
        self.objective_weight = p.parameter("front.objective_weight", 1.0)
        toward = self.z / scale if spec.sense == "min" else -self.z / scale
        p.minimize(self.objective_weight * self.objective_expr + (1.0 - self.objective_weight) * toward)
        # the declared start: a solve without warm start begins here, whatever an earlier front (this model is
        # cached per process) set as initial guesses -- so a front does not depend on what ran before it
        self._declared = {name: np.array(v.init, dtype=float) for name, v in p._variables.items()}

    # -- the aggregated quantity -------------------------------------------------------------------------------------

    def _aggregate(self):
        p, kind, sense = self.problem, self.kind, self.spec.sense
        exprs = self.built.expressions(self.spec.quantity, self.spec.target)
        if kind.shape in ("max", "ppte") and sense != "min":
            raise GearoptInputError(f"quantity {self.spec.quantity!r} is the largest value of a set: a front can "
                                    f"only make it small (sense='min')")
        if kind.shape == "min" and sense != "max":
            raise GearoptInputError(f"quantity {self.spec.quantity!r} is the smallest value of a set: a front can "
                                    f"only make it large (sense='max')")
        parts = []
        for label, _, e in exprs:
            if kind.shape == "ppte":
                start = self._initial(e)
                n = int(start.size)
                hi = p.variable(f"front.{label}.te_max_um", init=float(start.max()), scale=kind.scale, unit="um")
                lo = p.variable(f"front.{label}.te_min_um", init=float(start.min()), scale=kind.scale, unit="um")
                p.subject_to(f"front.{label}.te_below_max", nm.repeat_rows(hi, n) - e, lower=0.0, unit="um")
                p.subject_to(f"front.{label}.te_above_min", e - nm.repeat_rows(lo, n), lower=0.0, unit="um")
                parts.append(hi - lo)
            else:
                parts.append(e)
        elements = nm.vcat(parts)
        start = self._initial(elements)
        z0 = float(start.max() if sense == "min" else start.min())
        scale = kind.scale ** 2 if kind.squared else kind.scale
        z = p.variable("front.bound", init=z0, scale=scale, unit=_unit(kind))
        n = int(start.size)
        gap = nm.repeat_rows(z, n) - elements if sense == "min" else elements - nm.repeat_rows(z, n)
        p.subject_to("front.bound_epigraph", gap, lower=0.0, scale=scale, unit=_unit(kind))
        return z

    def _initial(self, expr) -> np.ndarray:
        if nm.is_numeric(expr):
            raise GearoptInputError(f"quantity {self.spec.quantity!r} of {self.spec.target!r} does not depend on the "
                                    f"design variables: it has no trade-off with the objective")
        opti = self.problem.opti
        return np.atleast_1d(np.asarray(opti.value(expr, opti.initial()), dtype=float)).ravel()

    # -- solving -----------------------------------------------------------------------------------------------------

    def solve(self, epsilon: float | None, *, start: Mapping[str, Any] | None = None,
              warm: bool | WarmStartPoint = False, objective: str = "scene", starts: int = 1):
        """Solve with the front constraint at ``epsilon`` (``None``: loose). ``objective``: ``"scene"`` (the scene's
        objective) or ``"quantity"`` (the quantity itself: the other end of the front). ``start``: variable values
        to start from (a neighbour's point); ``warm``: start from the previous solve (primal and multipliers) or
        from a neighbour's :class:`~gearopt.nlp.WarmStartPoint` (its solve's primal and multipliers);
        ``starts`` > 1: also ``starts - 1`` Latin-hypercube starts of the design variables, the best optimum."""
        p, sense = self.problem, self.spec.sense
        if objective not in ("scene", "quantity"):
            raise GearoptInputError(f"objective={objective!r} must be 'scene' or 'quantity'")
        p.set_parameter("front.objective_weight", 0.0 if objective == "quantity" else 1.0)
        eps = (LOOSE if sense == "min" else -LOOSE) if epsilon is None else float(epsilon)
        p.set_parameter("front.epsilon", eps)
        if not warm:
            for name, value in self._declared.items():
                p.set_initial(name, value)
        if start is not None:
            for name, value in start.items():
                p.set_initial(name, value)
        options = dict(self.spec.ipopt)
        if warm:
            options = {**WARM_START_IPOPT, **options}
        with warnings.catch_warnings():      # a neighbour's value on a bound may read as just outside it
            warnings.simplefilter("ignore", InitialGuessWarning)
            if starts > 1:
                design = [f"{v.target}.{v.name}" for v in self.spec.scene.variables]
                return p.multistart(starts - 1, seed=0, variables=design, include_initial=True, **options).best
            return p.solve(warm_start=warm, **options)

    def quantity_value(self, solved, table: pd.DataFrame | None = None) -> float:
        """The front quantity at a solve: the largest (smallest) value over the load cases, in its unit
        (``table``: the solve's quantity table, when already made)."""
        table = self.built.quantity_table(solved) if table is None else table
        rows = table[(table["quantity"] == self.spec.quantity) & (table["target"] == self.spec.target)]
        values = rows["value"].to_numpy(dtype=float)
        return float(values.max() if self.spec.sense == "min" else values.min())


_MODELS: dict[str, EpsilonModel] = {}


def epsilon_model(spec: FrontSpec) -> EpsilonModel:
    """The :class:`EpsilonModel` of ``spec``, built once per process."""
    key = spec.key()
    if key not in _MODELS:
        if len(_MODELS) > 4:
            _MODELS.pop(next(iter(_MODELS)))
        _MODELS[key] = EpsilonModel(spec)
    return _MODELS[key]


def failure_record(exc: BaseException) -> dict[str, Any]:
    """Status and message of a failed point: the typed error's class name, its first line, the worst constraint."""
    worst = exc.violated[0].name if isinstance(exc, SolveError) and exc.violated else ""
    return {"status": type(exc).__name__, "error": str(exc).splitlines()[0], "worst_violated": worst}


def _unit(kind) -> str:
    return f"({kind.unit})^2" if kind.squared else kind.unit


__all__ = ["FrontSpec", "EpsilonModel", "epsilon_model", "failure_record", "LOOSE"]
