"""Tests of gearopt.design.Problem: optimum, multipliers, scaling, parameters, pre-solve check, typed failures.

Every reference value is analytic (derived in the comment next to it), not produced by this code.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from gearopt.nlp import InitialGuessWarning, Problem, ProblemResult
from gearopt.errors import (BadInitialGuessError, GearoptInputError, InfeasibleProblemError, IterationLimitError,
                            SolveError)

THIS_FILE = "test_problem.py"


def rosenbrock(name: str = "rosenbrock") -> Problem:
    """f = (1-x)^2 + 100 (y-x^2)^2, unique minimum f=0 at (1, 1); classic start (-1.2, 1)."""
    p = Problem(name)
    x = p.variable("x", init=-1.2)
    y = p.variable("y", init=1.0)
    p.minimize((1 - x) ** 2 + 100 * (y - x ** 2) ** 2)
    return p


def circle_problem(var_scale: float = 1.0, con_scale: float = 1.0) -> Problem:
    """min x^2 + y^2 s.t. x + y >= 1 (active), x <= 2 (inactive).

    KKT: 2x = 2y = lambda, x + y = 1 -> x = y = 1/2, f* = 1/2. With the bound c of x + y >= c, f*(c) = c^2/2, so
    d f*/d c = c = 1: the multiplier is 1.
    """
    p = Problem("circle")
    x = p.variable("x", init=0.0, scale=var_scale)
    y = p.variable("y", init=0.0, scale=var_scale)
    p.subject_to("sum_min", x + y, lower=1.0, scale=con_scale)
    p.subject_to("x_max", x, upper=2.0, scale=con_scale)
    p.minimize(x ** 2 + y ** 2)
    return p


# --------------------------------------------------------------------------- optimum and multipliers

def test_rosenbrock_minimum_found():
    res = rosenbrock().solve()
    assert isinstance(res, ProblemResult)
    assert res.success and res.status == "Solve_Succeeded"
    assert res.values["x"] == pytest.approx(1.0, abs=1e-7)
    assert res.values["y"] == pytest.approx(1.0, abs=1e-7)
    assert res.objective == pytest.approx(0.0, abs=1e-12)
    assert res.iterations > 5
    assert res.solve_time_s > 0 and res.build_time_s > 0


def test_kkt_multiplier_and_constraint_table():
    res = circle_problem().solve()
    assert res.values["x"] == pytest.approx(0.5, abs=1e-7)
    assert res.values["y"] == pytest.approx(0.5, abs=1e-7)
    assert res.objective == pytest.approx(0.5, abs=1e-7)
    table = res.constraints.set_index("name")
    active = table.loc["sum_min"]
    assert active["multiplier"] == pytest.approx(1.0, rel=1e-6)
    assert res.multipliers["sum_min"] == pytest.approx(1.0, rel=1e-6)
    assert active["margin"] == pytest.approx(0.0, abs=1e-7)
    assert bool(active["active"]) is True
    assert (active["lower"], active["upper"]) == (1.0, np.inf)
    assert THIS_FILE in active["source"]
    inactive = table.loc["x_max"]
    # x = 0.5 against x <= 2: margin 1.5 in the constraint's units, no multiplier.
    assert inactive["margin"] == pytest.approx(1.5, abs=1e-7)
    assert abs(inactive["multiplier"]) < 1e-6
    assert bool(inactive["active"]) is False


def test_equality_and_upper_bound_multiplier_signs():
    # Equality x + y == c: same optimum and f*(c) = c^2/2, so the multiplier is again 1.
    p = Problem("equality")
    x = p.variable("x", init=0.0)
    y = p.variable("y", init=0.0)
    p.subject_to("sum_eq", x + y, lower=1.0, upper=1.0)
    p.minimize(x ** 2 + y ** 2)
    res = p.solve()
    assert res.multipliers["sum_eq"] == pytest.approx(1.0, rel=1e-6)

    # min (x-2)^2 s.t. x^2 <= u with u = 1: x* = 1, f*(u) = (sqrt(u) - 2)^2, d f*/d u = (sqrt(u)-2)/sqrt(u) = -1.
    q = Problem("upper")
    x = q.variable("x", init=0.0)
    q.subject_to("x_sq_max", x ** 2, upper=1.0)
    q.minimize((x - 2) ** 2)
    res = q.solve()
    assert res.values["x"] == pytest.approx(1.0, abs=1e-7)
    assert res.multipliers["x_sq_max"] == pytest.approx(-1.0, rel=1e-6)

    # Maximising -(x-2)^2 instead: objective* = -f*, so d objective*/d u = +1.
    m = Problem("upper_max")
    x = m.variable("x", init=0.0)
    m.subject_to("x_sq_max", x ** 2, upper=1.0)
    m.maximize(-(x - 2) ** 2)
    res = m.solve()
    assert res.objective == pytest.approx(-1.0, abs=1e-7)
    assert res.multipliers["x_sq_max"] == pytest.approx(1.0, rel=1e-6)


def test_variable_bound_reported_at_bound_with_multiplier():
    # min (x-3)^2 with x <= 1: x* = 1, f*(u) = (u-3)^2, d f*/d u = -4.
    p = Problem("bounded")
    x = p.variable("x", init=0.0, lower=-1.0, upper=1.0, scale=2.0, unit="mm")
    p.minimize((x - 3) ** 2)
    res = p.solve()
    row = res.variables.set_index("name").loc["x"]
    assert row["value"] == pytest.approx(1.0, abs=1e-7)
    assert bool(row["at_bound"]) is True
    assert row["multiplier"] == pytest.approx(-4.0, rel=1e-6)
    assert row["unit"] == "mm"


# --------------------------------------------------------------------------- scaling

def projection_problem(var_scale: float, con_scale: float) -> Problem:
    """Project (3, 2) onto the half-plane x + y <= 1 inside the disc x^2 + y^2 <= 9, with a vector variable.

    Analytic: the point is (3, 2) - t (1, 1) with 5 - 2t = 1, t = 2 -> (1, 0) (inside the disc, |.|^2 = 1 < 9).
    f*(u) = (5 - u)^2 / 2, so the multiplier of x + y <= u is -(5 - u) = -4; the disc is inactive.
    """
    p = Problem("projection")
    z = p.variable("z", init=[0.5, -0.5], scale=var_scale, n=2)
    p.subject_to("half_plane", z[0] + z[1], upper=1.0, scale=con_scale)
    p.subject_to("disc", ca.sumsqr(z), upper=9.0, scale=con_scale)
    p.minimize((z[0] - 3) ** 2 + (z[1] - 2) ** 2)
    return p


@pytest.mark.parametrize("var_scale", [1.0, 7.0])
@pytest.mark.parametrize("con_scale", [1.0, 7.0])
def test_scale_invariance(var_scale, con_scale):
    res = projection_problem(var_scale, con_scale).solve()
    np.testing.assert_allclose(res.values["z"], [1.0, 0.0], atol=1e-7)
    assert res.multipliers["half_plane"] == pytest.approx(-4.0, rel=1e-6)
    assert abs(res.multipliers["disc"]) < 1e-6
    reference = projection_problem(1.0, 1.0).solve()
    np.testing.assert_allclose(res.values["z"], reference.values["z"], atol=1e-7)
    assert res.multipliers["half_plane"] == pytest.approx(reference.multipliers["half_plane"], rel=1e-6)


def test_scaled_variable_is_scale_times_decision_variable():
    p = Problem("scaled")
    x = p.variable("x", init=3.5, scale=7.0, lower=0.0, upper=14.0)
    # Ipopt's decision variable is x/7; the expression handed back is 7 * x_s.
    symbol = ca.symvar(x)[0]
    assert float(ca.substitute(x, symbol, ca.MX(0.5))) == pytest.approx(3.5)
    lower = np.asarray(ca.evalf(p.opti.lbg)).ravel()
    upper = np.asarray(ca.evalf(p.opti.ubg)).ravel()
    np.testing.assert_allclose([lower[0], upper[0]], [0.0, 2.0])


# --------------------------------------------------------------------------- parameters and re-solve

def parametric_problem() -> tuple[Problem, ca.MX, ca.MX]:
    """min x^2 + y^2 s.t. x + y >= k: x = y = k/2, multiplier d f*/d k = k."""
    p = Problem("parametric")
    k = p.parameter("k_N", value=1.0, unit="N")
    x = p.variable("x", init=0.0)
    y = p.variable("y", init=0.0)
    p.subject_to("sum_min", x + y - k, lower=0.0)
    p.minimize(x ** 2 + y ** 2)
    return p, k, x


def test_set_parameter_resolves_without_rebuilding():
    p, _, _ = parametric_problem()
    opti = p.opti
    first = p.solve()
    assert first.values["x"] == pytest.approx(0.5, abs=1e-7)
    assert p.solver_builds == 1
    p.set_parameter("k_N", 3.0)
    second = p.solve()
    assert p.opti is opti
    assert p.solver_builds == 1
    assert second.parameters["k_N"] == 3.0 and first.parameters["k_N"] == 1.0
    assert second.values["x"] == pytest.approx(1.5, abs=1e-7)
    assert second.values["y"] == pytest.approx(1.5, abs=1e-7)
    assert second.multipliers["sum_min"] == pytest.approx(3.0, rel=1e-6)
    # The first result is detached from later parameter changes.
    assert first.values["x"] == pytest.approx(0.5, abs=1e-7)


def test_warm_start_and_option_change():
    p, _, _ = parametric_problem()
    cold = p.solve()
    warm = p.solve(warm_start=True)
    assert warm.values["x"] == pytest.approx(cold.values["x"], abs=1e-7)
    assert warm.variables["init"].to_numpy() == pytest.approx([0.5, 0.5], abs=1e-7)
    assert p.solver_builds == 1
    p.solve(tol=1e-9)  # different Ipopt options: a new solver instance
    assert p.solver_builds == 2


def test_setting_the_same_objective_again_keeps_the_solver_and_another_one_rebuilds_it():
    p = Problem("objectives")
    x = p.variable("x", init=0.0)
    y = p.variable("y", init=0.0)
    p.subject_to("sum_min", x + y, lower=1.0)
    distance = x ** 2 + y ** 2
    p.minimize(distance)
    p.solve()
    p.minimize(distance)                  # the objective it has (same expression, sense and scale): no rebuild
    again = p.solve()
    assert p.solver_builds == 1 and again.values["x"] == pytest.approx(0.5, abs=1e-7)
    p.minimize(x ** 2 + y ** 2)           # a new expression (equal in value): a new objective, one rebuild
    p.solve()
    assert p.solver_builds == 2
    p.minimize(x ** 2 + y ** 2, scale=2.0)
    p.minimize(distance, scale=2.0)       # the same expression at another scale is another objective
    p.solve()
    assert p.solver_builds == 3
    p.maximize(-distance, scale=2.0)      # another expression and sense
    res = p.solve()
    assert p.solver_builds == 4 and res.values["y"] == pytest.approx(0.5, abs=1e-7)


def constrained_rosenbrock(radius: float) -> Problem:
    """min (1 - x)^2 + 100 (y - x^2)^2 s.t. x^2 + y^2 <= r: the disc cuts the valley below (1, 1) for r < 2."""
    p = Problem("rosenbrock_disc")
    r = p.parameter("r", value=radius)
    x = p.variable("x", init=0.0)
    y = p.variable("y", init=0.0)
    p.subject_to("disc", x ** 2 + y ** 2 - r, upper=0.0)
    p.minimize((1 - x) ** 2 + 100 * (y - x ** 2) ** 2)
    return p


def test_warm_start_point_carries_a_solution_to_another_problem_built_the_same_way():
    import pickle

    from scipy.optimize import minimize

    from gearopt.nlp import WarmStartPoint

    first = constrained_rosenbrock(1.5)
    assert first.warm_start_point() is None
    first.solve()
    point = pickle.loads(pickle.dumps(first.warm_start_point()))       # e.g. to a worker process
    assert isinstance(point, WarmStartPoint) and point.multipliers.size == 1 and point.multipliers[0] != 0.0
    from gearopt.nlp import WARM_START_IPOPT as warm_options
    cold = constrained_rosenbrock(1.6).solve()
    other = constrained_rosenbrock(1.6)
    warm = other.solve(warm_start=point, **warm_options)
    # SciPy's SLSQP on the same problem (an independent solver) gives the optimum both must reach
    ref = minimize(lambda v: (1 - v[0]) ** 2 + 100 * (v[1] - v[0] ** 2) ** 2, [0.0, 0.0], method="SLSQP",
                   constraints=[{"type": "ineq", "fun": lambda v: 1.6 - v[0] ** 2 - v[1] ** 2}],
                   options={"ftol": 1e-12, "maxiter": 500})
    for res in (cold, warm):
        assert [res.values["x"], res.values["y"]] == pytest.approx(list(ref.x), abs=1e-5)
    assert warm.iterations < cold.iterations
    # a point of a problem with another number of constraints and another size of y: its multipliers and y are
    # not used (zeros, y's declared start), no error
    foreign = WarmStartPoint({**point.x_scaled, "y": np.zeros(3)}, np.array([1.0, 2.0]))   # y: another size
    again = constrained_rosenbrock(1.6).solve(warm_start=foreign)
    assert again.values["x"] == pytest.approx(ref.x[0], abs=1e-5)
    # bad points are refused by name
    with pytest.raises(GearoptInputError, match="x_scaled"):
        WarmStartPoint([1.0, 2.0], np.zeros(1))
    with pytest.raises(GearoptInputError, match="multipliers"):
        WarmStartPoint({"x": 1.0}, np.array([np.nan]))


def test_multipliers_by_name_start_a_problem_with_more_constraints_and_other_scales():
    """``WarmStartPoint.from_result``: a solve's multipliers by constraint name start another problem that shares
    the constraint (here with another scale, an extra limit and another objective scale): each shared row gets the
    solved multiplier in its own scaling, the new rows none, and the warm solve from the solved design reaches
    SciPy SLSQP's optimum of the new problem in fewer iterations than the same start without multipliers."""
    from scipy.optimize import minimize

    from gearopt.nlp import WARM_START_IPOPT, WarmStartPoint

    def problem(extra: bool):
        p = Problem("rosenbrock_disc_more")
        x = p.variable("x", init=0.0)
        y = p.variable("y", init=0.0)
        p.subject_to("disc", x ** 2 + y ** 2 - 1.6, upper=0.0, scale=10.0 if extra else 1.0)
        if extra:
            p.subject_to("half_plane", x + 2.0 * y, upper=3.0)          # inactive at the optimum
        p.minimize((1 - x) ** 2 + 100 * (y - x ** 2) ** 2, scale=4.0 if extra else 1.0)
        return p

    solved = problem(False).solve()
    point = WarmStartPoint.from_result(solved)
    assert point.x_scaled == {} and set(point.multipliers_by_name) == {"disc", "x", "y"}   # x, y: their bounds
    bigger = problem(True)
    lam = bigger._multipliers_by_name(point.multipliers_by_name)
    disc, half = bigger._constraints["disc"], bigger._constraints["half_plane"]
    # the start multiplier, read back as d objective / d bound, is the solved one; the new limit starts at 0
    assert lam[disc.rows[0]] * (-1.0 * 4.0) / 10.0 == pytest.approx(solved.multipliers["disc"], rel=1e-12)
    assert lam[half.rows[0]] == 0.0
    ref = minimize(lambda v: (1 - v[0]) ** 2 + 100 * (v[1] - v[0] ** 2) ** 2, [0.0, 0.0], method="SLSQP",
                   constraints=[{"type": "ineq", "fun": lambda v: 1.6 - v[0] ** 2 - v[1] ** 2},
                                {"type": "ineq", "fun": lambda v: 3.0 - v[0] - 2.0 * v[1]}],
                   options={"ftol": 1e-12, "maxiter": 500})
    runs = {}
    for name, warm in (("cold", False), ("warm", point)):
        p = problem(True)
        p.set_initial("x", solved.values["x"])
        p.set_initial("y", solved.values["y"])
        runs[name] = p.solve(warm_start=warm, **WARM_START_IPOPT)
        assert [runs[name].values["x"], runs[name].values["y"]] == pytest.approx(list(ref.x), abs=1e-5)
    assert runs["warm"].iterations < runs["cold"].iterations
    # a variable at its bound: its bound's multiplier is carried by the variable's name, rescaled likewise
    def bounded(scale: float):
        p = Problem("bounded_valley")
        x = p.variable("x", init=0.0, upper=0.8, scale=scale)
        y = p.variable("y", init=0.0)
        p.minimize((1 - x) ** 2 + 100 * (y - x ** 2) ** 2)
        return p
    at_bound = bounded(1.0).solve()
    other = bounded(4.0)
    start = other._multipliers_by_name(WarmStartPoint.from_result(at_bound).multipliers_by_name)
    x_entry = other._variables["x"]
    assert start[x_entry.bound_rows[0]] * -1.0 / 4.0 == pytest.approx(
        float(at_bound.variables.set_index("name").loc["x", "multiplier"]), rel=1e-12)
    assert float(at_bound.variables.set_index("name").loc["x", "multiplier"]) != 0.0
    with pytest.raises(GearoptInputError, match="multipliers_by_name"):
        WarmStartPoint({}, np.zeros(0), ["disc"])
    with pytest.raises(GearoptInputError, match=r"multipliers_by_name\['disc'\].*real numbers"):
        WarmStartPoint({}, np.zeros(0), {"disc": "abc"})
    with pytest.raises(GearoptInputError, match="disc"):
        WarmStartPoint({}, np.zeros(0), {"disc": [np.inf]})
    with pytest.raises(GearoptInputError, match="ProblemResult"):
        WarmStartPoint.from_result({"disc": 1.0})


def test_value_of_any_expression_at_solution():
    p, k, x = parametric_problem()
    res = p.solve()
    # x = 1/2, k = 1: 4x + k = 3.
    assert res.value(x * 4 + k) == pytest.approx(3.0, abs=1e-6)
    np.testing.assert_allclose(res.value(ca.vertcat(x, k)), [0.5, 1.0], atol=1e-7)
    assert res.value("k_N") == 1.0
    with pytest.raises(KeyError):
        res.value("no_such_name")


# --------------------------------------------------------------------------- typed failures

def test_infeasible_bounds_raise_with_both_constraints_named():
    p = Problem("infeasible")
    x = p.variable("x", init=0.0)
    p.subject_to("x_min", x, lower=2.0)
    p.subject_to("x_max", x, upper=1.0)
    p.minimize(x ** 2)
    with pytest.raises(InfeasibleProblemError) as info:
        p.solve()
    err = info.value
    names = {v.name for v in err.violated}
    assert names == {"x_min", "x_max"}
    assert "x_min" in str(err) and THIS_FILE in str(err)
    assert err.hint and err.status
    assert isinstance(err.result, ProblemResult) and not err.result.success


def test_nonlinear_infeasible_problem():
    # The disc x^2 + y^2 <= 1 never reaches the line x + y >= 3 (closest approach sqrt(2) < 3).
    p = Problem("infeasible_nl")
    x = p.variable("x", init=0.1)
    y = p.variable("y", init=0.2)
    p.subject_to("disc", x ** 2 + y ** 2, upper=1.0)
    p.subject_to("line", x + y, lower=3.0)
    p.minimize(x ** 2)
    with pytest.raises(InfeasibleProblemError) as info:
        p.solve()
    err = info.value
    assert err.status == "Infeasible_Problem_Detected"
    assert "cannot all be met" in err.hint
    assert "line" in [v.name for v in err.violated]
    assert "line" in str(err)


def test_iteration_limit():
    with pytest.raises(IterationLimitError) as info:
        rosenbrock().solve(max_iter=2)
    err = info.value
    assert err.status == "Maximum_Iterations_Exceeded"
    assert err.result.iterations == 2 and not err.result.success
    assert isinstance(err, SolveError)


# --------------------------------------------------------------------------- pre-solve check and bad input

def test_nan_at_initial_guess_names_the_constraint():
    p = Problem("nan")
    x = p.variable("x", init=-1.0)
    p.subject_to("root_min", ca.sqrt(x), lower=0.5)
    p.minimize(x ** 2)
    with pytest.raises(BadInitialGuessError, match="root_min") as info:
        p.check_initial_guess()
    assert THIS_FILE in str(info.value)
    with pytest.raises(BadInitialGuessError, match="root_min"):
        p.solve()
    assert p.solver_builds == 0  # Ipopt never ran


def test_nan_objective_at_initial_guess():
    p = Problem("nan_objective")
    y = p.variable("y", init=-1.0)
    p.minimize(ca.log(y) + y ** 2)
    with pytest.raises(BadInitialGuessError, match="objective: value is nan"):
        p.solve()


def test_initial_guess_on_domain_edge_is_judged_where_ipopt_starts():
    # sqrt has an infinite derivative at 0, but Ipopt pushes x = 0 inside the bound x >= 0 before evaluating.
    # min x^2 s.t. sqrt(x) >= 1/2 -> x* = 1/4.
    p = Problem("edge")
    x = p.variable("x", init=0.0, lower=0.0)
    p.subject_to("root_min", ca.sqrt(x), lower=0.5)
    p.minimize(x ** 2)
    assert p.check_initial_guess().ok
    assert p.solve().values["x"] == pytest.approx(0.25, abs=1e-7)


def test_init_outside_bounds_is_flagged_not_fatal():
    p = Problem("outside")
    x = p.variable("x", init=5.0, lower=0.0, upper=1.0)
    p.minimize((x - 0.25) ** 2)
    report = p.check_initial_guess()
    assert [f.name for f in report.outside_bounds] == ["x"]
    with pytest.warns(InitialGuessWarning, match="x"):
        res = p.solve()
    assert res.values["x"] == pytest.approx(0.25, abs=1e-7)


def test_inverted_bounds_name_the_variable():
    p = Problem("bad")
    with pytest.raises(GearoptInputError, match="profile_shift_1.*upper=-0.5.*lower=1"):
        p.variable("profile_shift_1", init=0.3, lower=1.0, upper=-0.5)


@pytest.mark.parametrize("kwargs, pattern", [
    ({"scale": 0.0}, "scale=0.*must be > 0"),
    ({"scale": -2.0}, "scale=-2"),
    ({"init": float("nan")}, "init=nan"),
    ({"n": 0}, "n=0"),
    ({"lower": [0.0, 1.0]}, "2 entries"),
])
def test_bad_variable_input(kwargs, pattern):
    p = Problem("bad")
    args = {"init": 0.0, **kwargs}
    with pytest.raises(GearoptInputError, match=pattern):
        p.variable("x1", **args)


def test_bad_names_and_constraints():
    p = Problem("bad")
    x = p.variable("x", init=0.0)
    with pytest.raises(GearoptInputError, match="already used by the variable"):
        p.variable("x", init=0.0)
    with pytest.raises(GearoptInputError, match="already used by the variable"):
        p.subject_to("x", x, lower=0.0)
    with pytest.raises(GearoptInputError, match="at least one bound"):
        p.subject_to("c", x)
    with pytest.raises(GearoptInputError, match="inverted"):
        p.subject_to("c", x, lower=2.0, upper=1.0)
    with pytest.raises(GearoptInputError, match="constant"):
        p.subject_to("c", 3.0, lower=0.0)
    with pytest.raises(GearoptInputError, match="c"):
        p.subject_to("c", p.parameter("k", 1.0) * 2, lower=0.0)
    with pytest.raises(GearoptInputError, match="scalar"):
        p.minimize(ca.vertcat(x, x))
    with pytest.raises(GearoptInputError, match="not declared"):
        p.set_parameter("nope", 1.0)


# --------------------------------------------------------------------------- vector constraints and report

def test_vector_constraint_rows_and_report():
    # min sum (z_i - 2)^2 s.t. z_i <= u_i with u = (1, 3): z = (1, 2); multipliers d f*/d u_i = (2(1-2), 0) = (-2, 0).
    p = Problem("vector")
    z = p.variable("z", init=0.0, n=2, unit="mm")
    p.subject_to("z_max", z, upper=[1.0, 3.0], unit="mm")
    p.subject_to("z_sum_min", ca.sum1(z), lower=0.0, unit="mm")
    p.minimize(ca.sumsqr(z - 2))
    res = p.solve()
    np.testing.assert_allclose(res.values["z"], [1.0, 2.0], atol=1e-7)
    np.testing.assert_allclose(res.multipliers["z_max"], [-2.0, 0.0], atol=1e-6)
    assert list(res.constraints["name"]) == ["z_max[0]", "z_max[1]", "z_sum_min"]
    assert list(res.constraints["active"]) == [True, False, False]
    assert res.constraints.loc[1, "margin"] == pytest.approx(1.0, abs=1e-7)
    text = res.report()
    for token in ("Problem 'vector'", "Solve_Succeeded", "z_max[0]", "z_sum_min", "yes", THIS_FILE):
        assert token in text
    assert res.violations() == []


# --- constraints that do not depend on the variables (added with the shift-distribution NLP) ------------------------

def test_constant_constraint_is_recorded_not_sent_to_ipopt():
    # an affine constraint with a zero coefficient (x*0.5*2 - x) used to make Ipopt report Invalid_Problem_Definition
    # through CasADi's detect_simple_bounds when a second variable exists
    from gearopt.nlp import Problem

    p = Problem("constant")
    x = p.variable("x", init=0.5, lower=-1.0, upper=1.0)
    t = p.variable("t", init=0.0, lower=-5.0, upper=5.0)
    zero = ca.MX(0.75) + ca.mtimes(ca.DM([[0.0]]), x)
    p.subject_to("fixed_margin", zero, lower=0.0)
    p.subject_to("epigraph", ca.sin(x) - t, lower=0.0)
    p.maximize(t)
    res = p.solve()
    assert "fixed_margin" in p.constant_constraints
    assert res.values["x"] == pytest.approx(1.0, abs=1e-6)


def test_violated_constant_constraint_raises_by_name():
    from gearopt.nlp import Problem
    from gearopt.errors import InfeasibleProblemError

    p = Problem("constant_violated")
    x = p.variable("x", init=0.5, lower=-1.0, upper=1.0)
    with pytest.raises(InfeasibleProblemError, match="fixed_margin") as e:
        p.subject_to("fixed_margin", ca.MX(-0.2) + ca.mtimes(ca.DM([[0.0]]), x), lower=0.0)
    assert e.value.violated[0].name == "fixed_margin"


def _polygon_problem(screen):
    """Maximise x + 2 y inside the regular 400-gon circumscribing the unit circle (one half-plane per side):
    the optimum is the polygon's vertex nearest the direction (1, 2)/sqrt(5), between sqrt(5) and sqrt(5)/cos(pi/400)
    (analytic bounds of an inscribed circle and the circumscribed one)."""
    p = Problem("polygon")
    x = p.variable("x", init=0.0, lower=-3.0, upper=3.0)
    y = p.variable("y", init=0.0, lower=-3.0, upper=3.0)
    t = np.linspace(0.0, 2.0 * np.pi, 400, endpoint=False)
    p.subject_to("side", ca.cos(ca.DM(t)) * x + ca.sin(ca.DM(t)) * y, upper=1.0, screen=screen)
    p.maximize(x + 2.0 * y)
    return p


def test_screened_constraint_rows_by_exchange_reach_the_full_optimum():
    """Rows by exchange (``screen``): the start (0, 0) is 1 from every side, so no side is handed to Ipopt at
    first; the unconstrained optimum (3, 3) breaks sides, they join with their neighbours within the screen and the
    warm re-solve ends at the polygon's vertex -- the optimum of the problem with every row -- with far fewer rows."""
    full = _polygon_problem(None)
    reference = full.solve()
    screened = _polygon_problem(0.05)
    result = screened.solve()
    assert result.exchanges >= 1
    assert np.sqrt(5.0) - 1e-7 <= result.objective <= np.sqrt(5.0) / np.cos(np.pi / 400) + 1e-7
    assert result.objective == pytest.approx(reference.objective, rel=1e-7)
    side = result.constraints[result.constraints["base"] == "side"]
    assert len(side) == 400 and float(side["margin"].min()) >= -1e-7          # every row met, every row reported
    passed = screened.opti.ng - 2                                             # minus the variables' bound rows
    assert passed <= (full.opti.ng - 2) // 2
    assert int((side["multiplier"] != 0.0).sum()) <= passed                   # held-back rows: multiplier 0
    assert f"{result.exchanges} re-solve" in result.report().splitlines()[0]


def test_held_back_blocks_of_a_stacked_screened_constraint_stay_out_of_ipopts_functions():
    """A screened constraint stacked from independent blocks (one model per element, as the LTCAs of relief
    variants are): Ipopt's constraint functions depend on the blocks of the passed rows only. Each side of the
    polygon of :func:`_polygon_problem` is its own block with its own offset parameter (at 0 the side is that
    polygon's); the optimum is the full problem's, and the parameters of sides never passed are not in Opti's g --
    a plain slice of the stack would depend on (and evaluate) every block."""
    p = Problem("polygon_blocks")
    x = p.variable("x", init=0.0, lower=-3.0, upper=3.0)
    y = p.variable("y", init=0.0, lower=-3.0, upper=3.0)
    t = np.linspace(0.0, 2.0 * np.pi, 400, endpoint=False)
    offsets = [p.parameter(f"offset_{i}", 0.0) for i in range(t.size)]
    p.subject_to("side", ca.vertcat(*[np.cos(a) * x + np.sin(a) * y - r for a, r in zip(t, offsets)]), upper=1.0,
                 screen=0.05)
    p.maximize(x + 2.0 * y)
    result = p.solve()
    assert result.objective == pytest.approx(_polygon_problem(None).solve().objective, rel=1e-7)
    in_graph = {str(v) for v in ca.symvar(p.opti.g)}           # symbols of the graph Ipopt's functions evaluate
    passed = [i for i, r in enumerate(offsets) if str(r) in in_graph]
    assert 0 < len(passed) <= t.size // 2
    assert p.opti.ng - 2 == len(passed)                       # one row per passed side (minus the bound rows)


def test_screen_must_be_a_nonnegative_margin():
    p = Problem("bad_screen")
    x = p.variable("x", init=0.0, lower=-1.0, upper=1.0)
    with pytest.raises(GearoptInputError, match=r"screen=-0\.5.*below its limit 0"):
        p.subject_to("c", ca.vertcat(x, 2 * x), upper=1.0, screen=-0.5)


def test_depends_on_variables_tells_variables_from_parameters_and_numbers():
    """An expression of a variable depends on the variables; one of a parameter alone, a number or a DM does not
    (the check a scene makes before imposing a limit, without reading ``opti.x``)."""
    p = Problem("dependence")
    k = p.parameter("k", 2.0)
    assert not p.depends_on_variables(k * 3.0)                    # no variables declared yet
    x = p.variable("x", init=1.0)
    v = p.variable("v", init=[1.0, 2.0], n=2)                     # declared, used by nothing yet
    assert p.depends_on_variables(x * k + 1.0)
    assert p.depends_on_variables(ca.vertcat(k, ca.sin(x)))
    assert p.depends_on_variables(k * v[1])                       # the second variable, a vector's element
    assert not p.depends_on_variables(k ** 2)
    assert not p.depends_on_variables(3.0)
    assert not p.depends_on_variables(ca.DM([1.0, 2.0]))
    assert not p.depends_on_variables(ca.MX.sym("stranger") * k)  # a symbol not declared through the problem


def test_violations_are_ranked_by_scaled_violation_with_ties_in_table_order():
    """violations_from_tables against a plain row-by-row reference (max(lower - value, value - upper, 0) > tol *
    scale, ranked by violation / scale, ties in table order, bounds rows suffixed): the worst first, NaN and
    infinite bounds never counted, ``n`` the first n of the full ranking."""
    import pandas as pd

    from gearopt.nlp.result import violations_from_tables

    rng = np.random.default_rng(3)
    size = 40
    value = rng.normal(0.0, 2.0, size)
    value[[3, 7]] = [np.nan, 5.0]
    lower = np.where(rng.random(size) < 0.3, -np.inf, -1.0)
    upper = np.where(rng.random(size) < 0.3, np.inf, 1.0)
    scale = rng.choice([1.0, 10.0, 0.1], size)
    scale[[10, 11]], value[[10, 11]], lower[[10, 11]], upper[[10, 11]] = 1.0, 3.0, -1.0, 1.0   # a tie
    table = pd.DataFrame({"name": [f"c{i}" for i in range(size)], "value": value, "lower": lower, "upper": upper,
                          "scale": scale, "source": [f"src{i}" for i in range(size)]})
    bounds = table.iloc[:5].assign(name=[f"x{i}" for i in range(5)], value=[2.0, 0.0, -3.0, 0.5, 9.0])
    tol = 1e-6
    reference = []
    for t, (tab, suffix) in enumerate(((table, ""), (bounds, " (bounds)"))):
        for i, r in enumerate(tab.itertuples(index=False)):
            violation = max(r.lower - r.value, r.value - r.upper, 0.0) if np.isfinite(r.value) else 0.0
            if violation > tol * r.scale:
                reference.append((-violation / r.scale, t, i, f"{r.name}{suffix}", violation))
    reference.sort(key=lambda item: item[:3])
    found = violations_from_tables(table, bounds, tol)
    assert [(v.name, v.violation) for v in found] == [(name, pytest.approx(v)) for *_, name, v in reference]
    names = [v.name for v in found]
    assert names.index("c10") == names.index("c11") - 1                     # the tie in table order
    assert [v.name for v in violations_from_tables(table, bounds, tol, 3)] == [r[3] for r in reference[:3]]
    assert violations_from_tables(table.iloc[:0], None, tol) == []
