"""Friction joint element (gearopt.dynamics.joint_friction): closed forms of Coulomb slip with a combined capacity,
key and shoulder stops, ratcheting direction, spur limit, regularisation convergence, typed failures."""

import math
from dataclasses import replace

import numpy as np
import pytest

from gearopt import numerics as nm
from gearopt.dynamics import TorsionalNetwork
from gearopt.dynamics.joint_friction import (
    SLIP_UNIT_M,
    STATES_PER_JOINT,
    THRUST_FREE_STATES,
    FrictionJoint,
    JointIntegrationError,
    JointSimulator,
    slip_rates_m_s,
    walked_distance_mm,
)
from gearopt.errors import GearoptInputError

RB1, RB2, JG, K_MESH = 0.040, 0.050, 0.01, 1e8
R_FIT = 0.020
SPEED = 1000.0
CYCLE_S = 60.0 / SPEED  # cycle_deg 360


def gear_on_shaft(beta_deg=20.0, mean_Nm=300.0, ripple_Nm=0.0):
    """Speed-controlled pinion driving a gear (node 'gear') whose shaft load acts on the gear node itself: the
    joint torque (mesh torque - J alpha) then equals the load torque exactly, whatever the dynamics."""
    net = TorsionalNetwork("gear on shaft", cycle_deg=360.0)
    net.add_inertia("drive", 1.0).add_inertia("gear", JG)
    net.add_mesh("drive", "gear", base_radii_mm=(RB1 * 1e3, RB2 * 1e3), teeth=(32, 40), stiffness_N_per_m=K_MESH,
                 damping_N_s_per_m=2 * 0.1 * math.sqrt(K_MESH * JG / RB2 ** 2), base_helix_angle_deg=beta_deg)
    net.set_speed_boundary("drive")
    net.add_torque("gear", lambda t, a, w, T0, T1, nominal_angle_rad: -(T0 + T1 * nm.sin(2 * nominal_angle_rad)),
                   parameters={"T0": mean_Nm, "T1": ripple_Nm}, name="load")
    return net


def joint(sign=1.0, capacity=10000.0, key=None, slip_speed=1.0, **kw):
    return FrictionJoint("j", "gear", 2e3 * R_FIT, capacity, (("drive-gear", sign),), JG, key_clearance_um=key,
                         slip_speed_m_s=slip_speed, **kw)


def run(net, j, cycles=1, run_in=0, **kw):
    return JointSimulator(net, [j], lash=False, **kw).run(SPEED, cycles, run_in_cycles=run_in)


def test_steady_sliding_under_constant_force_matches_closed_form():
    # constant demand D = (T/r, F_a) outside the capacity circle: v = V (|D|/C - 1) along D/|D| (closed form of
    # the viscoplastic law), hence u_a / u_t = F_a r / T -- the rigid-plastic Coulomb slip direction. One run-in
    # cycle: the gear's axial mass starts from rest and lags the interface's slip for a few m/sqrt(k_c m) at first
    T, beta = 300.0, 20.0
    res = run(gear_on_shaft(beta, T), joint(), run_in=1)
    d_t, d_a = T / R_FIT, T / RB2 * math.tan(math.radians(beta))
    mag = math.hypot(d_t, d_a)
    v = 1.0 * (mag / 10000.0 - 1.0)
    s = res.summary.loc["j"]
    assert res.frames["thrust_N"]["j"].to_numpy() == pytest.approx(d_a, rel=1e-6)
    # the gear's equilibrium: mesh torque - J alpha = the load on the gear (absolute sense: the gear turns -)
    assert res.frames["joint_torque_Nm"]["j"].to_numpy() == pytest.approx(-T, rel=1e-6)
    assert s["slip_um_per_cycle"] == pytest.approx(v * d_t / mag * CYCLE_S * 1e6, rel=1e-4)
    assert s["axial_creep_um_per_cycle"] == pytest.approx(v * d_a / mag * CYCLE_S * 1e6, rel=1e-4)
    assert s["max_rigid_utilisation"] == pytest.approx(mag / 10000.0, rel=1e-6)


def test_slip_rate_law_inside_circle_is_exactly_zero_and_dual_typed():
    assert slip_rates_m_s(600.0, 800.0, 1000.0001, 1.0) == (0.0, 0.0)
    v_t, v_a = slip_rates_m_s(1200.0, 1600.0, 1000.0, 1.0)   # |D| = 2000 = 2 C: speed 1 m/s along (0.6, 0.8)
    assert (v_t, v_a) == pytest.approx((0.6, 0.8), rel=1e-9)
    x = nm.symbol("x", 2)
    f = nm.function("f", [x], [nm.vertcat(*slip_rates_m_s(x[0], x[1], 1000.0, 1.0))])
    assert np.array(f([1200.0, 1600.0])).ravel() == pytest.approx([0.6, 0.8], rel=1e-9)


def test_no_creep_below_capacity_under_oscillating_load():
    # peak demand ~0.75 of capacity: the hub sticks, both slip states stay exactly at rest
    res = run(gear_on_shaft(20.0, 100.0, 50.0), joint(capacity=10000.0, key=10.0), cycles=2)
    s = res.summary.loc["j"]
    assert s["max_rigid_utilisation"] < 0.8
    assert s["slip_um_per_cycle"] == 0.0
    assert abs(s["axial_creep_um_per_cycle"]) < 1e-12


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_ratchet_creep_direction_follows_thrust_sign(sign):
    # torque swings beyond capacity with the key engaged: off-nose thrust (+1) walks the gear off every cycle;
    # thrust towards the shoulder (-1) cannot move it (one-sided stop): it stays within the shoulder's compliance
    res = run(gear_on_shaft(20.0, 100.0, 250.0), joint(sign, key=10.0), cycles=3 if sign > 0 else 8, run_in=1)
    s = res.summary.loc["j"]
    assert s["slip_um_per_cycle"] > 5.0
    if sign > 0:
        assert s["axial_creep_um_per_cycle"] > 0.5
        # the ratchet need not repeat every cycle (the slip state shifts against the key): per-cycle spread reported
        assert s["max_cycle_axial_creep_um"] >= s["axial_creep_um_per_cycle"]
        assert s["axial_creep_um_cycle_std"] >= 0.0
    else:
        k_sh = joint().shoulder_stiffness_N_per_m
        assert s["axial_position_um"] >= -1.01 * res.frames["thrust_N"]["j"].abs().max() / k_sh * 1e6
        # the load ripple reverses the thrust briefly (off the nose): the gear lifts off the shoulder elastically
        # (F/k_c) and the slip settles in a few cycles (shakedown: geometrically decaying steps), no ratchet
        z = res.frames["axial_slip_um"]["j"].to_numpy().reshape(8, -1)
        steps = np.diff(z.max(axis=1))
        assert abs(steps[-1]) < 0.1 * abs(steps[0]) and abs(steps[-1]) < 0.01
        assert z.max() < 2.0 * res.frames["thrust_N"]["j"].max() / joint().interface_stiffness_N_per_m * 1e6


def test_thrust_towards_the_shoulder_pulls_a_loose_gear_back():
    net = gear_on_shaft(20.0, 100.0, 250.0)
    sim = JointSimulator(net, [joint(-1.0, key=10.0)], lash=False)
    x0 = np.concatenate([sim.base.static_state(SPEED), np.array([0.0, 50.0, 50.0, 0.0]) * 1e-6 / SLIP_UNIT_M])  # gear 50 um off the shoulder
    res = sim.run(SPEED, 2, run_in_cycles=0, x0=x0)
    assert res.summary.loc["j", "axial_creep_um_per_cycle"] < -0.5  # mirror of the +1 ratchet


def test_spur_mesh_slips_without_axial_creep():
    res = run(gear_on_shaft(0.0, 100.0, 250.0), joint(1.0, key=10.0), cycles=2)
    s = res.summary.loc["j"]
    assert s["slip_um_per_cycle"] > 5.0
    assert abs(s["axial_creep_um_per_cycle"]) < 1e-9


def test_thrust_free_joint_integrates_its_circumferential_slip_only():
    """A gear on which no mesh puts a thrust (here: a helical mesh the joint takes no thrust sign from) carries one
    slip state instead of four -- its axial states would stay exactly 0 -- and slips as the four-state joint with
    zero thrust does (same network, thrust scaled to 0; they differ by CVODES' step choice only, a smooth run)."""
    net = gear_on_shaft(20.0, 100.0, 250.0)
    free = FrictionJoint("j", "gear", 2e3 * R_FIT, 10000.0, (), JG, key_clearance_um=10.0, slip_speed_m_s=1.0)
    full = joint(1.0, key=10.0)
    sim_free = JointSimulator(net, [free], lash=False, rtol=1e-8)
    sim_full = JointSimulator(net, [full], lash=False, rtol=1e-8)
    assert sim_free.eq.thrust_free == (True,) and sim_full.eq.thrust_free == (False,)
    assert sim_full.eq.x.numel() - sim_free.eq.x.numel() == STATES_PER_JOINT - THRUST_FREE_STATES
    a = sim_free.run(SPEED, 2, run_in_cycles=0).summary.loc["j"]
    b = sim_full.run(SPEED, 2, run_in_cycles=0, parameters={"j.thrust_scale": 0.0}).summary.loc["j"]
    assert a["slip_um_per_cycle"] > 5.0
    assert a["slip_um_per_cycle"] == pytest.approx(b["slip_um_per_cycle"], rel=1e-4)
    assert a["max_rigid_utilisation"] == pytest.approx(b["max_rigid_utilisation"], rel=1e-6)
    assert a["axial_creep_um_per_cycle"] == 0.0 and a["axial_position_um"] == 0.0


def test_regularisation_converges():
    # ratchet creep as the slip law approaches rate-independent Coulomb (V -> inf); tight rtol so that the
    # integration error stays below the regularisation error (at rtol 1e-6, V = 1 m/s is within 0.2 % here)
    creep = []
    for v in (0.3, 1.0, 3.0, 10.0):
        res = run(gear_on_shaft(20.0, 100.0, 250.0), joint(1.0, key=10.0, slip_speed=v), cycles=2, run_in=1,
                  rtol=1e-8)
        creep.append(res.summary.loc["j", "axial_creep_um_per_cycle"])
    steps = np.abs(np.diff(creep))
    assert steps[2] < steps[1] < steps[0]
    assert steps[2] < 1e-3 * abs(creep[-1])


def test_key_stop_closed_form():
    # constant torque above capacity, thrust off the nose: free slip across the clearance along D = (T/r, F_a),
    # then the key takes the torque beyond the circle: D_t falls to sqrt(C^2 - F_a^2) while du_a/du_t = F_a/D_t:
    # u_t = c + (T/r - sqrt(C^2 - F_a^2))/k,  u_a = c F_a r/T + (F_a/k) ln((T/r)/sqrt(C^2 - F_a^2))
    T, beta, C, c, k = 300.0, 20.0, 10000.0, 10e-6, 1e9
    # V small enough that the slip (ms) is slower than the gear's axial response on the interface (sqrt(m/k_c) =
    # 45 us): the thrust is then carried by the interface all along the path; the path itself is rate-independent
    # (the slip direction is D/|D| whatever the overstress), so the closed form holds at any V that slow
    res = run(gear_on_shaft(beta, T), joint(1.0, capacity=C, key=c * 1e6, slip_speed=0.02))
    d_t, f_a = T / R_FIT, T / RB2 * math.tan(math.radians(beta))
    held = math.sqrt(C ** 2 - f_a ** 2)
    u_t = c + (d_t - held) / k
    u_a = c * f_a / d_t + f_a / k * math.log(d_t / held)
    assert abs(res.frames["slip_um"]["j"].iloc[-1]) == pytest.approx(u_t * 1e6, rel=2e-3)
    # the plastic axial slip z (the gear itself sits a further F_a/k_c off it, elastically)
    assert res.frames["axial_slip_um"]["j"].iloc[-1] == pytest.approx(u_a * 1e6, rel=2e-3)
    assert abs(res.frames["key_force_N"]["j"].iloc[-1]) == pytest.approx(d_t - held, rel=2e-3)


def test_shoulder_stop_holds_thrust_towards_it():
    # no key, sustained circumferential slip, thrust into the shoulder: the shoulder reacts the thrust, the
    # axial position settles at the contact compression F_a / k_sh
    T, beta = 300.0, 20.0
    j = joint(-1.0)
    res = run(gear_on_shaft(beta, T), j)
    f_a = T / RB2 * math.tan(math.radians(beta))
    assert res.summary.loc["j", "slip_um_per_cycle"] > 1000.0
    assert res.frames["axial_position_um"]["j"].iloc[-1] == pytest.approx(-f_a / j.shoulder_stiffness_N_per_m * 1e6,
                                                                          rel=1e-3)


def test_integration_without_step_budget_raises_typed_error():
    net = gear_on_shaft(20.0, 100.0, 250.0)
    sim = JointSimulator(net, [joint(1.0, key=10.0)], lash=False, max_num_steps=20)
    with pytest.raises(JointIntegrationError, match="could not hold"):
        sim.run(SPEED, 1, run_in_cycles=0)


def test_bad_input_names_the_parameter():
    with pytest.raises(GearoptInputError, match="capacity_N"):
        joint(capacity=-1.0)
    with pytest.raises(GearoptInputError, match="slip_speed_m_s"):
        joint(slip_speed=0.0)
    with pytest.raises(GearoptInputError, match="gear_mass_kg"):
        joint(gear_mass_kg=0.0)
    with pytest.raises(GearoptInputError, match="interface_stiffness_N_per_m"):
        joint(interface_stiffness_N_per_m=-1.0)
    with pytest.raises(GearoptInputError, match="thrust sign"):
        FrictionJoint("j", "gear", 40.0, 1e4, (("drive-gear", 0.5),), JG)
    sim = JointSimulator(gear_on_shaft(), [joint()], lash=False)
    with pytest.raises(GearoptInputError, match="j.capacity_N"):
        sim.run(SPEED, 1, parameters={"j.capacity_N": 0.0})
    with pytest.raises(GearoptInputError, match="hours"):
        walked_distance_mm(1.0, 3000.0, -1.0)
    with pytest.raises(GearoptInputError, match="integration='both'"):
        JointSimulator(gear_on_shaft(), [joint()], lash=False, integration="both")
    with pytest.raises(GearoptInputError, match="forcing_step_deg=0.3 must divide output_step_deg=0.5"):
        JointSimulator(gear_on_shaft(), [joint()], lash=False, forcing_step_deg=0.3)
    with pytest.raises(GearoptInputError, match="forcing_step_deg"):
        JointSimulator(gear_on_shaft(), [joint()], lash=False, forcing_step_deg=1.0)
    with pytest.raises(GearoptInputError, match="thrust_free_integrator='euler'"):
        JointSimulator(gear_on_shaft(), [joint()], lash=False, thrust_free_integrator="euler")


def test_sequential_integration_matches_the_simultaneous_one():
    """The coupling is one-way, so integrating the network first and the slip states after it, driven by the
    forcing interpolated linearly on a grid, is the same model as integrating them together: on a ratcheting joint
    (stick-slip on the key every load cycle) both agree to the integrators' tolerance, and a forcing grid 20x
    coarser than the default moves the slip and the creep by less than 0.1 %."""
    net = gear_on_shaft(20.0, 100.0, 250.0)
    quantities = ["slip_um_per_cycle", "axial_creep_um_per_cycle", "max_rigid_utilisation", "max_key_force_N"]
    results = {}
    for name, options in {"simultaneous": {"integration": "simultaneous"}, "sequential": {},
                          "coarse": {"forcing_step_deg": 0.5}}.items():
        sim = JointSimulator(net, [joint(1.0, key=10.0)], lash=False, rtol=1e-8, **options)
        results[name] = sim.run(SPEED, 2, run_in_cycles=0).summary.loc["j", quantities]
    reference = results["simultaneous"]
    assert reference["slip_um_per_cycle"] > 5.0 and reference["axial_creep_um_per_cycle"] > 1.0  # it ratchets
    assert results["sequential"].to_numpy() == pytest.approx(reference.to_numpy(), rel=1e-5)
    assert results["coarse"].to_numpy() == pytest.approx(reference.to_numpy(), rel=1e-3)


def test_thrust_free_slip_by_fixed_steps_matches_cvodes():
    """A spur gear's joints (no thrust: one slip state each) are integrated by fixed BDF2 steps on the forcing grid
    (the default ``thrust_free_integrator``): on a key-ratcheting spur joint with three capacities, every chunk's
    steps converge, and slip path, key force and utilisation agree with CVODES at rtol 1e-8 within 0.5 %."""
    net = gear_on_shaft(0.0, 100.0, 250.0)
    joints = [replace(joint(1.0, key=10.0, capacity=c), name=f"j{i}") for i, c in enumerate((3000.0, 6000.0, 12000.0))]
    quantities = ["slip_um_per_cycle", "max_key_force_N", "max_utilisation", "max_rigid_utilisation"]
    results, slips = {}, {}
    for integrator in ("cvodes", "bdf2"):
        sim = JointSimulator(net, joints, lash=False, rtol=1e-8, thrust_free_integrator=integrator)
        assert all(sim.eq.thrust_free)
        res = sim.run(SPEED, 2, run_in_cycles=0)
        assert res.stats["fallback_chunks"] == 0 and res.stats["substep_steps"] >= 0
        results[integrator], slips[integrator] = res.summary[quantities], res.frames["slip_um"].to_numpy()
    ref = results["cvodes"]
    assert ref.loc["j0", "slip_um_per_cycle"] > 20.0 and ref.loc["j0", "max_key_force_N"] > 100.0  # rides the key
    assert results["bdf2"].to_numpy() == pytest.approx(ref.to_numpy(), rel=5e-3)
    span = slips["cvodes"].max(axis=0) - slips["cvodes"].min(axis=0)          # and point by point on the output grid
    assert np.all(np.abs(slips["bdf2"] - slips["cvodes"]).max(axis=0) < 2e-3 * span)


def test_unresolved_fixed_steps_fall_back_to_cvodes():
    """A chunk whose fixed steps leave a residual above the absolute tolerance is integrated by CVODES instead: with
    every chunk rejected the result is CVODES' own; with every other chunk rejected the fixed steps restart after
    each CVODES chunk and the slip follows CVODES' point by point; the run counts the chunks."""
    net = gear_on_shaft(0.0, 100.0, 250.0)
    reference = JointSimulator(net, [joint(1.0, key=10.0)], lash=False, rtol=1e-8, thrust_free_integrator="cvodes")
    a = reference.run(SPEED, 1, run_in_cycles=0)
    sim = JointSimulator(net, [joint(1.0, key=10.0)], lash=False, rtol=1e-8)
    sim._fixed_steps_resolved = lambda residuals: False
    b = sim.run(SPEED, 1, run_in_cycles=0)
    assert b.stats["fallback_chunks"] == sim.chunks
    assert b.summary.to_numpy() == pytest.approx(a.summary.to_numpy(), rel=1e-12, abs=1e-12)
    verdicts = iter([True, False] * sim.chunks)
    sim._fixed_steps_resolved = lambda residuals: next(verdicts)
    c = sim.run(SPEED, 1, run_in_cycles=0)
    assert c.stats["fallback_chunks"] == sim.chunks // 2
    slip_a, slip_c = a.frames["slip_um"].to_numpy(), c.frames["slip_um"].to_numpy()
    assert slip_a.max() - slip_a.min() > 5.0
    assert np.abs(slip_c - slip_a).max() < 2e-3 * (slip_a.max() - slip_a.min())


def test_walked_distance_counts_four_stroke_cycles():
    # 1 um per cycle for 1 h at 3000 rpm: 1500 cycles/min x 60 = 90 000 cycles = 90 mm
    assert walked_distance_mm(1.0, 3000.0, 1.0) == pytest.approx(90.0)


def test_thrust_above_capacity_slides_the_gear_by_newton_with_coulomb_friction():
    # key without clearance holds the torque, thrust F above the capacity C: the gear (mass m) slides off with
    # m dw/dt = F - C (1 + w/V) -> w = V (F/C - 1)(1 - exp(-t/tau)), tau = m V / C; for t << tau this is Coulomb
    # friction with inertia, x = (F - C) t^2 / (2 m) (closed form of the element; Meriam & Kraige, dry friction)
    T, beta, C, m, V = 300.0, 20.0, 1500.0, 1.0, 30.0
    F = T / RB2 * math.tan(math.radians(beta))
    j = joint(1.0, capacity=C, key=0.0, slip_speed=V, gear_mass_kg=m)
    sim = JointSimulator(gear_on_shaft(beta, T), [j], lash=False, rtol=1e-8)
    # start with the key already holding the torque (u_t = T/(r k)) and the interface at its capacity (u_a = C/k_c)
    x0 = np.concatenate([sim.base.static_state(SPEED),
                         np.array([-T / R_FIT / j.key_stiffness_N_per_m, 0.0, C / j.interface_stiffness_N_per_m,
                                   0.0]) / SLIP_UNIT_M])
    res = sim.run(SPEED, 1, run_in_cycles=0, x0=x0)
    t = np.radians(res.crank_angle_deg) / (2 * math.pi) * CYCLE_S
    tau = m * V / C
    x = V * (F / C - 1.0) * (t - tau * (1.0 - np.exp(-t / tau)))
    z = res.frames["axial_slip_um"]["j"].to_numpy() * 1e-6
    late = t > 0.2 * CYCLE_S
    assert z[late] == pytest.approx(x[late], rel=2e-3)
    early = (t > 0.02 * tau) & (t < 0.05 * tau)
    assert z[early] == pytest.approx((F - C) * t[early] ** 2 / (2 * m), rel=0.03)
    assert res.frames["slip_um"]["j"].abs().max() < 1.01 * T / R_FIT / 1e9 * 1e6  # the key holds the torque


def test_ratchet_creep_bounded_by_the_coulomb_flow_rule():
    # while the hub slips round, du_a/|du_t| = D_a/|D_t| <= F_max / sqrt(C^2 - F_max^2) (|D| >= C, D_a <= F_max):
    # creep per cycle is bounded by the slip path times that ratio -- nothing accumulates without circumferential
    # slip, and the spur limit (F = 0) has no creep at all
    C = 10000.0
    res = run(gear_on_shaft(20.0, 100.0, 250.0), joint(1.0, capacity=C, key=10.0), cycles=3, run_in=1)
    s = res.summary.loc["j"]
    f_max = res.frames["thrust_N"]["j"].max()
    bound = s["slip_um_per_cycle"] * f_max / math.sqrt(C ** 2 - f_max ** 2)
    assert 0.0 < s["axial_creep_um_per_cycle"] <= bound
    assert s["max_cycle_axial_creep_um"] <= 1.01 * bound
