"""Dual-typed numerics: numeric = symbolic, overflow-free smoothing, exact limits, derivatives vs finite differences."""

import math
import os
import subprocess
import sys

import casadi as ca
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearopt import numerics as nm
from gearopt.errors import GearoptInputError

SMOOTH = {
    "softplus": (lambda x, w: nm.softplus(x, w), lambda x: np.maximum(x, 0.0)),
    "smooth_abs": (lambda x, w: nm.smooth_abs(x, w), np.abs),
    "smooth_max": (lambda x, w: nm.smooth_max(x, 0.3 * x + 1.0, w), lambda x: np.maximum(x, 0.3 * x + 1.0)),
    "smooth_min": (lambda x, w: nm.smooth_min(x, 0.3 * x + 1.0, w), lambda x: np.minimum(x, 0.3 * x + 1.0)),
}


def _sx_eval(fun, xs, *extra):
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [fun(x, *extra)])
    return np.array(f.map(len(xs))(np.asarray(xs)[None, :])).ravel()


@pytest.mark.parametrize("name", SMOOTH)
def test_smooth_numeric_equals_symbolic(name):
    fun, _ = SMOOTH[name]
    xs = np.linspace(-50.0, 50.0, 201)
    np.testing.assert_allclose(fun(xs, 2.0), _sx_eval(fun, xs, 2.0), rtol=1e-14, atol=1e-12)


@pytest.mark.parametrize("name", SMOOTH)
def test_smooth_no_overflow_or_nan_up_to_1e6_widths(name):
    fun, exact = SMOOTH[name]
    w = 0.01
    xs = np.array([-1e6, -1e5, -1.0, 0.0, 1.0, 1e5, 1e6]) * w
    with np.errstate(over="raise", invalid="raise", divide="raise"):  # underflow of exp(-big) to 0 is exact enough
        num = fun(xs, w)
    sym = _sx_eval(fun, xs, w)
    assert np.all(np.isfinite(num)) and np.all(np.isfinite(sym))
    # far from the kink the smooth function is the exact one to rounding
    np.testing.assert_allclose(num[[0, -1]], exact(xs[[0, -1]]), rtol=1e-12)


@pytest.mark.parametrize("name", SMOOTH)
def test_smooth_converges_to_exact_with_documented_bound(name):
    fun, exact = SMOOTH[name]
    xs = np.linspace(-3.0, 3.0, 601)
    errors = []
    for w in (1.0, 0.1, 0.01, 0.001):
        err = np.max(np.abs(fun(xs, w) - exact(xs)))
        assert err <= w * math.log(2.0) * (1 + 1e-12)  # bound stated in the numerics docstring
        errors.append(err)
    assert errors[-1] < 1e-3 * errors[0] * 1.01


@pytest.mark.parametrize("name", SMOOTH)
def test_smooth_derivative_matches_finite_differences(name):
    fun, _ = SMOOTH[name]
    x = ca.SX.sym("x")
    df = ca.Function("df", [x], [ca.jacobian(fun(x, 0.5), x)])
    for x0 in (-2.0, -0.1, 0.0, 0.07, 1.5):
        h = 1e-6
        fd = (fun(x0 + h, 0.5) - fun(x0 - h, 0.5)) / (2 * h)
        assert float(df(x0)) == pytest.approx(fd, rel=1e-7, abs=1e-8)


def test_softplus_derivative_at_kink_is_one_half():
    x = ca.SX.sym("x")
    df = ca.Function("df", [x], [ca.jacobian(nm.softplus(x, 1e-3), x)])
    assert float(df(0.0)) == pytest.approx(0.5, abs=1e-15)


def test_width_must_be_positive():
    with pytest.raises(GearoptInputError, match="width"):
        nm.softplus(1.0, 0.0)


def test_where_is_dual_typed():
    assert nm.where(1.0 > 0.0, 2.0, 3.0) == 2.0
    x = ca.SX.sym("x")
    f = ca.Function("f", [x], [nm.where(x > 0, x, -2 * x)])
    assert float(f(-1.0)) == 2.0 and float(f(3.0)) == 3.0


def test_guarded_functions_never_nan():
    with np.errstate(all="raise"):
        assert nm.sqrt_safe(-1.0) == 0.0
        assert nm.acos_safe(1.0 + 1e-9) == 0.0
        assert nm.acos_safe(-1.5) == pytest.approx(math.pi)


# --- involute -----------------------------------------------------------------------------------------------------

def test_involute_known_value():
    # inv 20 deg = 0.014904383867336 (KHK Gear Technical Reference involute table: 0.014904)
    assert nm.involute(math.radians(20.0)) == pytest.approx(0.0149043838673, rel=1e-12)


def test_involute_series_branch_continuous_and_accurate():
    # at the switch (0.1 rad) the series and tan(a) - a agree to the cancellation error of the latter (~1e-13 rel.)
    a = 0.1 - 1e-15
    assert nm.involute(a) == pytest.approx(math.tan(0.1) - 0.1, rel=2e-13)
    # tan(a) - a for a = 1e-3, by the series to 6 terms (exact to double precision): a^3/3 + 2a^5/15 + ...
    a0 = 1e-3
    ref = a0**3 / 3 + 2 * a0**5 / 15 + 17 * a0**7 / 315
    assert nm.involute(a0) == pytest.approx(ref, rel=1e-15)


@settings(max_examples=200, deadline=None)
@given(st.floats(min_value=1e-5, max_value=math.radians(75.0)))
def test_inverse_involute_round_trip_numeric(alpha):
    assert abs(nm.inverse_involute(nm.involute(alpha)) - alpha) < 1e-12


def test_inverse_involute_vectorised_and_symbolic_equal():
    alphas = np.linspace(1e-4, math.radians(75.0), 5001)
    y = nm.involute(alphas)
    num = nm.inverse_involute(y)
    assert np.max(np.abs(num - alphas)) < 1e-12
    v = ca.SX.sym("v")
    expr = nm.inverse_involute(v)
    f = ca.Function("f", [v], [expr, ca.jacobian(expr, v)]).map(len(y))
    sym, dsym = (np.array(o).ravel() for o in f(y[None, :]))
    assert np.max(np.abs(sym - num)) < 1e-12
    # derivative of the inverse: d alpha / d inv = 1 / tan^2(alpha)
    np.testing.assert_allclose(dsym, 1.0 / np.tan(alphas) ** 2, rtol=1e-10)


def test_inverse_involute_start_documented_accuracy():
    alphas = np.linspace(1e-4, math.radians(75.0), 20001)
    start = nm._inverse_involute_start(nm.involute(alphas))
    assert np.max(np.abs(start / alphas - 1.0)) < 5e-5


def test_inverse_involute_rejects_out_of_range():
    with pytest.raises(GearoptInputError, match="inv_value"):
        nm.inverse_involute(-0.01)
    with pytest.raises(GearoptInputError, match="inv_value"):
        nm.inverse_involute(5.0)


def test_inverse_involute_mx_works():
    v = ca.MX.sym("v")
    f = ca.Function("f", [v], [nm.inverse_involute(v)])
    assert float(f(nm.involute(0.4))) == pytest.approx(0.4, abs=1e-14)


def test_sigmoid_derivative_at_zero_is_one_over_four_w():
    # the logistic function's slope at 0 is 1/(4w) (found missing when sigmoid was built from fabs)
    import casadi as ca
    x = ca.SX.sym("x")
    d = ca.Function("d", [x], [ca.jacobian(nm.sigmoid(x, 0.5), x)])
    assert float(d(0.0)) == pytest.approx(0.5)
    assert float(nm.sigmoid(800.0, 1.0)) == 1.0 and float(nm.sigmoid(-800.0, 1.0)) == 0.0


def test_column_softmin_lies_between_the_minimum_and_width_ln_rows_below_it():
    # -w log sum exp(-x/w): min - w ln(n) <= softmin <= min (log-sum-exp bounds); shifted, so no overflow at
    # gaps of 1e4 um with w = 0.05 um; CasADi and numpy agree, and so do their derivatives (a softmax weighting)
    x = np.array([[3.0, 1e4, -2.0], [3.01, 0.5, -2.0], [50.0, 1e4, 7.0]])
    w = 0.05
    s = nm.column_softmin(x, w)
    assert np.all(s <= x.min(axis=0)) and np.all(s >= x.min(axis=0) - w * np.log(3))
    assert s[2] == pytest.approx(-2.0 - w * np.log(2), rel=1e-12)        # two equal minima
    X = ca.SX.sym("x", 3, 3)
    f = ca.Function("f", [X], [nm.column_softmin(X, w)])
    np.testing.assert_allclose(np.asarray(f(x)).ravel(), s, rtol=1e-13)
    grad = np.asarray(ca.Function("g", [X], [ca.jacobian(nm.column_softmin(X, w)[0], X)])(x)).reshape(3, 3, order="F")
    weights = np.exp(-(x[:, 0] - x[:, 0].min()) / w)
    np.testing.assert_allclose(grad[:, 0], weights / weights.sum(), rtol=1e-10)


def test_evaluate_stacked_is_one_call_with_each_value_of_its_own():
    """Several expressions evaluated by one call: each value equals its own evaluation (matrices column-major,
    like ``ca.vec``), numbers pass through without a call, and a shared subexpression needs no second call."""
    x = ca.MX.sym("x", 2)
    shared = ca.sin(x[0]) * x[1]
    exprs = [shared, ca.horzcat(ca.vertcat(x[0], x[1]), ca.vertcat(2 * x[0], shared)), 3.5,
             np.array([[1.0, 2.0], [3.0, 4.0]]), ca.DM([[4.0], [5.0]])]
    point = [0.7, -1.3]
    calls = []

    def evaluate(expr):
        calls.append(expr)
        return np.asarray(ca.Function("f", [x], [expr])(point))

    out = nm.evaluate_stacked(evaluate, exprs)
    assert len(calls) == 1
    s = math.sin(0.7) * -1.3
    np.testing.assert_allclose(out[0], [s], rtol=1e-15)
    np.testing.assert_allclose(out[1], [0.7, -1.3, 1.4, s], rtol=1e-15)      # column by column
    np.testing.assert_array_equal(out[2], [3.5])
    np.testing.assert_array_equal(out[3], [1.0, 3.0, 2.0, 4.0])                # numbers column by column too
    np.testing.assert_array_equal(out[4], [4.0, 5.0])
    calls.clear()
    assert [a.tolist() for a in nm.evaluate_stacked(evaluate, [1.0, ca.DM(2.0)])] == [[1.0], [2.0]]
    assert calls == []                                       # numbers only: nothing to evaluate
    with pytest.raises(GearoptInputError, match="returned 1 values for 2 elements"):
        nm.evaluate_stacked(lambda expr: np.array([1.0]), [x])   # an evaluator that drops values is caught


def test_traced_call_is_the_model_as_one_kernel_built_once():
    """A dual-typed model called through ``traced_call`` on MX expressions: one call node of an SX kernel traced
    once (a second call with other expressions of the same shapes and numbers reuses it; other numbers trace a new
    one), values and derivatives equal to the model evaluated on numbers (the independent path) and built on MX
    directly, a result value that depends on no input a plain number, and the model's warnings raised at every
    call."""
    import dataclasses
    import warnings

    @dataclasses.dataclass(frozen=True)
    class Pair:
        a: object
        b: tuple
        c: float = 2.0

    def model(pair, scale, *, offset=0.0):
        if nm.is_numeric(pair.a) and nm.to_float(pair.a) > 10:
            raise GearoptInputError("a too large")
        warnings.warn("validity note", UserWarning)
        return {"value": scale * nm.sin(pair.a) * pair.b[0] + offset, "pair": (pair.b[1] ** 2, pair.c * 3.0),
                "label": "ok"}

    x, y = ca.MX.sym("x"), ca.MX.sym("y")
    before = nm.traced_kernel_stats()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = nm.traced_call(model, Pair(x, (y, 2 * x)), 1.5, offset=0.25)
        again = nm.traced_call(model, Pair(y, (x, x + y)), 1.5, offset=0.25)
    assert [str(w.message) for w in caught] == ["validity note", "validity note"]
    after = nm.traced_kernel_stats()
    assert (after["traced"] - before["traced"], after["reused"] - before["reused"]) == (1, 1)
    assert out["label"] == "ok" and out["pair"][1] == 6.0 and isinstance(out["pair"][1], float)
    f = ca.Function("f", [x, y], [out["value"], out["pair"][0], again["value"]])
    direct = model(Pair(x, (y, 2 * x)), 1.5, offset=0.25)
    nodes = [ca.Function("n", [x, y], [v]).n_nodes() for v in (out["value"], direct["value"])]
    assert nodes[0] < nodes[1]                             # a call node instead of the model's operations
    g = ca.Function("g", [x, y], [direct["value"], ca.jacobian(direct["value"], ca.vertcat(x, y))])
    jac = ca.Function("j", [x, y], [ca.jacobian(out["value"], ca.vertcat(x, y))])
    for px, py in ((0.3, -1.2), (2.0, 0.7)):
        numeric = model(Pair(px, (py, 2 * px)), 1.5, offset=0.25)
        v, p0, v2 = (float(a) for a in f(px, py))
        assert v == pytest.approx(numeric["value"], rel=1e-14)
        assert p0 == pytest.approx(4 * px * px, rel=1e-14)
        assert v2 == pytest.approx(1.5 * math.sin(py) * px + 0.25, rel=1e-14)
        np.testing.assert_allclose(np.array(jac(px, py)), np.array(g(px, py)[1]), rtol=1e-14)
    with pytest.warns(UserWarning, match="validity note"):
        nm.traced_call(model, Pair(x, (y, 2 * x)), 2.5, offset=0.25)    # another number: another kernel
        assert nm.traced_kernel_stats()["traced"] - after["traced"] == 1
        assert nm.traced_call(model, Pair(0.5, (2.0, 1.0)), 1.0)["value"] == pytest.approx(2 * math.sin(0.5))
        with pytest.raises(GearoptInputError, match="a too large"):       # checks on its numbers still run
            nm.traced_call(model, Pair(11.0, (y, 1.0)), 1.0)


def test_traced_call_never_reuses_a_kernel_for_another_model_or_input():
    """A kernel is keyed by the model object, the numbers and the expressions' sparsity: two closures of one factory,
    a diagonal and a dense input of one shape each get their own kernel; an argument it cannot key exactly (a plain
    object, an interpolant) or a model that makes MX of its own is called directly; a numeric result array is a
    fresh copy each call."""
    def factory(k):
        return lambda x: k * x
    x = ca.MX.sym("x")
    values = [float(ca.evalf(ca.substitute(nm.traced_call(factory(k), x), x, 1.0))) for k in (2.0, 3.0)]
    assert values == [2.0, 3.0]

    def total(m):
        return ca.sum1(ca.sum2(m))
    dense, diag = ca.MX.sym("d", 2, 2), ca.diag(ca.MX.sym("g", 2))
    for m in (diag, dense):
        out = nm.traced_call(total, m)
        assert float(ca.evalf(ca.substitute(out, ca.symvar(m)[0], ca.DM.ones(ca.symvar(m)[0].shape)))) == m.nnz()

    class Gain:                                            # a plain object: its repr does not show its state
        def __init__(self, k):
            self.k = k

        def __repr__(self):
            return "Gain"
    before = nm.traced_kernel_stats()["direct"]
    outs = [nm.traced_call(lambda g, y: g.k * y, Gain(k), x) for k in (2.0, 5.0)]
    assert [float(ca.evalf(ca.substitute(o, x, 1.0))) for o in outs] == [2.0, 5.0]
    assert nm.traced_kernel_stats()["direct"] - before == 2
    own = nm.traced_call(lambda y: {"v": 2 * y, "own": ca.MX.sym("z") + 1.0}, x)          # an MX of its own
    assert isinstance(own["own"], ca.MX) and nm.traced_kernel_stats()["direct"] - before == 3

    def with_array(y):
        return {"v": y, "table": np.array([1.0, 2.0])}
    first = nm.traced_call(with_array, x)
    first["table"][0] = 99.0
    assert nm.traced_call(with_array, x)["table"].tolist() == [1.0, 2.0]


_SOLVER_BLAS_THREADS = """
import ctypes, os, casadi as ca, gearopt
x = ca.MX.sym("x")
ca.nlpsol("s", "ipopt", {"x": x, "f": (x - 1) ** 2}, {"print_time": 0, "ipopt.print_level": 0, "ipopt.sb": "yes"})(x0=0)
here = os.path.dirname(ca.__file__)
blas = sorted({line.split()[-1] for line in open("/proc/self/maps")
               if line.split()[-1].startswith(here) and "openblas" in line})
print(os.environ["OPENBLAS_NUM_THREADS"], *[ctypes.CDLL(path).openblas_get_num_threads() for path in blas])
"""


@pytest.mark.parametrize("preset, expected", [(None, 1), ("2", 2)])
def test_solver_blas_runs_one_thread_unless_the_user_chose(preset, expected):
    """After ``import gearopt`` the environment asks one BLAS thread, and CasADi's own OpenBLAS (loaded with the
    first Ipopt solver, where the wheel bundles one) runs one, unless the user set ``OPENBLAS_NUM_THREADS`` first
    (numerics module docstring: its spinning threads cost CPU)."""
    env = {k: v for k, v in os.environ.items() if k != nm.BLAS_THREADS_VARIABLE}
    if preset is not None:
        env[nm.BLAS_THREADS_VARIABLE] = preset
    out = subprocess.run([sys.executable, "-c", _SOLVER_BLAS_THREADS], env=env, capture_output=True, text=True,
                         timeout=120, check=True)
    variable, *threads = (int(v) for v in out.stdout.split())
    assert variable == expected
    assert all(t == expected for t in threads)
