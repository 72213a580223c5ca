"""Every quantity of a solved scene as one CasADi Function of its inputs, evaluated over batches of samples.

:func:`scene_evaluator` rebuilds the scene with its data as parameters (``Scene.build(parametric=True)``) and makes
one :class:`casadi.Function` from the NLP's variables and parameters to the elements of every objective and limit
quantity. :class:`SceneEvaluator` is plain picklable data (the Function, index tables, bounds), so an executor's
workers evaluate it without rebuilding anything; a batch is one call of the Function's ``map`` over the samples
(vectorised), then each quantity is reduced from its elements as the scene reports it (largest value,
peak-to-peak of a TE column, square root of a squared stress).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from ..errors import GearoptInputError


@dataclass
class SceneEvaluator:
    """Quantities of a scene as functions of its inputs (see the module docstring).

    ``inputs``: input name -> (kind ``"variable"``/``"parameter"``, row in x or p, scale, nominal, unit);
    ``quantities``: label -> (first, last element, shape, squared, lower, upper, unit); ``keys``: label ->
    (quantity, target, load case or ``""``)."""

    function: ca.Function
    x_nominal: np.ndarray
    p_nominal: np.ndarray
    inputs: dict[str, tuple[str, int, float, float, str]]
    quantities: dict[str, tuple[int, int, str, bool, float | None, float | None, str]]
    _mapped: dict[int, ca.Function] = field(default_factory=dict, repr=False)
    keys: dict[str, tuple[str, str, str]] = field(default_factory=dict)

    def nominal(self, name: str) -> float:
        if name not in self.inputs:
            raise GearoptInputError(f"input {name!r} is not a design variable or datum of the scene "
                                    f"({sorted(self.inputs)})")
        return self.inputs[name][3]

    def evaluate(self, values: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """Every quantity at ``n`` samples of the inputs named in ``values`` (arrays of length n, input units; the
        others at nominal). Returns label -> array of n values (NaN where the model gave a non-finite element)."""
        n = len(next(iter(values.values()))) if values else 1
        X = np.repeat(self.x_nominal[:, None], n, axis=1)
        P = np.repeat(self.p_nominal[:, None], n, axis=1)
        for name, v in values.items():
            kind, row, scale, _, _ = self.inputs[name]
            if kind == "variable":
                X[row] = np.asarray(v, dtype=float) / scale
            else:
                P[row] = np.asarray(v, dtype=float)
        if n not in self._mapped:
            self._mapped[n] = self.function.map(n)
        out = np.asarray(self._mapped[n](X, P).full(), dtype=float) if n > 0 else np.zeros((0, 0))
        result = {}
        for label, (a, b, shape, squared, _, _, _) in self.quantities.items():
            block = out[a:b]
            if shape == "ppte":
                v = block.max(axis=0) - block.min(axis=0)
            elif shape == "max":
                v = block.max(axis=0)
            elif shape == "min":
                v = block.min(axis=0)
            else:
                v = block[0]
            if squared:
                v = np.sqrt(np.maximum(v, 0.0))
            bad = ~np.isfinite(block).all(axis=0)
            result[label] = np.where(bad, np.nan, v)
        return result

    def broken(self, label: str, values: np.ndarray) -> np.ndarray:
        """Whether each value breaks the quantity's limit (False for an objective)."""
        _, _, _, _, lo, hi, _ = self.quantities[label]
        out = np.zeros(np.shape(values), dtype=bool)
        if lo is not None:
            out |= values < lo
        if hi is not None:
            out |= values > hi
        return out

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_mapped"] = {}
        return state


def scene_evaluator(result) -> SceneEvaluator:
    """The :class:`SceneEvaluator` of a solved scene result, at its reported design (``result.values``: the NLP's
    optimum, or where the exact polish moved it, the polished design -- the design ``result.quantities`` describes)
    and its data's nominal values."""
    built = getattr(result, "source", None)
    if built is None:
        raise GearoptInputError(f"result={type(result).__name__} must be the SceneResult of a solved scene "
                                f"(scene.build().solve())")
    pb = built.parametric_twin(approach="nested")   # quantities of perturbed inputs: each approach re-solved
    problem = pb.problem
    opti = problem.opti
    vtable = result.solve.variables.set_index("name")
    x0 = []
    inputs: dict[str, tuple[str, int, float, float, str]] = {}
    design = {f"{v.target}.{v.name}" for v in built.scene.variables}
    reported = getattr(result, "values", {}) or {}
    for i, name in enumerate(problem.variable_names):
        scale = float(vtable.loc[name, "scale"])
        value = float(reported[name]) if name in reported else float(vtable.loc[name, "value"])
        x0.append(value / scale)
        if name in design:
            inputs[name] = ("variable", i, scale, value, str(vtable.loc[name, "unit"]))
    for j, name in enumerate(problem.parameter_names):
        entry = pb.data_parameters[name]
        inputs[name] = ("parameter", j, 1.0, float(entry["value"]), entry["unit"])
    exprs, quantities, keys, row = [], {}, {}, 0
    for rec in pb.records:
        kind, expr = rec["kind"], rec["expr"]
        if kind.shape == "named":
            continue
        mx = ca.vec(ca.MX(expr))
        n = int(mx.numel())
        exprs.append(mx)
        lo, hi = rec["lower"], rec["upper"]
        quantities[rec["label"]] = (row, row + n, kind.shape, kind.squared, lo, hi, kind.unit)
        keys[rec["label"]] = (rec["quantity"], rec["target"], rec["load_case"] or "")
        row += n
    params = ca.vertcat(*[pb.data_parameters[n]["symbol"] for n in problem.parameter_names])  # all declared
    fn = ca.Function("scene_quantities", [opti.x, params], [ca.vertcat(*exprs)])
    p0 = np.array([pb.data_parameters[n]["value"] for n in problem.parameter_names], dtype=float)
    return SceneEvaluator(fn, np.asarray(x0, dtype=float), p0, inputs, quantities, keys=keys)


STATUS = "_status"
"""Key of the per-sample status in the output of :func:`evaluate_chunk`."""


def evaluate_chunk(task: tuple[SceneEvaluator, dict[str, np.ndarray]]) -> dict[str, np.ndarray]:
    """Executor task: :meth:`SceneEvaluator.evaluate` of one chunk of samples, plus a status per sample (``"ok"``,
    ``"NonFiniteOutput"``, or the class name of the exception the model raised at that sample: then the chunk is
    evaluated sample by sample, so one bad sample does not take the others with it)."""
    evaluator, values = task
    n = len(next(iter(values.values()))) if values else 1
    try:
        out = evaluator.evaluate(values)
        status = np.full(n, "ok", dtype=object)
    except Exception:  # noqa: BLE001  (recorded per sample below, by class name)
        out = {label: np.full(n, np.nan) for label in evaluator.quantities}
        status = np.full(n, "ok", dtype=object)
        for i in range(n):
            try:
                one = evaluator.evaluate({k: np.asarray(v)[i:i + 1] for k, v in values.items()})
            except Exception as exc:  # noqa: BLE001
                status[i] = type(exc).__name__
                continue
            for label, v in one.items():
                out[label][i] = v[0]
    finite = np.all(np.isfinite(np.column_stack(list(out.values()))), axis=1) if out else np.ones(n, bool)
    status[(status == "ok") & ~finite] = "NonFiniteOutput"
    out[STATUS] = status
    return out


__all__ = ["SceneEvaluator", "scene_evaluator", "evaluate_chunk", "STATUS"]
