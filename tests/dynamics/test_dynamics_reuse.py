"""Runs computed once per session (gearopt.dynamics.simulate.simulate(reuse=True)): identical arguments share one
Simulation, anything different (parameters, speed, cycles, a changed network, reuse=False) integrates again."""

import numpy as np
from dynamics_networks import forced_pair

from gearopt.dynamics.simulate import simulate


def test_identical_runs_are_shared_and_different_ones_are_not():
    net = forced_pair(ripple_Nm=50.0)
    args = dict(cycles=1, backlash=True, output_step_deg=5.0, jit=False)
    a = simulate(net, 1500.0, **args)
    assert simulate(net, 1500.0, **args) is a
    fresh = simulate(net, 1500.0, reuse=False, **args)
    assert fresh is not a
    np.testing.assert_array_equal(fresh.mesh_force_N.to_numpy(), a.mesh_force_N.to_numpy())
    assert simulate(net, 1600.0, **args) is not a
    assert simulate(net, 1500.0, parameters={"g1-g2.backlash_mm": 0.05}, **args) is not a
    assert simulate(net, 1500.0, **dict(args, cycles=2)) is not a
    assert simulate(net, 1500.0, x0=a.final_state, **args) is not a
    net.add_inertia("extra", 0.1)   # a changed network forgets its runs
    net.add_shaft("load", "extra", 1e4, 1.0)
    assert simulate(net, 1500.0, **args) is not a
