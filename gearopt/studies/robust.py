"""Robust design of a scene: its limits held at every corner of the tolerance box (or at a sample set) inside the NLP.

:func:`robust_design` builds the scene with its data as parameters, then, for each corner ``δ`` of the box spanned
by the tolerances (``2^k`` corners for ``k`` tolerances) -- or each of ``samples`` points drawn inside it -- adds
a copy of every limit of the scene evaluated at the design and data moved by ``δ``: one CasADi Function of the
limit's elements called at the shifted point, so the copies share the models already built. The objective stays
the nominal one. For quantities monotone over the box (small tolerances) the corners are the worst cases, and the
robust optimum keeps every limit over the whole box; compare it with the nominal optimum on the same
:func:`~gearopt.studies.monte_carlo.monte_carlo` samples. A limit on a peak-to-peak (``ppte_um``) is held at the
nominal point only (its epigraph variables would have to be copied per corner).
"""

from __future__ import annotations

import itertools
import warnings
from typing import Any, Sequence

import casadi as ca
import numpy as np

from ..design.scene import BuiltScene, Scene, SceneResult
from ..design.scene_terms import variable_kind
from ..errors import GearoptInputError
from ..nlp import InitialGuessWarning
from .tolerances import Tolerance, default_tolerances

MAX_CORNERS = 1024


def robust_design(scene: Scene, tolerances: Sequence[Tolerance] | None = None, *, samples: int | None = None,
                  seed: int = 0, start: SceneResult | None = None, **solve: Any) -> SceneResult:
    """The scene's optimum with its limits held over the tolerances (see the module docstring).

    Args:
        scene: the scene (design variables, objective, limits).
        tolerances: :class:`Tolerance` list (design variables ``"target.name"`` or data such as
            ``"torque_Nm[mesh]@case"``); default :func:`~gearopt.studies.tolerances.default_tolerances`.
        samples: ``None``: the corners of the tolerance box; ``n``: ``n`` points drawn uniformly (numpy PCG64 at
            ``seed``) in the box of each tolerance's interval.
        start: a solved result of the same scene (the nominal optimum) to start from instead of the declared guess.
        **solve: keyword arguments of ``BuiltScene.solve`` (``starts``, Ipopt options, ``check``; ``refine``
            defaults to False: the semi-infinite refinement rebuilds the scene, which would drop the corners).

    Returns:
        the :class:`SceneResult` of the robust optimum (its ``quantities`` are the nominal ones).
    """
    source = getattr(start, "source", None)
    # from a nominal optimum: its NLP as it was solved (a refinement's mesh positions included), data as parameters
    # the nested approach: each shifted copy of a limit solves its own contact (a lifted approach is one per position)
    built = source.parametric_twin(approach="nested") if source is not None and source.scene is scene else \
        BuiltScene(scene, parametric=True, options={"approach": "nested"})
    problem = built.problem
    opti = problem.opti
    names_x, names_p = list(problem.variable_names), list(problem.parameter_names)
    params = ca.vertcat(*[built.data_parameters[n]["symbol"] for n in names_p])   # all declared, in order
    design = [f"{v.target}.{v.name}" for v in scene.variables]
    if tolerances is None:
        tols = default_tolerances(design, names_p)
    else:
        tols = list(tolerances)
    if not tols:
        raise GearoptInputError(f"robust_design: no tolerance applies to the scene's inputs ({design + names_p})")
    deltas = _deltas(tols, samples, seed)
    dx = np.zeros((len(deltas), opti.nx))
    dp = np.zeros((len(deltas), len(names_p)))
    vscale = {f"{v.target}.{v.name}": v.scale or variable_kind(v.name).scale for v in scene.variables}
    for k, t in enumerate(tols):
        if t.name in design:
            dx[:, names_x.index(t.name)] = deltas[:, k] / vscale[t.name]
        elif t.name in names_p:
            dp[:, names_p.index(t.name)] = deltas[:, k]
        else:
            raise GearoptInputError(f"tolerance {t.name!r} is not a design variable or datum of the scene "
                                    f"({design + names_p})")
    for rec in built.records:
        kind, expr = rec["kind"], rec["expr"]
        if rec["role"] != "limit" or kind.shape in ("named", "ppte") or isinstance(expr, (int, float)):
            continue
        lower, upper, scale, unit = rec["lower"], rec["upper"], kind.scale, kind.unit
        if kind.squared:
            upper, scale, unit = upper ** 2, upper ** 2 / 100.0, f"({unit})^2"
        fn = ca.Function("limit", [opti.x, params], [ca.vec(ca.MX(expr))])
        for c in range(len(deltas)):
            shifted = fn(opti.x + ca.DM(dx[c]), params + ca.DM(dp[c]))
            problem.subject_to(f"robust[{c}].{rec['label']}", shifted, lower=lower, upper=upper, scale=scale,
                               unit=unit)
    if start is not None:
        for name, value in start.solve.values.items():
            if name in names_x:
                problem.set_initial(name, value)
    with warnings.catch_warnings():      # the nominal optimum may sit on a bound (read as just outside it)
        warnings.simplefilter("ignore", InitialGuessWarning)
        # the corner constraints live in this build: a refinement would re-build the scene without them
        return built.solve(**{"refine": False, **solve})


def _deltas(tols: list[Tolerance], samples: int | None, seed: int) -> np.ndarray:
    if samples is None:
        if 2 ** len(tols) > MAX_CORNERS:
            raise GearoptInputError(f"{len(tols)} tolerances have 2^{len(tols)} corners; limit: {MAX_CORNERS} "
                                    f"(give samples=n)")
        return np.array(list(itertools.product(*[(t.lower, t.upper) for t in tols])), dtype=float)
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1:
        raise GearoptInputError(f"samples={samples!r} must be an integer >= 1 (or None for the corners)")
    u = np.random.default_rng(seed).random((int(samples), len(tols)))
    return np.column_stack([t.lower + (t.upper - t.lower) * u[:, k] for k, t in enumerate(tols)])


__all__ = ["robust_design", "MAX_CORNERS"]
