"""Tests of gearopt.nlp.elastic: the least weighted relaxation of an infeasible problem, by name and in units.

References are analytic (derived next to each test) or a brute-force scan computed here; none comes from the code
under test.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pandas as pd
import pytest

from gearopt.nlp import Problem
from gearopt.nlp.elastic import ELASTIC_COLUMNS, ElasticResult, solve_elastic
from gearopt.errors import GearoptInputError, InfeasibleProblemError, SolveError

TOL = 1e-5   # phase 2 keeps the relaxation within 1e-6 (scaled) of phase 1; Ipopt tol 1e-8


def conflict(scale_min: float = 1.0, scale_max: float = 1.0, objective=None) -> Problem:
    """x >= 2 mm and x <= 1 mm: infeasible by exactly 1 mm whichever bound moves."""
    p = Problem("conflict")
    x = p.variable("x_mm", init=0.0, scale=1.0, unit="mm")
    p.subject_to("x_min_mm", x, lower=2.0, scale=scale_min, unit="mm")
    p.subject_to("x_max_mm", x, upper=1.0, scale=scale_max, unit="mm")
    p.minimize(objective(x) if objective else x ** 2)
    return p


# --------------------------------------------------------------------------- analytic toy problems

@pytest.mark.parametrize("weights, scales, relaxed, x_star", [
    # cost of relaxing by r: w r / scale. w_min/s_min = 1 < w_max/s_max = 3: move x >= 2 down to 1 -> x = 1
    ({"x_min_mm": 1.0, "x_max_mm": 3.0}, (1.0, 1.0), "x_min_mm", 1.0),
    # 3 > 1: move x <= 1 up to 2 -> x = 2
    ({"x_min_mm": 3.0, "x_max_mm": 1.0}, (1.0, 1.0), "x_max_mm", 2.0),
    # equal weights, scales 0.1 vs 1: relaxing x >= 2 costs 10 per mm, x <= 1 costs 1 per mm -> x = 2
    (None, (0.1, 1.0), "x_max_mm", 2.0),
    # weights and scales together: 5/10 = 0.5 < 1/1 -> relax x >= 2 -> x = 1
    ({"x_min_mm": 5.0}, (10.0, 1.0), "x_min_mm", 1.0),
])
def test_two_conflicting_bounds_relax_the_cheaper_one_by_one_mm(weights, scales, relaxed, x_star):
    p = conflict(*scales)
    res = p.solve_elastic(weights=weights)
    assert isinstance(res, ElasticResult)
    assert not res.feasible
    assert res.values["x_mm"] == pytest.approx(x_star, abs=TOL)
    # the two relaxations total exactly the 1 mm gap, all of it on the cheaper constraint
    assert res.table["relaxation"].sum() == pytest.approx(1.0, abs=TOL)
    assert res.relaxation(relaxed) == pytest.approx(1.0, abs=TOL)
    top = res.table.iloc[0]
    assert top["base"] == relaxed and top["unit"] == "mm"
    assert list(res.relaxed["base"]) == [relaxed]
    # total weighted scaled relaxation = w / s of the relaxed constraint times 1 mm
    w = (weights or {}).get(relaxed, 1.0)
    s = scales[0] if relaxed == "x_min_mm" else scales[1]
    assert res.total_relaxation == pytest.approx(w / s, rel=1e-6)


@pytest.mark.parametrize("sign, x_star", [(1.0, 2.0), (-1.0, 1.0)])
def test_lexicographic_phase_picks_the_objective_among_least_relaxations(sign, x_star):
    """Equal costs: every x in [1, 2] relaxes a total of 1 mm. Phase 2 minimises (x - 5 sign)^2 over that segment:
    x = 2 for a target at +5, x = 1 for -5. Phase 1 alone may stop anywhere in [1, 2]."""
    p = conflict(objective=lambda x: (x - 5.0 * sign) ** 2)
    res = p.solve_elastic()
    assert res.values["x_mm"] == pytest.approx(x_star, abs=TOL)
    assert res.objective == pytest.approx((x_star - 5.0 * sign) ** 2, abs=1e-4)
    assert res.table["relaxation"].sum() == pytest.approx(1.0, abs=TOL)
    phase1 = p.solve_elastic(mode="relaxation")
    assert 1.0 - TOL <= phase1.values["x_mm"] <= 2.0 + TOL
    assert phase1.table["relaxation"].sum() == pytest.approx(1.0, abs=TOL)


@pytest.mark.parametrize("penalty, x_star", [(2.0, 4.0), (100.0, 1.0)])
def test_penalty_mode_is_the_exact_l1_penalty(penalty, x_star):
    """min (x-5)^2 s.t. x <= 1: the multiplier of x <= 1 is 2(5-1) = 8. The l1 penalty (x-5)^2 + g max(x-1, 0)
    is exact for g > 8 (x = 1); for g = 2 its minimum is where 2(x-5) + 2 = 0, x = 4, a violation of 3."""
    p = Problem("penalty")
    x = p.variable("x", init=0.0)
    p.subject_to("x_max", x, upper=1.0)
    p.minimize((x - 5.0) ** 2)
    res = p.solve_elastic(mode="penalty", penalty=penalty)
    assert res.values["x"] == pytest.approx(x_star, abs=1e-6)
    assert res.relaxation("x_max") == pytest.approx(x_star - 1.0, abs=1e-6)
    assert res.feasible is (x_star == 1.0)


@pytest.mark.parametrize("w1, w2, total", [(1.0, 3.0, 3.0), (3.0, 1.0, 1.0)])
def test_conflicting_equalities_relaxed_by_their_gap(w1, w2, total):
    """x + y = 1 and x + y = 3 conflict by 2. The cheaper equality (weight 1 against 3) moves by 2 to the other's
    value; phase 2 then minimises x^2 + y^2 on x + y = total: x = y = total / 2. The first equality's relaxation is
    on its upper side when x + y = 3 lies above it, the second's on its lower side."""
    p = Problem("equalities")
    x = p.variable("x", init=0.0)
    y = p.variable("y", init=0.0)
    p.subject_to("sum_a", x + y, lower=1.0, upper=1.0, unit="N")
    p.subject_to("sum_b", x + y, lower=3.0, upper=3.0, unit="N")
    p.minimize(x ** 2 + y ** 2)
    res = p.solve_elastic(weights={"sum_a": w1, "sum_b": w2})
    assert res.values["x"] == pytest.approx(total / 2, abs=TOL)
    assert res.values["y"] == pytest.approx(total / 2, abs=TOL)
    top = res.table.iloc[0]
    expected = ("sum_a", "upper") if total == 3.0 else ("sum_b", "lower")
    assert (top["name"], top["bound_side"], top["unit"]) == (*expected, "N")
    assert top["relaxation"] == pytest.approx(2.0, abs=TOL)
    assert res.table["relaxation"].iloc[1:].max() == pytest.approx(0.0, abs=TOL)


def test_vector_constraint_elements_are_named_and_in_units():
    """Stresses s_i = 100 x_i [MPa] with limits (50, 150, 250) MPa and x_i >= 1 (hard variable bounds):
    the least relaxation is s_0 by 50 MPa (x_0 = 1), the others hold."""
    p = Problem("stresses")
    x = p.variable("x", init=2.0, lower=1.0, upper=5.0, n=3)
    p.subject_to("stress_MPa", 100.0 * x, upper=np.array([50.0, 150.0, 250.0]), scale=10.0, unit="MPa")
    p.minimize(ca.sumsqr(x))
    res = p.solve_elastic()
    assert list(res.table.columns) == ELASTIC_COLUMNS
    top = res.table.iloc[0]
    assert (top["name"], top["element"], top["bound_side"], top["unit"]) == ("stress_MPa[0]", 0, "upper", "MPa")
    assert top["relaxation"] == pytest.approx(50.0, abs=1e-4)
    assert top["scaled_relaxation"] == pytest.approx(5.0, abs=1e-5)
    assert res.table["relaxation"].iloc[1:].max() == pytest.approx(0.0, abs=1e-6)
    # variable bounds are hard: x_0 stays at its lower bound 1 instead of moving to 0.5
    assert res.values["x"][0] == pytest.approx(1.0, abs=1e-6)
    assert "stress_MPa[0]: upper bound 50 MPa -> 100 MPa" in res.summary()


def test_feasible_problem_reports_zero_relaxation_and_the_same_optimum():
    """min x^2 + y^2 s.t. x + y >= 1, x <= 2: optimum (1/2, 1/2), f = 1/2 (KKT)."""
    def build():
        p = Problem("circle")
        x = p.variable("x", init=0.0, scale=2.0)
        y = p.variable("y", init=0.0)
        p.subject_to("sum_min", x + y, lower=1.0, scale=0.5)
        p.subject_to("x_max", x, upper=2.0)
        p.minimize(x ** 2 + y ** 2)
        return p
    direct = build().solve()
    elastic = build().solve_elastic()
    assert elastic.feasible
    assert elastic.relaxed.empty
    assert elastic.table["relaxation"].max() == pytest.approx(0.0, abs=1e-7)
    for name in ("x", "y"):
        assert elastic.values[name] == pytest.approx(direct.values[name], abs=1e-5)
        assert elastic.values[name] == pytest.approx(0.5, abs=1e-5)
    assert elastic.objective == pytest.approx(direct.objective, abs=1e-5)
    assert "can be met" in elastic.summary()


def test_original_problem_is_untouched_and_still_solves():
    p = conflict()
    p.solve_elastic()
    assert p.constraint_names == ("x_min_mm", "x_max_mm")
    assert p.variable_names == ("x_mm",)
    with pytest.raises(InfeasibleProblemError):
        p.solve()


def test_parameters_are_used_at_their_current_value():
    """x >= a, x <= 1 with a a parameter: the relaxation is a - 1 for every a > 1, 0 below."""
    p = Problem("param")
    a = p.parameter("a_mm", 3.0, unit="mm")
    x = p.variable("x", init=0.0)
    p.subject_to("x_min", x - a, lower=0.0, unit="mm")
    p.subject_to("x_max", x, upper=1.0, unit="mm", scale=0.5)
    p.minimize(x ** 2)
    assert p.solve_elastic().relaxation("x_min") == pytest.approx(2.0, abs=TOL)
    p.set_parameter("a_mm", 1.5)
    assert p.solve_elastic().relaxation("x_min") == pytest.approx(0.5, abs=TOL)
    p.set_parameter("a_mm", 0.5)
    assert p.solve_elastic().feasible


# --------------------------------------------------------------------------- errors carrying the relaxation

def test_solve_with_elastic_on_failure_attaches_relaxations_to_the_typed_error():
    p = conflict(scale_min=0.1)
    with pytest.raises(InfeasibleProblemError) as info:
        p.solve(elastic_on_failure=True)
    err = info.value
    assert isinstance(err.relaxations, pd.DataFrame)
    assert err.relaxations.iloc[0]["name"] == "x_max_mm"       # x >= 2 is 10x dearer to move (scale 0.1)
    assert err.relaxations.iloc[0]["relaxation"] == pytest.approx(1.0, abs=TOL)
    assert "x_max_mm: upper bound 1 mm -> 2 mm (relax by 1 mm)" in str(err)
    assert err.status and err.hint and err.violated            # the ordinary failure data are kept
    assert isinstance(err.elastic, ElasticResult)


def test_without_elastic_on_failure_the_error_is_unchanged():
    with pytest.raises(InfeasibleProblemError) as info:
        conflict().solve()
    assert not hasattr(info.value, "relaxations")
    assert "elastic mode" not in str(info.value)


def test_input_errors_name_the_parameter():
    p = conflict()
    with pytest.raises(GearoptInputError, match="mode='phase3'"):
        p.solve_elastic(mode="phase3")
    with pytest.raises(GearoptInputError, match="no_such"):
        p.solve_elastic(weights={"no_such": 1.0})
    with pytest.raises(GearoptInputError, match=r"weights\['x_min_mm'\]=-1.0"):
        p.solve_elastic(weights={"x_min_mm": -1.0})
    with pytest.raises(GearoptInputError, match="penalty=0"):
        p.solve_elastic(mode="penalty", penalty=0.0)
    q = Problem("free")
    x = q.variable("x", init=1.0)
    q.minimize(x ** 2)
    with pytest.raises(GearoptInputError, match="no constraints"):
        solve_elastic(q)


def test_variable_bounds_are_hard():
    """Variable bounds are hard: with x in [0, 1] and the constraint x >= 3, only the constraint moves (by 2, at
    x = 1), even though moving the variable bound would be as cheap."""
    p = Problem("box")
    x = p.variable("x", init=0.5, lower=0.0, upper=1.0)
    p.subject_to("x_min", x, lower=3.0)
    p.minimize(x)
    res = p.solve_elastic()
    assert res.values["x"] == pytest.approx(1.0, abs=1e-6)
    assert res.relaxation("x_min") == pytest.approx(2.0, abs=1e-6)


def test_elastic_failure_of_a_nan_model_is_typed():
    """A model that is NaN over the whole box cannot be relaxed: phase 1 raises a typed error naming it."""
    p = Problem("nan")
    x = p.variable("x", init=1.0, lower=0.5, upper=2.0)
    p.subject_to("bad_log", ca.log(x - 3.0), lower=0.0)
    p.minimize(x)
    with pytest.raises((SolveError, GearoptInputError)) as info:
        p.solve_elastic()
    assert "bad_log" in str(info.value)


def test_elastic_constraints_derivatives_match_finite_differences():
    """The elastic NLP (original constraints through one CasADi Function, scaling, relaxation selection) feeds
    Ipopt: its constraint Jacobian (ca.jacobian on the SX expansion) against central differences."""
    from gearopt.nlp.elastic import _mirror, _weights

    p = Problem("nonlinear")
    a = p.parameter("a", 1.5)
    x = p.variable("x", init=0.3, lower=-2.0, upper=2.0, scale=0.5)
    y = p.variable("y", init=np.array([0.2, -0.4]), n=2, scale=2.0)
    p.subject_to("ring", ca.vertcat(x ** 2 + y[0] ** 2, ca.sin(x * y[1])), lower=np.array([1.0, -0.5]),
                 upper=np.array([4.0, 0.5]), scale=np.array([2.0, 0.1]), unit="m^2")
    p.subject_to("exp_min", ca.exp(a * x) - y[1], lower=0.2, scale=3.0)
    p.minimize((x - 1) ** 2 + ca.sumsqr(y))
    constraints = list(p._constraints.values())
    ep, total, _ = _mirror(p, constraints, _weights(constraints, None), p._start(False), relax=True)
    ep.minimize(total)
    fn = ca.Function("elastic_g", [ep.opti.x], [ep.opti.g, ep.opti.f]).expand()
    xs = ca.SX.sym("x", ep.opti.nx)
    g, f = fn(xs)
    jac = ca.Function("elastic_jacobian", [xs], [ca.jacobian(ca.vertcat(g, f), xs)])
    val = ca.Function("val", [xs], [ca.vertcat(g, f)])
    point = np.random.default_rng(4).uniform(-0.8, 0.8, ep.opti.nx)
    exact = np.array(jac(point))
    h = 1e-6
    fd = np.column_stack([(np.array(val(point + h * e)) - np.array(val(point - h * e))).ravel() / (2 * h)
                          for e in np.eye(ep.opti.nx)])
    np.testing.assert_allclose(exact, fd, rtol=1e-6, atol=1e-7)
    assert ep.opti.nx == 3 + 2 + 2 + 1      # variables, ring lower/upper relaxations, exp_min lower relaxation
