"""Tests of gearopt.nlp.multistart: Latin-hypercube starts, typed failures kept, success rate, best optimum.

Minima are analytic (roots of the stationarity condition, computed here with numpy.roots) or textbook (Rosenbrock).
"""

from __future__ import annotations

import warnings

import casadi as ca
import numpy as np
import pytest

from gearopt.nlp import Problem
from gearopt.nlp.multistart import MultiStartResult, latin_hypercube, multistart
from gearopt.errors import (
    BadInitialGuessError,
    GearoptInputError,
    InfeasibleProblemError,
    SolveError,
)

TILT = 0.3


def double_well(init: float = 2.0) -> Problem:
    """f(x) = (x^2 - 1)^2 + 0.3 x on [-2, 2]: two minima near -1 (global) and +1 (local)."""
    p = Problem("double well")
    x = p.variable("x", init=init, lower=-2.0, upper=2.0)
    p.minimize((x ** 2 - 1) ** 2 + TILT * x)
    return p


def double_well_minima() -> tuple[float, float]:
    """Stationary points: f'(x) = 4x^3 - 4x + 0.3 = 0; the outer two roots are the minima."""
    roots = np.sort(np.roots([4.0, 0.0, -4.0, TILT]).real)
    return roots[0], roots[2]


def test_global_minimum_found_where_the_default_start_finds_the_local_one():
    global_x, local_x = double_well_minima()
    single = double_well().solve()
    assert single.values["x"] == pytest.approx(local_x, abs=1e-7)
    # with 5 strata on [-2, 2], the stratum [-2, -1.2] always holds one start, which descends to the global minimum
    for seed in range(3):
        ms = double_well().multistart(5, seed=seed)
        assert isinstance(ms, MultiStartResult)
        assert ms.best.values["x"] == pytest.approx(global_x, abs=1e-7)
        f = lambda x: (x ** 2 - 1) ** 2 + TILT * x
        assert ms.best.objective == pytest.approx(f(global_x), abs=1e-10)
        assert ms.success_rate == 1.0
        assert ms.table["objective"].min() == pytest.approx(ms.best.objective)


def test_maximisation_keeps_the_highest_objective():
    """max -(x^2-1)^2 - 0.3x: the same wells; the best of a maximisation is the global maximiser (x near -1)."""
    p = Problem("max well")
    x = p.variable("x", init=2.0, lower=-2.0, upper=2.0)
    p.maximize(-(x ** 2 - 1) ** 2 - TILT * x)
    ms = p.multistart(4, seed=1)
    assert ms.best.values["x"] == pytest.approx(double_well_minima()[0], abs=1e-7)
    assert ms.best.objective == pytest.approx(ms.table["objective"].max())


def test_rosenbrock_in_a_box_every_start_reaches_one_one():
    """(1-x)^2 + 100(y-x^2)^2 on [-2, 2]^2 has one minimum, f = 0 at (1, 1)."""
    p = Problem("rosenbrock")
    x = p.variable("x", init=-1.2, lower=-2.0, upper=2.0)
    y = p.variable("y", init=1.0, lower=-2.0, upper=2.0)
    p.minimize((1 - x) ** 2 + 100 * (y - x ** 2) ** 2)
    ms = p.multistart(6, seed=3, include_initial=True)
    assert len(ms.table) == 7 and ms.table["origin"][0] == "initial"
    assert ms.table["x_init"][0] == -1.2 and ms.table["y_init"][0] == 1.0
    assert ms.success_rate == 1.0
    assert ms.best.values["x"] == pytest.approx(1.0, abs=1e-6)
    assert ms.best.values["y"] == pytest.approx(1.0, abs=1e-6)
    assert (ms.table["iterations"] > 0).all() and (ms.table["wall_time_s"] > 0).all()
    assert p.solver_builds == 1                       # the NLP was built once for all 7 starts


@pytest.mark.parametrize("n, dims", [(1, 1), (7, 3), (50, 5)])
def test_latin_hypercube_has_one_point_per_stratum_in_every_dimension(n, dims):
    u = latin_hypercube(n, dims, np.random.default_rng(11))
    assert u.shape == (n, dims)
    assert ((u >= 0) & (u < 1)).all()
    for j in range(dims):
        assert sorted(np.floor(u[:, j] * n).astype(int)) == list(range(n))


def test_multistart_points_are_latin_in_the_variable_bounds():
    """A vector variable with per-element bounds: each element's starts fill its own strata."""
    p = Problem("box")
    lower, upper = np.array([-1.0, 0.0, 10.0]), np.array([1.0, 5.0, 30.0])
    x = p.variable("x", init=np.array([0.0, 1.0, 20.0]), lower=lower, upper=upper, n=3)
    p.minimize(ca.sumsqr(x - np.array([0.5, 2.0, 15.0])))
    n = 8
    ms = p.multistart(n, seed=5)
    assert ms.dimensions == ["x[0]", "x[1]", "x[2]"]
    assert list(ms.table.columns[2:5]) == ["x[0]_init", "x[1]_init", "x[2]_init"]
    strata = np.floor((ms.starts - lower) / (upper - lower) * n).astype(int)
    for j in range(3):
        assert sorted(strata[:, j]) == list(range(n))
    np.testing.assert_allclose(ms.best.values["x"], [0.5, 2.0, 15.0], atol=1e-7)


def test_same_seed_same_starts_other_seed_other_starts():
    a = double_well().multistart(6, seed=42)
    b = double_well().multistart(6, seed=42)
    c = double_well().multistart(6, seed=43)
    np.testing.assert_array_equal(a.starts, b.starts)
    np.testing.assert_array_equal(a.table["objective"], b.table["objective"])
    assert not np.array_equal(a.starts, c.starts)


def test_declared_initial_guess_is_restored():
    p = double_well(init=1.5)
    p.multistart(3, seed=0)
    assert p.solve().values["x"] == pytest.approx(double_well_minima()[1], abs=1e-7)
    assert p.solve().variables["init"][0] == 1.5


def test_unbounded_variables_keep_their_guess_or_use_the_stated_span():
    """y has no bounds: without span it keeps init 3 in every start; with span 2 (x its scale 0.5) its starts lie
    in 3 +- 1, one per stratum."""
    p = Problem("span")
    x = p.variable("x", init=0.0, lower=-1.0, upper=1.0)
    y = p.variable("y", init=3.0, scale=0.5)
    p.minimize(x ** 2 + (y - 1.0) ** 2)
    ms = p.multistart(4, seed=2)
    assert ms.dimensions == ["x"]
    ms = p.multistart(4, seed=2, span=2.0)
    assert ms.dimensions == ["x", "y"]
    ys = ms.table["y_init"].to_numpy()
    assert sorted(np.floor((ys - 2.0) / 2.0 * 4).astype(int)) == [0, 1, 2, 3]
    ms = p.multistart(4, seed=2, variables=["y"], span={"y": 2.0})
    assert ms.dimensions == ["y"] and (ms.table.columns == "x_init").sum() == 0
    with pytest.raises(GearoptInputError, match="span"):
        p.multistart(4, variables=["y"])


def test_failed_starts_are_recorded_with_their_typed_error():
    """sqrt(x) >= 0.5 on x in [-1, 1]: the constraint is NaN for x < 0, so the two starts of the strata
    [-1, -0.5) and [-0.5, 0) fail the pre-solve check (BadInitialGuessError), the two others solve to x = 0.25."""
    p = Problem("sqrt")
    x = p.variable("x", init=0.5, lower=-1.0, upper=1.0)
    p.subject_to("root", ca.sqrt(x), lower=0.5)
    p.minimize(x)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ms = p.multistart(4, seed=0)
    negative = ms.table["x_init"] < 0
    assert negative.sum() == 2
    assert (ms.table.loc[negative, "error"] == "BadInitialGuessError").all()
    assert (ms.table.loc[negative, "status"] == "bad_initial_guess").all()
    assert not ms.table.loc[negative, "success"].any()
    assert ms.success_rate == 0.5
    assert all(isinstance(ms.errors[k], BadInitialGuessError) for k in np.flatnonzero(negative))
    assert all(ms.results[k] is None for k in np.flatnonzero(negative))
    assert ms.best.values["x"] == pytest.approx(0.25, abs=1e-7)
    assert ms.status_counts()["bad_initial_guess"] == 2


def test_all_starts_failing_raise_the_typed_error_of_the_least_infeasible():
    """x >= 2 with x^2 <= 1 on [-3, 3] is infeasible from everywhere."""
    p = Problem("impossible")
    x = p.variable("x", init=0.0, lower=-3.0, upper=3.0)
    p.subject_to("x_min", x, lower=2.0)
    p.subject_to("square_max", x ** 2, upper=1.0)
    p.minimize(x)
    with pytest.raises(SolveError) as info:
        p.multistart(3, seed=0)
    err = info.value
    assert isinstance(err, InfeasibleProblemError)
    assert "all 3 multi-start runs failed" in str(err)
    assert err.status and err.violated
    assert len(err.multistart) == 3 and not err.multistart["success"].any()
    assert set(err.multistart["error"]) == {"InfeasibleProblemError"}


def test_input_errors():
    p = double_well()
    for bad in (0, -1, 2.5, True):
        with pytest.raises(GearoptInputError, match="n="):
            multistart(p, bad)
    with pytest.raises(GearoptInputError, match="nope"):
        p.multistart(3, variables=["nope"])
    with pytest.raises(GearoptInputError, match="warm_start"):
        p.multistart(3, warm_start=True)
    with pytest.raises(GearoptInputError, match=r"span\['x'\]"):
        p.multistart(3, span=-1.0)
