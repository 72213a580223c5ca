"""How far a design space reaches toward a rating requirement no design in it meets, and what stops it.

:func:`rating_reach` answers, for ISO 6336 safety requirements (S_H, S_F, S_B at given mesh torques) that a design
fails: could any design of the space meet them, and if not, how close does the space come and which of its bounds
or limits are in the way. It declares a :class:`~gearopt.design.scene.Scene` of the space's macro variables (a
:class:`DesignSpace`: e.g. the root profile shift and the helix angle with their bounds), the space's own limits held
hard (geometry, the safeties at the design torques, walk-off margins) and the requirement's rows as limits that may
be relaxed. For each requirement in turn (the others' rows all but free, :data:`OTHER_WEIGHT`) it finds the least
l1 sum of the scaled shortfalls of that requirement's rows -- the space's own limits cost :data:`HARD_WEIGHT` times
as much, so they relax only if nothing else can hold them -- by the elastic mode (:func:`gearopt.nlp.elastic.solve_elastic`,
``"relaxation"``) started at the best point of an exact grid (:func:`_grid_best`), whose multipliers say what stops
it; where it does not converge, by bounded Nelder-Mead on the exact model from that grid point (:func:`_polish`). At that point:

- ``best_value``: the requirement's worst row (the smallest safety over the rated gears), recomputed by the exact
  rating (:func:`~gearopt.design.requirements.rating_table`, the function the verdict uses);
- ``stopped_by``: every variable bound at which the elastic optimum sits with a nonzero multiplier, and every hard
  limit that is active, each with its multiplier (the change of the least summed shortfall per unit move of that
  bound, in the requirement's unit: a negative value for an upper bound means raising it would help); where Ipopt
  does not converge (the rating's clamps, e.g. Z_B = max(1, M_1), can put the optimum on a kink), the bounds the
  search's point sits on, with a finite difference of the re-polished optimum (:data:`BOUND_STEP`) as multiplier;
- ``meets``: True when the least relaxation is zero -- some design of the space meets the requirement (then the
  design optimisers can carry it as a constraint).

The rating in the scene is the same closed-form ISO 6336 rating (:func:`~gearopt.rating.rate_iso6336`, dual-typed),
not a surrogate. The elastic point minimises the *sum* of the rows' shortfalls, so its worst row is close to, but
not always exactly, the largest smallest safety the space allows (the rows of one requirement move together with
the macro geometry).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from ..data import System
from ..errors import GearoptInputError, SolveError
from ..geometry.train import GearTrain
from ..nlp.elastic import RELAX_SUFFIX, ElasticResult, solve_elastic
from .requirements import rating_table, safety_values
from .scene import Scene
from .scene_spec import DesignVariable, Limit, LoadCase, Objective

HARD_WEIGHT = 1.0e3
"""Weight of a relaxation of the design space's own limits against one of the requirement's rows (scaled units)."""

SAFETY_QUANTITIES = {"S_H": "contact_safety_factor", "S_F": "root_safety_factor",
                     "S_B": "scuffing_safety_factor_flash"}
"""Scene quantities of the ISO 6336 safeties a requirement names."""

MULTIPLIER_TOL = 1e-6
"""Smallest |multiplier| (scaled) of a bound or limit reported as stopping the reach."""

OTHER_WEIGHT = 1e-6
"""Weight of the other requirements' rows in one requirement's reach: present in the scene, all but free."""

NLP_ITERATIONS = 200
"""Ipopt iteration budget of the elastic solve (started from the exact grid's best point)."""

GRID_POINTS = {1: 17, 2: 9}
"""Grid points per variable of the exact search by the number of variables (5 beyond two)."""

BOUND_STEP = 0.01
"""Fraction of a variable's range by which a bound moves outward in the finite-difference multiplier."""


@dataclass(frozen=True)
class DesignSpace:
    """The macro design space a reach is computed over: train-level ``variables`` with their bounds (e.g.
    ``DesignVariable("root_profile_shift", "train", lower=0, upper=0.6)``), the space's own ``limits`` (held in
    every design of it: geometry limits, safeties at the design torques, walk-off margins), the ``load_cases``
    those limits name, and the scene's ``iso6336_options`` (e.g. the application factor of the design torques)."""

    variables: tuple[DesignVariable, ...]
    limits: tuple[Limit, ...] = ()
    load_cases: tuple[LoadCase, ...] = ()
    iso6336_options: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        if not self.variables:
            raise GearoptInputError("DesignSpace needs at least one design variable")
        for v in self.variables:
            if v.target != "train":
                raise GearoptInputError(f"DesignSpace variable {v.name!r} on {v.target!r}: a design space's "
                                        f"variables are the train's macro variables (target 'train')")
            if v.lower is None or v.upper is None:
                raise GearoptInputError(f"DesignSpace variable {v.name!r} needs both bounds (lower={v.lower}, "
                                        f"upper={v.upper})")

    def describe(self) -> str:
        """``"root_profile_shift 0..0.6, helix_angle_deg 0..8"``."""
        return ", ".join(f"{v.name} {v.lower:g}..{v.upper:g}" for v in self.variables)


@dataclass
class RequirementReach:
    """The reach of the design space toward one safety requirement (module docstring)."""

    key: str                       # "S_H", "S_F" or "S_B"
    limit: float
    best_value: float              # the worst row at the elastic point, exact rating
    worst_case: str                # "mesh gear" (or "mesh" for S_B)
    meets: bool
    values: dict[str, float]       # the macro variables at the elastic point
    stopped_by: list[dict]         # {"kind": "bound"|"limit", "name", "side", "bound", "multiplier", "unit"}
    space: str
    elastic: ElasticResult | None = field(repr=False, default=None)   # None: the elastic NLP did not converge
    shortfall: float = 0.0          # the least weighted sum of scaled shortfalls found (the phase-1 objective)
    signature: dict = field(default_factory=dict)   # what the reach is a function of (:func:`reach_signature`)

    def text(self) -> str:
        """One sentence for the requirement table's "what it would take"."""
        at = ", ".join(f"{k} {v:.4g}" for k, v in self.values.items())
        if self.meets:
            return (f"a design of the space ({self.space}) meets it: {self.key} {self.best_value:.3g} at {at}")
        stops = "; ".join(f"the {s['side']} {'bound' if s['kind'] == 'bound' else 'limit'} of {s['name']} "
                          f"({s['bound']:.4g}{(' ' + s['unit']) if s['unit'] else ''}: the summed shortfall falls by "
                          f"{abs(s['multiplier']):.3g} per unit beyond it)" for s in self.stopped_by) \
            or ("no bound or limit of the space: the requirement's own rows trade against each other there (raising one "
                "lowers another)")
        return (f"no design of the space ({self.space}) meets it: the best reached is {self.key} "
                f"{self.best_value:.3g} ({self.worst_case}) at {at}, stopped by {stops}")

    def as_json(self) -> dict:
        return {"key": self.key, "limit": self.limit, "best_value": self.best_value, "worst_case": self.worst_case,
                "meets": self.meets, "values": dict(self.values), "stopped_by": [dict(s) for s in self.stopped_by],
                "design_space": self.space, "shortfall": self.shortfall, "signature": dict(self.signature)}

    @classmethod
    def from_json(cls, d: Mapping[str, Any]) -> "RequirementReach":
        """The reach :meth:`as_json` wrote (without its elastic solve)."""
        return cls(key=d["key"], limit=float(d["limit"]), best_value=float(d["best_value"]),
                   worst_case=d["worst_case"], meets=bool(d["meets"]), values=dict(d["values"]),
                   stopped_by=[dict(x) for x in d["stopped_by"]], space=d["design_space"],
                   shortfall=float(d.get("shortfall", 0.0)), signature=dict(d.get("signature", {})))


def reach_signature(space: DesignSpace, key: str, limit: float, torques_Nm: Mapping[str, float],
                    speeds_rpm: Mapping[str, float], rating_options: Mapping[str, Any] | None) -> dict:
    """What a reach is a function of, as plain data: the space's description, the requirement and its limit, the
    torques, speeds and rating keywords. Two reaches of the same signature (on the same system and space limits)
    are the same reach."""
    return {"design_space": space.describe(), "key": key, "limit": float(limit),
            "torques_Nm": {m: float(t) for m, t in sorted(torques_Nm.items())},
            "speeds_rpm": {m: float(speeds_rpm[m]) for m in sorted(torques_Nm)},
            "rating_options": {k: v for k, v in sorted(dict(rating_options or {}).items())}}


def _train_at(train: GearTrain, values: Mapping[str, float]) -> GearTrain:
    kw = {k.removeprefix("train."): float(v) for k, v in values.items() if k.startswith("train.")}
    return dataclasses.replace(train, **kw)


def rating_reach(system: System, train: GearTrain, space: DesignSpace, torques_Nm: Mapping[str, float],
                 speeds_rpm: Mapping[str, float], limits: Mapping[str, float], *,
                 rating_options: Mapping[str, Any] | None = None) -> dict[str, RequirementReach]:
    """The reach of ``space`` toward the safety requirements ``limits`` ({"S_H": 1.0, "S_F": 1.4, ...}) of every
    mesh in ``torques_Nm`` (torque on its driving gear [N m]) at its crank speed ``speeds_rpm`` [rpm], rated with
    the scene's ``space.iso6336_options`` and then ``rating_options`` (e.g. ``{"application_factor": 1.0,
    "K_v": 1.0}`` at a dynamic peak). ``train``: the design whose macro values start the search (the train's
    gears, teeth and materials are the space's). One scene, one reach per requirement (its own best: the other
    requirements' rows barely weigh); {key: reach}."""
    unknown = sorted(set(limits) - set(SAFETY_QUANTITIES))
    if unknown:
        raise GearoptInputError(f"rating_reach: limits name {unknown}; the safeties are {sorted(SAFETY_QUANTITIES)}")
    if not torques_Nm:
        raise GearoptInputError("rating_reach: torques_Nm is empty: name at least one mesh and its torque")
    missing = sorted(set(torques_Nm) - set(speeds_rpm))
    if missing:
        raise GearoptInputError(f"rating_reach: speeds_rpm gives no speed for meshes {missing}")
    options = dict(rating_options or {})
    cases, relaxed = [], []
    for mesh, torque in torques_Nm.items():
        name = f"reach:{mesh}"
        cases.append(LoadCase(name, {mesh: float(torque)}, speed_rpm=float(speeds_rpm[mesh]),
                              iso6336_options=options))
        relaxed += [Limit(SAFETY_QUANTITIES[k], mesh, lower=float(b), load_cases=(name,)) for k, b in limits.items()]
    first = next(iter(torques_Nm))
    scene = Scene(f"reach of {', '.join(limits)}", train=train, load_cases=[*cases, *space.load_cases],
                  variables=list(space.variables),
                  # a scene needs an objective; the relaxation solve ignores it (a geometry quantity: no epigraph
                  # variable left free in phase 1)
                  objectives=[Objective("transverse_contact_ratio", first, sense="max")],
                  limits=[*relaxed, *space.limits], data=system, iso6336_options=dict(space.iso6336_options))
    built = scene.build()
    problem = built.problem
    names = [v.name for v in problem._variables.values()]
    lower = np.array([float(problem._variables[n].lower[0]) for n in names])
    upper = np.array([float(problem._variables[n].upper[0]) for n in names])
    out = {}
    for key, bound in limits.items():
        out[key] = _reach_of(system, train, space, built, key, float(bound), torques_Nm, speeds_rpm, options,
                             names, lower, upper)
    return out


def _reach_of(system, train, space, built, key, bound, torques_Nm, speeds_rpm, options, names, lower, upper
              ) -> RequirementReach:
    """The reach toward one requirement (its rows weigh 1, the other requirements' :data:`OTHER_WEIGHT`, the
    space's own limits :data:`HARD_WEIGHT`): the elastic mode from an exact grid's best point, the exact polish
    where it does not converge."""
    problem = built.problem
    reach_rows = {r["label"]: r["quantity"] for r in built.records if r["role"] == "limit"
                  and r["load_case"].startswith("reach:")}
    own = {n for n, q in reach_rows.items() if q == SAFETY_QUANTITIES[key]}
    weights = {n: (1.0 if n in own else OTHER_WEIGHT if n in reach_rows else HARD_WEIGHT)
               for n in problem._constraints}
    shortfall = _shortfall(problem, weights)
    start = _grid_best(shortfall, lower, upper)
    for n, x in zip(names, start):
        problem.set_initial(n, float(x))
    try:
        elastic = solve_elastic(problem, mode="relaxation", weights=weights, casadi_options={"expand": True},
                                max_iter=NLP_ITERATIONS)
        point = np.array([float(elastic.values[n]) for n in names])
        converged = shortfall(point) <= shortfall(start) + 1e-9
    except SolveError:
        elastic, converged = None, False
    if not converged:                               # a kink of the rating: the exact polish from the grid's best
        point = _polish(shortfall, lower, upper, start)
    point = np.clip(point, lower, upper)            # Ipopt may end a hair outside a bound
    span = upper - lower                            # a value within round-off of a bound is the bound
    point = np.where(np.abs(point - lower) <= 1e-6 * span, lower,
                     np.where(np.abs(point - upper) <= 1e-6 * span, upper, point))
    values = dict(zip(names, (float(x) for x in point)))
    at = _train_at(train, values)
    rows: list[tuple[str, float]] = []
    for mesh, torque in torques_Nm.items():
        tab = rating_table(system, at, {mesh: float(torque)}, float(speeds_rpm[mesh]),
                           **{"application_factor": 1.0, **dict(space.iso6336_options), **options})
        rows += safety_values(tab, key)
    scales = {float(problem._constraints[n].scale[0]) for n in own}
    unit_scale = scales.pop() if len(scales) == 1 else 1.0
    stopped = (_stopped_by(elastic, set(reach_rows), unit_scale) if converged
               else _stopped_at_bounds(shortfall, point, lower, upper, names, unit_scale,
                                       [problem._variables[n].unit for n in names]))
    worst, value = min(rows, key=lambda r: r[1])
    return RequirementReach(key=key, limit=bound, best_value=float(value), worst_case=worst,
                            meets=bool(value >= bound * (1 - 1e-6)),
                            values={v.removeprefix("train."): x for v, x in values.items()}, stopped_by=stopped,
                            space=space.describe(), elastic=elastic if converged else None,
                            shortfall=float(shortfall(point)),
                            signature=reach_signature(space, key, bound, torques_Nm, speeds_rpm, options))


def _shortfall(problem, weights: Mapping[str, float]):
    """The elastic phase-1 objective on the exact model: ``x`` (the problem's variables in their units, declaration
    order) -> the weighted sum of the scaled violations of every constraint bound: the total of
    :func:`gearopt.nlp.elastic.solve_elastic`'s relaxation table, on arrays (it runs hundreds of times per reach)."""
    constraints = list(problem._constraints.values())
    variables = list(problem._variables.values())
    scale = np.concatenate([c.scale for c in constraints])
    lo = np.concatenate([c.lower for c in constraints])
    hi = np.concatenate([c.upper for c in constraints])
    w = np.concatenate([np.full(c.size, float(weights[c.name])) for c in constraints])

    def f(x: np.ndarray) -> float:
        g = problem._evaluate({v.name: np.atleast_1d(float(xi)) / v.scale for v, xi in zip(variables, x)})[0]
        if not np.all(np.isfinite(g)):
            return float("inf")
        excess = np.maximum(np.where(np.isfinite(lo), lo - g, 0.0), 0.0) \
            + np.maximum(np.where(np.isfinite(hi), g - hi, 0.0), 0.0)
        return float(np.sum(w * excess / scale))
    return f


def _polish(f, lower: np.ndarray, upper: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Bounded Nelder-Mead on ``f`` from ``start`` (a fixed evaluation budget); the start when it is no better."""
    from scipy.optimize import minimize

    n = lower.size
    span = np.where(upper > lower, upper - lower, 1.0)
    res = minimize(lambda u: f(lower + u * span), np.clip((start - lower) / span, 0.0, 1.0), method="Nelder-Mead",
                   bounds=[(0.0, 1.0)] * n, options={"xatol": 1e-7, "fatol": 1e-12, "maxfev": 200 * n})
    polished = lower + np.clip(res.x, 0.0, 1.0) * span
    return polished if f(polished) <= f(start) else start


def _grid_best(f, lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """The best point of an exact grid over the box (:data:`GRID_POINTS`): the start of the elastic NLP (a global
    look the NLP's local convergence lacks), and of the exact polish (:func:`_polish`) where the NLP does not
    converge -- the ISO 6336 rating is only piecewise smooth (its clauses clamp factors, e.g. Z_B = max(1, M_1)),
    so the least shortfall can sit on a kink where a Newton-type solver oscillates."""
    n = lower.size
    axes = [np.linspace(lo, hi, GRID_POINTS.get(n, 5)) for lo, hi in zip(lower, upper)]
    grid = np.array(np.meshgrid(*axes, indexing="ij")).reshape(n, -1).T
    values = np.array([f(x) for x in grid])
    return grid[int(np.argmin(values))]


def _stopped_at_bounds(f, point: np.ndarray, lower: np.ndarray, upper: np.ndarray, names: Sequence[str],
                       unit_scale: float, units: Sequence[str]) -> list[dict]:
    """Where the elastic NLP did not converge: every variable at a bound of the box whose outward move by
    :data:`BOUND_STEP` of its range lowers the least shortfall (re-polished in the moved box), with that finite
    difference of the optimum as its multiplier."""
    out = []
    base = f(point)
    for i, name in enumerate(names):
        step = BOUND_STEP * (upper[i] - lower[i])
        for side, sign in (("lower", -1.0), ("upper", 1.0)):
            bound = lower[i] if side == "lower" else upper[i]
            if step <= 0 or abs(point[i] - bound) > 1e-6 * (upper[i] - lower[i]):
                continue
            lo, hi = lower.copy(), upper.copy()
            (lo if side == "lower" else hi)[i] = bound + sign * step
            moved = point.copy()
            moved[i] = bound + sign * step
            best = _polish(f, lo, hi, moved if f(moved) <= base else point)
            slope = (f(best) - base) / (sign * step)
            if sign * slope < 0:
                out.append({"kind": "bound", "name": name.removeprefix("train."), "side": side,
                            "bound": float(bound), "multiplier": float(slope) * unit_scale, "unit": units[i]})
    return out


def _stopped_by(elastic: ElasticResult, relaxed: set[str], unit_scale: float) -> list[dict]:
    """Variable bounds and hard limits active at the elastic point with a nonzero multiplier, largest first."""
    solve = elastic.relaxation_solve
    out = []
    var = solve.variables
    for _, r in var.iterrows():
        if any(s in str(r["base"]) for s in RELAX_SUFFIX.values()) or not str(r["base"]).startswith("train."):
            continue
        if r["at_bound"] and abs(float(r["multiplier"])) > MULTIPLIER_TOL:
            side = "upper" if abs(float(r["value"]) - float(r["upper"])) <= abs(float(r["value"]) - float(r["lower"])) \
                else "lower"
            out.append({"kind": "bound", "name": str(r["base"]).removeprefix("train."), "side": side,
                        "bound": float(r[side]), "multiplier": float(r["multiplier"]) * unit_scale,
                        "unit": str(r["unit"])})
    con = solve.constraints
    for _, r in con[con["active"]].iterrows():
        if str(r["base"]) in relaxed or abs(float(r["multiplier"])) <= MULTIPLIER_TOL:
            continue
        side = "lower" if np.isfinite(r["lower"]) and abs(r["value"] - r["lower"]) <= abs(r["value"] - r["upper"]) \
            else "upper"
        out.append({"kind": "limit", "name": str(r["name"]), "side": side, "bound": float(r[side]),
                    "multiplier": float(r["multiplier"]) * unit_scale, "unit": str(r["unit"])})
    return sorted(out, key=lambda s: -abs(s["multiplier"]))


def reach_table(reaches: Mapping[str, RequirementReach]) -> pd.DataFrame:
    """One row per requirement: key, limit, best value, worst case, meets, the macro values and what stops it."""
    return pd.DataFrame([{"requirement": k, "limit": r.limit, "best_value": r.best_value, "worst_case": r.worst_case,
                          "meets": r.meets, **r.values,
                          "stopped_by": "; ".join(f"{s['name']} ({s['side']})" for s in r.stopped_by)}
                         for k, r in reaches.items()])


__all__ = ["DesignSpace", "RequirementReach", "rating_reach", "reach_signature", "reach_table", "HARD_WEIGHT", "SAFETY_QUANTITIES"]
