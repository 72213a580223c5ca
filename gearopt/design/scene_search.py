"""The exact model's global phase and last word around a scene's NLP: an exact screen picks the starts, an exact
polish finishes the optimum.

The NLP optimises a smooth stand-in of the LTCA (softplus contact, sampled mesh positions); its optimum is a local
one of the stand-in. Measured on the spur tip relief of the packaged timing train's first mesh over 150/300/450 N m (loaded contact ratio >= 1.2),
the refined NLP returned 3.589 um where differential evolution with a Nelder-Mead polish on the exact LTCA found
3.539 um (+1.4 %), and 1.476 um against 1.422 um (+3.8 %) on its second: the smooth optimum lies a little
off the exact one, and which local optimum Ipopt reaches depends on its start. Both are closed here, on the exact
model and within evaluation budgets (no wall time):

1. **Exact screen** (:func:`exact_screen`, the global phase): a scrambled Sobol sample of the design variables inside
   their bounds (Owen-scrambled base-2 digital net; ``screen_samples`` points, seeded), plus the declared start,
   each evaluated by the exact check (:meth:`~gearopt.design.scene_contact.ContactModels.exact_check`: the exact LTCA
   of every mesh and load case at ``screen_positions``, 320 for a one-slice mesh: the screen only ranks designs, so
   a quarter of ``check_positions`` serves), and ranked like the
   multistart (:func:`rank_key`: meeting every exact limit first, then the exact objective). The ``starts`` best are
   the Ipopt starts. The same seed gives the same ranked sample whatever ``starts``, so the starts of a larger
   ``starts`` include those of a smaller one. A build warm-started with ``initial`` (a continuation, a front
   point's re-solve) is not screened: its caller chose the start.
2. **Exact polish** (:func:`exact_polish`): from the chosen optimum, a Nelder-Mead search (Nelder & Mead, Comput.
   J. 7 (1965) 308; SciPy's adaptive variant, Gao & Han 2012) on the exact objective with the exact limits as a
   penalty, in bound-normalised coordinates, for ``polish_evaluations_per_variable`` evaluations per variable. The
   polished design replaces the optimum only if it meets the exact limits at least as well and its exact objective
   is lower.

Both apply to a scene whose objectives are all PPTE and whose limits are all on quantities the exact model
evaluates -- the exact LTCA's (PPTE, contact and root stress, contact temperature, loaded contact ratio) and the
closed-form geometry's (``geometry_limits``, contact ratios, tip thicknesses) -- so every number of the search is
the exact model's; with microgeometry variables (reliefs, their starts, crowns) and macro variables (the train's
root profile shift and helix angle, a mesh's shift, tip diameters, face width), finitely bounded, at most
``screen_max_variables`` of them (a space-filling sample thins out quickly with the dimension). A box sample of
macro values meets designs the geometry refuses: such a design (the exact model raises a
:class:`~gearopt.errors.GearoptError` for it: pointed teeth, an unreachable centre distance) ranks as infeasible, and
the NLP's closed-form constraints between macro and micro values (a free relief start between the pitch point and
the tip margin) count in its exact violation (:func:`exact_geometry_violations`). :func:`search_scope` says why a
scene is out of scope (a co-design with joint limits, say); those scenes are solved as before. Cost on the first
scene: 64 + 1 screen evaluations and 100 polish evaluations, about 2 CPU-s against 0.7 CPU-s for the NLP.
"""

from __future__ import annotations

from typing import Mapping

import numpy as np
import pandas as pd

from ..errors import GearoptError
from .scene_terms import quantity_kind, variable_kind

EXACT_RANK_TOLERANCE = 1e-3
"""Relative violation of an exact limit below which a candidate counts as meeting it."""

EXACT_LIMIT_COLUMNS = ("ppte_um", "max_contact_stress_MPa", "max_root_stress_MPa", "max_contact_temperature_C",
                       "loaded_contact_ratio", "ppte_um_toleranced")
"""The quantities the exact check evaluates (the limits it can judge)."""

SEARCH_VARIABLE_GROUPS = ("micro", "macro", "train")
"""Variable groups the exact search samples (:data:`~gearopt.design.scene_terms.VARIABLES`): not joints or blanks,
whose limits the exact LTCA does not evaluate."""

REFUSED_MERIT = 1e6
"""The polish's merit of a design the exact model refuses (no objective exists there)."""

POLISH_PENALTY = 1e3
"""Penalty of the polish: an exact limit violated by 0.1 % (relative) costs as much as the start's objective."""

POLISH_STEP = 0.05
"""First simplex of the polish: this fraction of each variable's bound range from the start."""


def exact_limit_violations(built, exact: pd.DataFrame | Mapping[str, np.ndarray]) -> dict[str, float]:
    """``{"<quantity> <target>": relative violation}`` of each of the scene's limits on LTCA quantities in the exact
    check (summed over its load cases; 0 where it is met). ``exact``: the exact check's table, or its columns as
    arrays (``exact_check(..., table=False)``)."""
    out: dict[str, float] = {}
    if "mesh" not in exact or not len(exact["mesh"]):
        return out
    # plain arrays, not pandas masks: this runs once per exact evaluation of the screen and the polish
    mesh, case = np.asarray(exact["mesh"]), np.asarray(exact["load_case"])
    for lim in built.scene.limits:
        if lim.quantity not in EXACT_LIMIT_COLUMNS or lim.quantity not in exact:
            continue
        rows = mesh == lim.target
        if lim.load_cases is not None:
            rows &= np.isin(case, list(lim.load_cases))
        key = f"{lim.quantity} {lim.target}"
        out[key] = out.get(key, 0.0) + _relative_violation(lim, np.asarray(exact[lim.quantity], dtype=float)[rows])
    return out


def _relative_violation(lim, vals: np.ndarray) -> float:
    """Summed relative violation of ``lim``'s bounds by the values ``vals`` (0 where met)."""
    total = 0.0
    if lim.upper is not None:
        total += float(np.clip((vals - lim.upper) / max(abs(lim.upper), 1e-12), 0.0, None).sum())
    if lim.lower is not None:
        total += float(np.clip((lim.lower - vals) / max(abs(lim.lower), 1e-12), 0.0, None).sum())
    return total


def _geometry_limit(quantity: str) -> bool:
    """Whether ``quantity`` is a mesh quantity of the closed-form geometry alone (evaluated exactly at a numeric
    pair)."""
    kind = quantity_kind(quantity)
    return kind.target_kind == "mesh" and kind.needs == ("geometry",)


def _geometry_values(pair, quantity: str, options) -> np.ndarray:
    """The values of a closed-form geometry quantity of the numeric ``pair`` (the NLP's expressions of
    :meth:`~gearopt.design.scene_transcription.SceneTranscription.elements`, at numbers)."""
    if quantity == "geometry_limits":
        return np.array([float(v) for v in pair.constraints(**dict(options)).values()])
    g = pair.geometry()
    if quantity == "min_tip_thickness_mm":
        return np.array([float(v) for v in g["tip_thickness_mm"]])
    if quantity.startswith("tip_thickness_"):
        return np.array([float(g["tip_thickness_mm"][int(quantity[len("tip_thickness_")]) - 1])])
    return np.array([float(g[quantity])])


def exact_geometry_violations(built, values: Mapping[str, float]) -> dict[str, float]:
    """``{"<limit or constraint> <target>": violation}`` of the scene's closed-form constraints at the design
    ``values``: its limits on geometry quantities (relative to the limit; ``geometry_limits`` margins, whose bound is
    0, in their own units) and, where a mesh's macro geometry is free, each free tip-relief start between the pitch
    point and ``start_margin_deg`` below the tip (deg) -- the constraints the NLP carries beside the LTCA's. 0 where
    met."""
    out: dict[str, float] = {}
    pairs: dict[str, object] = {}

    def pair(mesh):
        if mesh not in pairs:
            pairs[mesh] = built.numeric_pair(mesh, values)
        return pairs[mesh]
    for lim in built.scene.limits:
        if not _geometry_limit(lim.quantity):
            continue
        vals = _geometry_values(pair(lim.target), lim.quantity, lim.options)
        total = float(np.clip(-vals, 0.0, None).sum()) if lim.quantity == "geometry_limits" else \
            _relative_violation(lim, vals)
        key = f"{lim.quantity} {lim.target}"
        out[key] = out.get(key, 0.0) + total
    margin = built.options.model.start_margin_deg
    for mesh in built.ltca_meshes():
        if not built.graph.macro_free(mesh):
            continue
        for i in (0, 1):
            start = built.contact.free_micro(mesh, i, "tip_relief_start_roll_deg", values)
            if start is None:
                continue
            g = pair(mesh).geometry()
            low, high = float(g["pitch_point_roll_deg"][i]), float(g["eap_roll_deg"][i]) - margin
            out[f"tip_relief_start_{i + 1}_in_profile {mesh}"] = max(low - start, start - high, 0.0)
    return out


def exact_limit_violation(built, exact: pd.DataFrame | Mapping[str, np.ndarray]) -> float:
    """Sum over the scene's limits on LTCA quantities of the exact check's relative violations (0: every exact
    limit met); ``exact`` as in :func:`exact_limit_violations`."""
    return float(sum(exact_limit_violations(built, exact).values()))


def rank_key(objective: float, violation: float) -> tuple[bool, float, float]:
    """Sort key of a candidate design: meeting every exact limit (within :data:`EXACT_RANK_TOLERANCE`) first, then
    the smaller violation, then the smaller exact objective."""
    over = violation > EXACT_RANK_TOLERANCE
    return over, violation if over else 0.0, objective


def exact_ppte_objective(built, exact: pd.DataFrame | Mapping[str, np.ndarray]) -> float:
    """The scene's objective from the exact check alone, for a scene whose objectives are all PPTE: each
    objective's PPTE over its load cases (largest or mean), weighted and scaled as in the NLP, summed or (with
    ``objective_aggregate="max"``) their largest. ``exact`` as in :func:`exact_limit_violations`."""
    names = [lc.name for lc in built.load_cases]
    mesh, case = np.asarray(exact["mesh"]), np.asarray(exact["load_case"])
    ppte = np.asarray(exact["ppte_um"], dtype=float)
    terms = []
    for obj in built.scene.objectives:
        cases = names if obj.load_cases is None else list(obj.load_cases)
        vals = ppte[(mesh == obj.target) & np.isin(case, cases)]
        agg = float(vals.mean() if obj.aggregate == "mean" else vals.max())
        scale = obj.weight / (obj.scale or quantity_kind(obj.quantity).scale)
        terms.append(scale * (agg if obj.sense == "min" else -agg))
    return max(terms) if built.scene.objective_aggregate == "max" else sum(terms)


def search_scope(built) -> str | None:
    """Why the exact screen and polish do not apply to ``built`` (``None``: they do; module docstring)."""
    scene, search = built.scene, built.options.search
    if not built.ltca_meshes():
        return "no LTCA mesh"
    other = sorted({o.quantity for o in scene.objectives if o.quantity != "ppte_um"})
    if other:
        return f"objectives on {', '.join(other)} (not PPTE)"
    if any(o.load_cases is None and not built.load_cases for o in scene.objectives):
        return "no load case"
    other = sorted({lim.quantity for lim in scene.limits
                    if lim.quantity not in EXACT_LIMIT_COLUMNS and not _geometry_limit(lim.quantity)})
    if other:
        return f"limits on {', '.join(other)} (not evaluated by the exact LTCA or the closed-form geometry)"
    names = built.variable_names
    if not names:
        return "no design variable"
    other = sorted({v.name for v in scene.variables if variable_kind(v.name).group not in SEARCH_VARIABLE_GROUPS})
    if other:
        return f"variables {', '.join(other)} are neither microgeometry nor gear geometry"
    if len(names) > search.screen_max_variables:
        return f"{len(names)} variables > screen_max_variables={search.screen_max_variables}"
    low, high = variable_bounds(built)
    if not (np.isfinite(low).all() and np.isfinite(high).all()):
        return "a variable without two finite bounds"
    return None


def variable_bounds(built) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of the scene's design variables (in ``variable_names`` order, variable units)."""
    entries = [built.problem._variables[n] for n in built.variable_names]
    return (np.array([float(e.lower[0]) for e in entries]), np.array([float(e.upper[0]) for e in entries]))


def exact_evaluation(built, values: Mapping[str, float], *, positions: int | None = None,
                     toleranced: bool = True) -> tuple[float, float]:
    """``(exact objective, exact limit violation)`` of the design ``values`` (:func:`exact_ppte_objective`,
    :func:`exact_limit_violation` plus :func:`exact_geometry_violations`; in-scope scenes only); ``(inf, inf)`` for a
    design the exact model refuses (a :class:`~gearopt.errors.GearoptError` from its pair or LTCA). ``positions``: a
    one-slice mesh's exact LTCA positions (default ``check_positions``); ``toleranced``: judge a
    ``ppte_um_toleranced`` limit (its relief variants cost an exact LTCA each: the screen and the polish's steps
    leave them out, the polish's acceptance judges them)."""
    try:
        geometry = sum(exact_geometry_violations(built, values).values())
        exact = built.exact_check(values, positions=positions, toleranced=toleranced, fractions=False, table=False)
    except GearoptError:
        return float("inf"), float("inf")
    return exact_ppte_objective(built, exact), exact_limit_violation(built, exact) + geometry


def exact_screen(built, *, seed: int = 0) -> pd.DataFrame:
    """The exact screen (module docstring, step 1): one row per design -- the declared start (``origin``
    ``"initial"``) and ``screen_samples`` scrambled-Sobol points (``"sobol"``) -- with the variables (columns
    ``variable_names``), ``exact_objective``, ``exact_violation`` and ``rank`` (0 best), sorted by rank. An
    in-scope scene only (:func:`search_scope`)."""
    names = built.variable_names
    low, high = variable_bounds(built)
    samples = built.options.search.screen_samples
    from scipy.stats import qmc   # imported here, not by `import gearopt`: SciPy's statistics and optimisers were
    #                               half of its import time (executor.WORKER_PRELOAD)

    unit = qmc.Sobol(len(names), scramble=True, seed=seed).random_base2(int(np.log2(samples))) if samples else \
        np.zeros((0, len(names)))
    initial = built.initial_values()
    points = np.vstack([[initial[n] for n in names], low + unit * (high - low)])
    rows = []
    for k, point in enumerate(points):
        objective, violation = exact_evaluation(built, dict(zip(names, point)),
                                                positions=built.options.search.screen_positions, toleranced=False)
        rows.append({"origin": "initial" if k == 0 else "sobol", **dict(zip(names, point)),
                     "exact_objective": objective, "exact_violation": violation})
    table = pd.DataFrame(rows)
    order = sorted(range(len(table)), key=lambda i: (rank_key(table["exact_objective"][i],
                                                              table["exact_violation"][i]), i))
    table = table.loc[order].reset_index(drop=True)
    table["rank"] = np.arange(len(table))
    table.attrs.update(samples=samples, seed=seed, evaluations=len(table),
                       positions=built.options.search.screen_positions)
    return table


def screened_starts(screen: pd.DataFrame, names: list[str], starts: int) -> np.ndarray:
    """The ``starts`` best designs of an exact screen as Ipopt starting points, shape ``(starts, variables)``."""
    return screen[names].to_numpy(float)[:max(1, int(starts))]


def exact_polish(built, values: Mapping[str, float]) -> tuple[dict[str, float], pd.DataFrame]:
    """The exact polish (module docstring, step 2) of the design ``values`` on ``built`` (an in-scope scene).

    Returns ``(values, summary)``: the polished design if it improves the exact objective without a larger exact
    limit violation, else ``values`` unchanged; ``summary`` is a one-row table (``start_objective``,
    ``polished_objective``, ``start_violation``, ``polished_violation``, ``evaluations``, ``accepted``)."""
    names = built.variable_names
    low, high = variable_bounds(built)
    span = np.where(high > low, high - low, 1.0)
    x0 = np.array([float(values[n]) for n in names])
    f0, v0 = exact_evaluation(built, values)
    weight = POLISH_PENALTY * max(abs(f0), 1e-9)
    budget = built.options.search.polish_evaluations_per_variable * len(names)
    seen: dict[bytes, tuple[float, float]] = {}

    def design(u: np.ndarray) -> dict[str, float]:
        return dict(zip(names, (float(x) for x in np.clip(low + np.clip(u, 0.0, 1.0) * span, low, high))))

    def merit(u: np.ndarray) -> float:
        key = np.clip(u, 0.0, 1.0).tobytes()
        if key not in seen:
            seen[key] = exact_evaluation(built, design(u), toleranced=False)
        objective, violation = seen[key]
        outside = float(np.sum(np.clip(u - 1.0, 0.0, None) + np.clip(-u, 0.0, None)))   # breaks the clip's plateau
        if not np.isfinite(violation):
            return REFUSED_MERIT * max(abs(f0), 1.0) + abs(f0) * outside
        return objective + weight * violation + abs(f0) * outside

    u0 = (x0 - low) / span
    simplex = [u0] + [u0 + np.where(np.arange(len(u0)) == i, POLISH_STEP if u0[i] <= 1 - POLISH_STEP
                                    else -POLISH_STEP, 0.0) for i in range(len(u0))]
    best_u = u0
    if budget > 0:
        from scipy.optimize import minimize   # imported here (as qmc above)

        res = minimize(merit, u0, method="Nelder-Mead",
                       options={"maxfev": budget, "initial_simplex": np.array(simplex), "xatol": 1e-6,
                                "fatol": 1e-9 * max(abs(f0), 1e-9)})
        best_u = np.clip(res.x, 0.0, 1.0)
    polished = design(best_u)
    f1, v1 = exact_evaluation(built, polished)
    accepted = bool(f1 < f0 and v1 <= max(v0, 0.0) + 1e-12)
    summary = pd.DataFrame([{"start_objective": f0, "polished_objective": f1, "start_violation": v0,
                             "polished_violation": v1, "evaluations": len(seen) + 2, "accepted": accepted}])
    return (polished if accepted else dict(values)), summary


__all__ = ["exact_screen", "exact_polish", "search_scope", "screened_starts", "exact_limit_violation",
           "exact_geometry_violations",
           "exact_ppte_objective", "rank_key", "EXACT_RANK_TOLERANCE", "EXACT_LIMIT_COLUMNS"]
