"""Tolerance robustness of a solved scene: Monte Carlo / quasi-Monte Carlo over its tolerances, Sobol indices.

:func:`monte_carlo` draws the toleranced inputs (design variables and data, :mod:`gearopt.studies.tolerances`) --
pseudo-random (``numpy`` PCG64 at ``seed``) or a scrambled Sobol' sequence (``method="sobol"``, quasi-Monte Carlo,
:class:`scipy.stats.qmc.Sobol`) -- in the calling process, evaluates every quantity of the scene at each sample in
chunks on the executor (one vectorised CasADi ``map`` call per chunk, :mod:`gearopt.studies.evaluator`) and tables
the distributions: mean, standard deviation, 5/95 % quantiles and the probability that each limit is broken. The
samples and the chunks do not depend on the executor, so the table is the same for ``"serial"``, ``"processes"``
and ``"dask"``. A sample whose model output is not finite is kept with ``status = "NonFiniteOutput"``, one where the
model raised with the exception's class name; the summary counts the ``"ok"`` samples.

:func:`sobol_indices` gives first-order and total Sobol indices of each quantity with respect to each toleranced
input (Saltelli 2002 sampling and estimators as implemented by SALib: Herman & Usher 2017, "SALib: an open-source
Python library for sensitivity analysis", JOSS 2(9)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np
import pandas as pd

from ..errors import GearoptInputError
from .evaluator import STATUS, SceneEvaluator, evaluate_chunk, scene_evaluator
from .executor import using_executor
from .tolerances import Tolerance, default_tolerances

CHUNK = 256
"""Samples per executor task (fixed, so the chunks do not depend on the executor)."""

METHODS = ("random", "sobol")


@dataclass
class MonteCarloResult:
    """``table``: one row per sample (``sample``, ``status``, the perturbed inputs, every quantity of the scene);
    ``summary``: one row per quantity (``quantity``, ``unit``, ``nominal``, ``mean``, ``std``, ``p05``, ``p95``,
    ``lower``, ``upper``, ``probability_broken``); ``tolerances`` used; ``inputs``/``quantities``: column names."""

    table: pd.DataFrame
    summary: pd.DataFrame
    tolerances: list[Tolerance]
    inputs: list[str]
    quantities: list[str]
    seed: int
    method: str


def monte_carlo(result, samples: int = 1000, seed: int = 0, executor: Any = "serial",
                tolerances: Sequence[Tolerance] | None = None, *, method: str = "random",
                workers: int | None = None, progress: bool | None = None) -> MonteCarloResult:
    """Monte Carlo of a solved scene over its tolerances (see the module docstring).

    Args:
        result: a solved scene (``scene.build().solve()``).
        samples: number of samples (>= 1); for ``method="sobol"`` a power of two balances the sequence.
        seed: seed of the sampling (the same seed gives the same table whichever executor runs it).
        executor: ``"serial"``, ``"processes"``, ``"dask"``, a ``dask.distributed.Client`` or an Executor.
        tolerances: :class:`Tolerance` list; default :func:`default_tolerances` of the scene's inputs.
        method: ``"random"`` or ``"sobol"`` (scrambled Sobol' points, quasi-Monte Carlo).

    Raises:
        GearoptInputError: zero or negative samples, an unknown method, a tolerance naming no input of the scene,
            no tolerance at all.
    """
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1:
        raise GearoptInputError(f"samples={samples!r} must be an integer >= 1")
    if method not in METHODS:
        raise GearoptInputError(f"method={method!r} must be one of {METHODS}")
    evaluator = scene_evaluator(result)
    tols = _tolerances(evaluator, tolerances)
    u = _unit_samples(len(tols), int(samples), int(seed), method)
    values = {t.name: evaluator.nominal(t.name) + t.deviation(u[:, k]) for k, t in enumerate(tols)}
    outputs = _run(evaluator, values, int(samples), executor, workers, progress)
    status = outputs.pop(STATUS)
    table = pd.DataFrame({"sample": np.arange(samples)})
    table["status"] = status.astype(str)
    finite = status == "ok"
    for name, v in values.items():
        table[name] = v
    for label, v in outputs.items():
        table[label] = v
    nominal = evaluator.evaluate({})
    rows = []
    for label, v in outputs.items():
        _, _, _, _, lo, hi, unit = evaluator.quantities[label]
        ok = v[finite]
        rows.append({"quantity": label, "unit": unit, "nominal": float(nominal[label][0]),
                     "mean": float(ok.mean()) if ok.size else np.nan,
                     "std": float(ok.std(ddof=1)) if ok.size > 1 else 0.0,
                     "p05": float(np.quantile(ok, 0.05)) if ok.size else np.nan,
                     "p95": float(np.quantile(ok, 0.95)) if ok.size else np.nan,
                     "lower": lo, "upper": hi,
                     "probability_broken": float(evaluator.broken(label, ok).mean()) if ok.size else np.nan})
    return MonteCarloResult(table, pd.DataFrame(rows), tols, list(values), list(outputs), int(seed), method)


def sobol_indices(result, samples: int = 256, seed: int = 0, executor: Any = "serial",
                  tolerances: Sequence[Tolerance] | None = None, *, workers: int | None = None,
                  progress: bool | None = None) -> pd.DataFrame:
    """First-order (``S1``) and total (``ST``) Sobol indices, with 95 % confidence half-widths, of every quantity
    of a solved scene with respect to every toleranced input. ``samples``: SALib's base sample count N (a power of
    two); the model is evaluated N (2k + 2) times for k inputs. Rows: ``quantity``, ``input``, ``S1``,
    ``S1_conf``, ``ST``, ``ST_conf``. A quantity that does not vary gets zeros."""
    from SALib.analyze import sobol as sobol_analyze
    from SALib.sample import sobol as sobol_sample

    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 2:
        raise GearoptInputError(f"samples={samples!r} must be an integer >= 2 (a power of two)")
    evaluator = scene_evaluator(result)
    tols = _tolerances(evaluator, tolerances)
    names = [t.name for t in tols]
    problem = {"num_vars": len(tols), "names": names, "bounds": [[0.0, 1.0]] * len(tols)}
    u = sobol_sample.sample(problem, int(samples), calc_second_order=False, seed=int(seed))
    u = np.clip(u, 0.0, np.nextafter(1.0, 0.0))
    values = {t.name: evaluator.nominal(t.name) + t.deviation(u[:, k]) for k, t in enumerate(tols)}
    outputs = _run(evaluator, values, len(u), executor, workers, progress)
    outputs.pop(STATUS)
    rows = []
    for label, y in outputs.items():
        if not np.all(np.isfinite(y)):
            raise GearoptInputError(f"quantity {label!r} is not finite at some Sobol samples; narrow the tolerances")
        if np.ptp(y) <= 1e-12 * max(1.0, float(np.abs(y).max())):
            res = {"S1": np.zeros(len(names)), "S1_conf": np.zeros(len(names)), "ST": np.zeros(len(names)),
                   "ST_conf": np.zeros(len(names))}
        else:
            res = sobol_analyze.analyze(problem, y, calc_second_order=False, seed=int(seed))
        for k, name in enumerate(names):
            rows.append({"quantity": label, "input": name, "S1": float(res["S1"][k]),
                         "S1_conf": float(res["S1_conf"][k]), "ST": float(res["ST"][k]),
                         "ST_conf": float(res["ST_conf"][k])})
    return pd.DataFrame(rows)


def _tolerances(evaluator: SceneEvaluator, tolerances: Sequence[Tolerance] | None) -> list[Tolerance]:
    if tolerances is None:
        variables = [n for n, v in evaluator.inputs.items() if v[0] == "variable"]
        parameters = [n for n, v in evaluator.inputs.items() if v[0] == "parameter"]
        tols = default_tolerances(variables, parameters)
    else:
        tols = list(tolerances)
        for t in tols:
            if not isinstance(t, Tolerance):
                raise GearoptInputError(f"tolerances: {t!r} is not a gearopt.studies.Tolerance")
            evaluator.nominal(t.name)
        names = [t.name for t in tols]
        if len(set(names)) != len(names):
            raise GearoptInputError(f"tolerances name an input twice ({names})")
    if not tols:
        raise GearoptInputError(f"no tolerance applies to the scene's inputs ({sorted(evaluator.inputs)}); give "
                                f"tolerances=[Tolerance(...)]")
    return tols


def _unit_samples(k: int, n: int, seed: int, method: str) -> np.ndarray:
    if method == "sobol":
        from scipy.stats import qmc

        m = math.ceil(math.log2(max(n, 2)))
        return qmc.Sobol(d=k, scramble=True, seed=seed).random_base2(m)[:n]
    return np.random.default_rng(seed).random((n, k))


def _run(evaluator: SceneEvaluator, values: dict[str, np.ndarray], n: int, executor, workers, progress):
    starts = list(range(0, n, CHUNK))
    tasks = [(evaluator, {k: v[s:s + CHUNK] for k, v in values.items()}) for s in starts]
    with using_executor(executor, workers=workers, progress=progress) as ex:
        parts = ex.map(evaluate_chunk, tasks, desc="samples")
    return {label: np.concatenate([p[label] for p in parts]) for label in [*evaluator.quantities, STATUS]}


__all__ = ["monte_carlo", "sobol_indices", "MonteCarloResult", "CHUNK", "METHODS"]
