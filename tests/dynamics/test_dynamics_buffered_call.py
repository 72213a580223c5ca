"""Calls through ``casadi.FunctionBuffer`` (:mod:`gearopt.dynamics.buffered_call`) give the numbers of plain CasADi
calls, per-call statistics, and the same errors; the simulator's cycles through them reproduce plain calls of its
integrator and output function. Reference: the plain ``Function.__call__`` of CasADi on the same inputs."""

import casadi as ca
import numpy as np
import pytest
from dynamics_networks import forced_pair

from gearopt.dynamics import budget
from gearopt.dynamics.buffered_call import BufferedFunction
from gearopt.dynamics.network import OFFSET_PARAMETER
from gearopt.dynamics.simulate import simulator
from gearopt.errors import BudgetExceededError


def _decay():
    x, p = ca.SX.sym("x", 2), ca.SX.sym("p", 2)
    dae = {"x": x, "p": p, "ode": ca.vertcat(x[1], -p[0] * x[0] - p[1] * x[1]), "quad": x[0] ** 2}
    return ca.integrator("decay", "cvodes", dae, 0.0, np.linspace(0.1, 2.0, 20), {"reltol": 1e-8, "abstol": 1e-10})


def test_matrix_inputs_and_outputs_are_read_and_written_column_major():
    a, b = ca.SX.sym("a", 3, 4), ca.SX.sym("b", 4, 2)
    f = ca.Function("f", [a, b], [ca.mtimes(a, b), ca.sin(a) + 2.0])
    rng = np.random.default_rng(1)
    av, bv = rng.normal(size=(3, 4)), rng.normal(size=(4, 2))
    got = BufferedFunction(f, [0, 1], [0, 1])(av, bv)
    want = [np.array(v) for v in f(av, bv)]
    for g, w in zip(got, want):
        assert g.shape == w.shape
        np.testing.assert_array_equal(g, w)
    # a C-ordered slice and a transposed view are read by their values, not their memory layout
    got = BufferedFunction(f, [0, 1], [0])(np.ascontiguousarray(av.T).T, bv[:, ::-1][:, ::-1])
    np.testing.assert_array_equal(got[0], want[0])


def test_integrator_outputs_and_per_call_statistics_match_the_plain_call():
    integ = _decay()
    x0, p = np.array([1.0, 0.0]), np.array([40.0, 0.5])
    plain = integ(x0=x0, p=p)
    plain_calls = integ.stats()["n_call_daeF"]
    call = BufferedFunction(integ, ["x0", "p"], ["xf", "qf"])
    for _ in range(3):  # CasADi accumulates the counters of one memory; stats() are the last call's
        xf, qf = call(x0, p)
        np.testing.assert_array_equal(xf, np.array(plain["xf"]))
        np.testing.assert_array_equal(qf, np.array(plain["qf"]))
        assert call.stats()["n_call_daeF"] == plain_calls
        assert call.stats()["nsteps"] == integ.stats()["nsteps"]
    # a second buffer may be handed the first one's memory: its statistics still count its own call
    second = BufferedFunction(integ, ["x0", "p"], ["xf"])
    second(x0, p)
    assert second.stats()["n_call_daeF"] == plain_calls


def test_failures_raise_like_the_plain_call_and_inputs_are_checked():
    x = ca.SX.sym("x")
    stiff = ca.integrator("stiff", "cvodes", {"x": x, "ode": -1e6 * x}, 0.0, [1.0], {"max_num_steps": 5})
    call = BufferedFunction(stiff, ["x0"], ["xf"])
    with pytest.raises(RuntimeError, match="TOO_MUCH_WORK"):
        call(np.ones(1))
    with pytest.raises(BudgetExceededError, match="max_num_steps=5"), budget.step_limit_errors(5):
        call(np.ones(1))
    with pytest.raises(ValueError, match="has 1 entries, got 2"):
        call(np.ones(2))
    with pytest.raises(ValueError, match="takes 1 buffered inputs"):
        call(np.ones(1), np.ones(1))
    y = ca.SX.sym("y", ca.Sparsity.diag(3))
    with pytest.raises(ValueError, match="sparse"):
        BufferedFunction(ca.Function("g", [y], [y * 2]), [0], [0])


def test_simulated_cycles_reproduce_plain_calls_and_report_their_evaluation_time():
    net = forced_pair()
    sim = simulator(net, lash=True, rtol=1e-6, jit=False)
    run = sim.run(1500.0, 2, run_in_cycles=1)
    # the same cycles by plain calls of the integrator and the output function
    pvec = sim.parameter_vector(1500.0)
    i_off = sim.eq.parameter_names.index(OFFSET_PARAMETER)
    x, outs = sim.static_state(1500.0), []
    for cycle in range(3):
        p = pvec.copy()
        p[i_off] = cycle * sim.cycle_rad
        xs = np.array(sim.integrator(x0=x, p=p)["xf"])
        if cycle:
            outs.append(np.array(sim.output_function(sim.grid_rad[None, :], xs, np.repeat(p[:, None], sim.n_out, 1))))
        x = xs[:, -1]
    force = np.concatenate([o[sim.output_names.index(("mesh_force_N", "g1-g2"))] for o in outs])
    np.testing.assert_array_equal(run.mesh_force_N["g1-g2"].to_numpy(), force)
    np.testing.assert_array_equal(run.final_state, x)
    stats = run.stats
    assert stats["cycles_integrated"] == 3
    assert 0.0 < stats["function_evaluation_time_s"] < stats["integrator_time_s"] <= stats["integration_time_s"]
    assert 0.0 < stats["output_time_s"] < stats["integration_time_s"]
    assert 0.0 < stats["function_evaluation_cpu_time_s"] < stats["integrator_cpu_time_s"]
    assert stats["integrator_cpu_time_s"] <= stats["integration_cpu_time_s"]
    assert sim.last_cycle_stats["nsteps"] == stats["steps_per_cycle"][-1]
