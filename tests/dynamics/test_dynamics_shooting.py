"""Periodic steady state by shooting (Simulator.periodic_state, steady_state="shooting")."""

import math

import casadi as ca
import numpy as np
import pytest
from dynamics_networks import forced_pair

from gearopt import numerics as nm
from gearopt.dynamics import TorsionalNetwork
from gearopt.dynamics.mesh import MeshStiffnessShape
from gearopt.dynamics.simulate import PeriodicStateError, Simulator
from gearopt.errors import GearoptInputError

J, K, ZETA, F = 0.01, 4.0e4, 0.01, 20.0


def _oscillator():
    # one inertia on a torsional spring-damper to the speed-held ground, forced by F cos(theta) (order 1)
    net = TorsionalNetwork("single DOF", cycle_deg=360.0)
    net.add_inertia("ground", 1.0).add_inertia("m", J)
    net.add_shaft("ground", "m", K, 2.0 * ZETA * math.sqrt(K * J))
    net.set_speed_boundary("ground")
    net.add_torque("m", lambda t, a, w, F0, nominal_angle_rad: F0 * nm.cos(nominal_angle_rad),
                   parameters={"F0": F}, name="force")
    return net


def test_harmonic_oscillator_amplitude_is_the_closed_form():
    # textbook steady state of m x'' + c x' + k x = F cos(w t) (e.g. Thomson, Theory of Vibration, sec. 3.1):
    # X = F / sqrt((k - m w^2)^2 + (c w)^2); w = 0.7 w_n, light damping (zeta 0.01): a run-in decays only by
    # exp(-zeta w_n T) ~ 0.91 per cycle, the shooting is exact Newton on a linear map
    speed = 0.7 * math.sqrt(K / J) * 30.0 / math.pi
    w, c = speed * math.pi / 30.0, 2.0 * ZETA * math.sqrt(K * J)
    amplitude = F / math.sqrt((K - J * w * w) ** 2 + (c * w) ** 2)
    sim = Simulator(_oscillator(), lash=False, rtol=1e-9, output_step_deg=0.5)
    run = sim.run(speed, 1, steady_state="shooting", x0=np.zeros(2))
    phi = run.node_angle_mrad["m"].to_numpy() * 1e-3
    assert 0.5 * np.ptp(phi) == pytest.approx(amplitude, rel=1e-5)
    assert run.steady_state_method == "shooting" and run.shooting["iterations"] <= 2
    assert run.shooting["residual"] < 1e-6
    # the same start, ten run-in cycles: still far from the steady amplitude
    slow = sim.run(speed, 1, run_in_cycles=10, x0=np.zeros(2))
    assert abs(0.5 * np.ptp(slow.node_angle_mrad["m"].to_numpy() * 1e-3) / amplitude - 1.0) > 0.01


def test_shooting_equals_the_run_in_limit_and_its_jacobian_is_the_sensitivity():
    # no lash, parametric mesh-stiffness excitation: both Jacobians reach the state that a long run-in reaches
    net = forced_pair(ripple_Nm=300.0, shape=MeshStiffnessShape.from_contact_ratios(1.6))
    sim = Simulator(net, lash=False, rtol=1e-9, output_step_deg=1.0)
    exact = sim.periodic_state(1500.0, jacobian="sensitivity")
    chord = sim.periodic_state(1500.0, jacobian="linear")
    limit = sim.run(1500.0, 1, run_in_cycles=15).final_state
    scale = np.max(np.abs(limit))
    assert np.max(np.abs(exact["x0"] - limit)) < 1e-5 * scale
    assert np.max(np.abs(chord["x0"] - limit)) < 1e-5 * scale
    assert exact["converged"] and chord["converged"] and exact["neutral_directions"] == 0
    # CasADi forward sensitivities of the cycle map against central differences
    cycle_map, x, p = sim._cycle_map()
    jac = ca.Function("cycle_jacobian", [x, p], [ca.jacobian(cycle_map(x, p), x)])
    pvec = sim.parameter_vector(1500.0)
    x0 = exact["x0"]
    analytic = np.array(jac(x0, pvec))
    fd = np.zeros_like(analytic)
    for i in range(x0.size):
        h = 1e-2 * max(1.0, abs(x0[i]))      # the map is nearly linear; a large step keeps integrator noise out
        e = np.zeros(x0.size)
        e[i] = h
        fd[:, i] = (np.array(cycle_map(x0 + e, pvec)) - np.array(cycle_map(x0 - e, pvec))).ravel() / (2 * h)
    assert np.max(np.abs(analytic - fd)) < 1e-3 * np.max(np.abs(analytic))


def test_failed_shooting_raises_a_typed_error_or_falls_back_to_run_in():
    net = forced_pair(ripple_Nm=1000.0, shape=MeshStiffnessShape.from_contact_ratios(1.6))
    sim = Simulator(net, lash=True, rtol=1e-7, output_step_deg=1.0)
    with pytest.raises(PeriodicStateError, match="did not converge") as info:
        sim.run(1500.0, 1, steady_state="shooting", shooting_max_iter=1, shooting_jacobian="linear",
                shooting_tol=1e-12)
    assert info.value.result["residual"] > 1e-12 and "run-in" in info.value.hint
    run = sim.run(1500.0, 1, steady_state="shooting", shooting_max_iter=1, shooting_jacobian="linear",
                  shooting_tol=1e-12, on_shooting_failure="run-in", steady_state_tol=0.5)
    assert run.steady_state_method == "run-in (shooting failed)" and not run.shooting["converged"]
    assert run.run_in_cycles >= 2 and run.cycle_change[-1] < 0.5
    with pytest.raises(GearoptInputError, match="steady_state"):
        sim.run(1500.0, 1, steady_state="newton")
    free = TorsionalNetwork("free", cycle_deg=360.0)
    free.add_inertia("a", 0.01).add_inertia("b", 0.01).add_shaft("a", "b", 1e4)
    with pytest.raises(GearoptInputError, match="speed boundary"):
        Simulator(free, lash=False).periodic_state(1000.0)
