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

from ..errors import GearoptError, GearoptInputError
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
    ``lower``, ``upper``, ``probability_broken``; with an exact re-check also ``exact_nominal``, ``exact_mean``,
    ``exact_probability_broken``, its binomial standard error ``exact_probability_broken_se``,
    ``smooth_error_max`` and ``exact_samples``); ``tolerances`` used; ``inputs``/``quantities``: column names;
    ``exact_samples``: samples re-evaluated by the exact model (their exact values in the table as
    ``exact:<quantity>``); ``exact_note``: why there is no exact re-check where one was asked for."""

    table: pd.DataFrame
    summary: pd.DataFrame
    tolerances: list[Tolerance]
    inputs: list[str]
    quantities: list[str]
    seed: int
    method: str
    exact_samples: int = 0
    exact_note: str = ""


def monte_carlo(result, samples: int = 1000, seed: int = 0, executor: Any = "serial",
                tolerances: Sequence[Tolerance] | None = None, *, method: str = "random",
                workers: int | None = None, progress: bool | None = None,
                exact_samples: int = 0) -> MonteCarloResult:
    """Monte Carlo of a solved scene over its tolerances (see the module docstring).

    The samples are evaluated by the scene's smooth model (the NLP's LTCA at its positions), an approximation of the
    exact LTCA; around a design whose exact polish put a limit exactly on its bound the smooth model's offset moves
    the probability of breaking it (measured on the packaged data's tip-relief scene of its root mesh: contact
    stress at 450 N m smooth 944.2 MPa, exact 945.5 MPa = the limit). ``exact_samples`` > 0 re-evaluates the
    reported design and the first ``exact_samples`` samples (a random subsample: the samples are independent; for
    ``method="sobol"`` the first points of the sequence) with the exact LTCA (``BuiltScene.exact_check``) and
    tables, beside the smooth statistics, the exact nominal, mean and probability of breaking each limit (with its
    binomial standard error) and the largest difference of smooth and exact values over the subsample. It needs
    design-variable tolerances only (the exact check takes no perturbed data): with tolerances of data the re-check
    is not made and ``exact_note`` says so.

    Args:
        result: a solved scene (``scene.build().solve()``).
        samples: number of samples (>= 1); for ``method="sobol"`` a power of two balances the sequence.
        seed: seed of the sampling (the same seed gives the same table whichever executor runs it).
        executor: ``"serial"``, ``"processes"``, ``"dask"``, a ``dask.distributed.Client`` or an Executor.
        tolerances: :class:`Tolerance` list; default :func:`default_tolerances` of the scene's inputs.
        method: ``"random"`` or ``"sobol"`` (scrambled Sobol' points, quasi-Monte Carlo).
        exact_samples: samples re-evaluated by the exact LTCA (0: none; at most ``samples``).

    Raises:
        GearoptInputError: zero or negative samples, an unknown method, a tolerance naming no input of the scene,
            no tolerance at all, a negative ``exact_samples``.
    """
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 1:
        raise GearoptInputError(f"samples={samples!r} must be an integer >= 1")
    if isinstance(exact_samples, bool) or not isinstance(exact_samples, (int, np.integer)) or exact_samples < 0:
        raise GearoptInputError(f"exact_samples={exact_samples!r} must be an integer >= 0")
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
    summary, n_exact, note = pd.DataFrame(rows), 0, ""
    if exact_samples:
        n_exact = min(int(exact_samples), int(samples))
        note = _exact_recheck(result, evaluator, tols, table, summary, n_exact)
        n_exact = 0 if note else n_exact
    return MonteCarloResult(table, summary, tols, list(values), list(outputs), int(seed), method, n_exact, note)


EXACT_TIE_RTOL = 1e-9
"""An exact value within this fraction of its limit is on the limit, not beyond it: a quantity the design cannot move
(a contact stress in single-pair contact, where tip relief does not act, under a limit set to the unmodified pair's
own maximum) equals its limit to rounding, and rounding must not count as a break."""


def _exactly_broken(evaluator: SceneEvaluator, label: str, values: np.ndarray) -> np.ndarray:
    """Whether each exact value lies beyond its limit by more than :data:`EXACT_TIE_RTOL` (False for an objective)."""
    _, _, _, _, lo, hi, _ = evaluator.quantities[label]
    out = np.zeros(np.shape(values), dtype=bool)
    if lo is not None:
        out |= values < lo - EXACT_TIE_RTOL * abs(lo)
    if hi is not None:
        out |= values > hi + EXACT_TIE_RTOL * abs(hi)
    return out


def _exact_recheck(result, evaluator: SceneEvaluator, tols: list[Tolerance], table: pd.DataFrame,
                   summary: pd.DataFrame, n: int) -> str:
    """The exact re-check of :func:`monte_carlo` (``exact_samples``): adds ``exact:<quantity>`` columns to the first
    ``n`` rows of ``table`` and the exact statistics to ``summary`` (in place). Returns ``""``, or why it was not
    made."""
    data = [t.name for t in tols if evaluator.inputs[t.name][0] != "variable"]
    if data:
        return (f"no exact re-check: tolerances of data ({', '.join(data)}) -- the exact check evaluates designs "
                f"at the scene's data")
    built = result.source
    design = dict(result.values)
    labels = list(summary["quantity"])

    def exact_at(values: dict) -> dict[str, float]:
        cols = built.exact_check(values, fractions=False, table=False)
        out = {}
        for label in labels:
            quantity, target, case = evaluator.keys.get(label, ("", "", ""))
            rows = (cols["mesh"] == target) & (cols["load_case"] == case) if quantity in cols else np.zeros(0, bool)
            out[label] = float(np.asarray(cols[quantity], dtype=float)[rows][0]) if rows.any() else np.nan
        return out

    def exact_or_nan(values: dict) -> dict[str, float]:     # a design the exact model refuses: NaN, not counted
        try:
            return exact_at(values)
        except GearoptError:
            return {label: np.nan for label in labels}

    nominal = exact_or_nan(design)
    names = [t.name for t in tols]
    exact = [exact_or_nan({**design, **{k: float(table.at[i, k]) for k in names}}) for i in range(n)]
    for label in labels:
        v = np.array([e[label] for e in exact])
        table.loc[:n - 1, f"exact:{label}"] = v
        smooth = table.loc[:n - 1, label].to_numpy(float)
        ok = np.isfinite(v)
        i = summary.index[summary["quantity"] == label][0]
        p = float(_exactly_broken(evaluator, label, v[ok]).mean()) if ok.any() else np.nan
        summary.loc[i, "exact_nominal"] = nominal[label]
        summary.loc[i, "exact_mean"] = float(v[ok].mean()) if ok.any() else np.nan
        summary.loc[i, "exact_probability_broken"] = p
        summary.loc[i, "exact_probability_broken_se"] = float(np.sqrt(p * (1 - p) / ok.sum())) if ok.any() else np.nan
        both = ok & np.isfinite(smooth)
        summary.loc[i, "smooth_error_max"] = float(np.max(np.abs(smooth[both] - v[both]))) if both.any() else np.nan
        summary.loc[i, "exact_samples"] = int(ok.sum())
    return ""


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
