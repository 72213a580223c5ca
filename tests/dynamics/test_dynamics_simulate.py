"""Time integration of torsional networks (gearopt.dynamics.simulate): conservation laws, impacts, integrators."""

import math

import numpy as np
import pytest
from dynamics_networks import J1, J2, R1, R2, W_MESH, forced_pair, free_pair

from gearopt.dynamics.mesh import MeshStiffnessShape, restitution_coefficient
from gearopt.dynamics.modes import forced_response, linear_matrices
from gearopt.dynamics.network import ANGLE_UNIT_RAD
from gearopt.dynamics.simulate import Simulator, simulate
from gearopt.errors import GearoptInputError


def test_undamped_free_vibration_conserves_energy():
    # no damping, no excitation: in deviation coordinates M phi'' + K phi = 0, so E = phi'M phi'/2 + phi'K phi/2
    # is constant (the nominal rotation does no work on the deviations)
    net = forced_pair(mean_Nm=0.0, ripple_Nm=0.0, damping=False)
    x0 = np.array([0.5, -0.3, 0.8, 20.0, 0.0, -10.0])   # mrad and rad/s of g1, g2, load
    mats = linear_matrices(net)
    drift = {rtol: _energy_drift(net, mats, x0, rtol) for rtol in (1e-7, 1e-10)}
    # BDF is slightly dissipative: the drift shrinks with the tolerance and is small at a tight one
    assert drift[1e-10] < 3e-6 and drift[1e-10] < 0.1 * drift[1e-7]


def _energy_drift(net, mats, x0, rtol):
    sim = simulate(net, 1000.0, cycles=1, backlash=False, rtol=rtol, x0=x0, output_step_deg=0.5)
    phi = sim.node_angle_mrad[["g1", "g2", "load"]].to_numpy() * ANGLE_UNIT_RAD
    ratios = net.speed_ratios()
    omega = 1000 * math.pi / 30
    rate = np.column_stack([sim.node_speed_rpm[n].to_numpy() * math.pi / 30 - ratios[n] * omega
                            for n in ("g1", "g2", "load")])
    energy = 0.5 * np.einsum("ti,ij,tj->t", rate, mats["M"], rate) + 0.5 * np.einsum("ti,ij,tj->t", phi, mats["K"], phi)
    e0 = 0.5 * x0[3:] @ mats["M"] @ x0[3:] + 0.5 * (x0[:3] * 1e-3) @ mats["K"] @ (x0[:3] * 1e-3)
    assert np.ptp(sim.transmission_error_um["g1-g2"]) > 1.0           # it did vibrate
    return float(np.max(np.abs(energy - e0)) / e0)


def test_zero_backlash_reproduces_the_linear_response():
    shape = MeshStiffnessShape.from_contact_ratios(1.6)
    net = forced_pair(ripple_Nm=400.0, shape=shape)   # ripple large enough that the linear force changes sign
    lin = simulate(net, 1500.0, cycles=2, backlash=False, rtol=1e-9)
    lash = simulate(net, 1500.0, cycles=2, backlash=True, rtol=1e-9, parameters={"g1-g2.backlash_mm": 0.0})
    f_lin, f_lash = lin.mesh_force_N["g1-g2"].to_numpy(), lash.mesh_force_N["g1-g2"].to_numpy()
    assert f_lin.min() < 0 < f_lin.max()
    assert np.max(np.abs(f_lash - f_lin)) < 1e-5 * np.max(np.abs(f_lin))


def _bounce_timeline(v, gap, omega_c, horizon):
    """Exact impact times of an undamped linear contact with a dead zone: start mid-gap moving to the drive
    flank; free flight gap/v between flanks, contact half-period pi/omega_c on each flank."""
    t, side, drive, back = 0.5 * gap / v, "drive", 0, 0
    while t < horizon:
        if side == "drive":
            drive += 1
        else:
            back += 1
        t += math.pi / omega_c + gap / v
        side = "back" if side == "drive" else "drive"
    return drive, back


def test_impacts_conserve_momentum_and_energy_and_none_is_skipped():
    # two free gears, undamped lash: the mesh force acts with moments F r1 and F r2, so J1 w1/r1 - J2 w2/r2 is
    # conserved through every impact; elastic contacts restore the kinetic energy; impacts follow the exact
    # timeline of a linear contact (period pi/omega_mesh) with free flight gap/v
    gap, v = 0.1e-3, 0.08
    net = free_pair(backlash_mm=gap * 1e3)
    x0 = np.array([-0.5 * gap / R1 / ANGLE_UNIT_RAD, 0.0, v / R1, 0.0])
    speed = 1000.0
    fine = simulate(net, speed, cycles=1, backlash=True, rtol=1e-9, x0=x0, output_step_deg=0.05)
    omega = speed * math.pi / 30
    w1 = fine.node_speed_rpm["g1"].to_numpy() * math.pi / 30 - omega
    w2 = fine.node_speed_rpm["g2"].to_numpy() * math.pi / 30 + 0.5 * omega
    p = J1 * w1 / R1 - J2 * w2 / R2
    assert np.max(np.abs(p - J1 * v / R1 / R1)) < 1e-7 * abs(J1 * v / R1 / R1)
    contacts = fine.contact_summary().loc["g1-g2"]
    drive, back = _bounce_timeline(v, gap, W_MESH, fine.time_s[-1])
    assert back > 10
    assert contacts["back_impacts_integrated"] == pytest.approx(back, abs=0.6)
    assert contacts["back_impacts_sampled"] == back
    assert contacts["drive_separations_integrated"] == pytest.approx(drive, abs=0.6)
    free = (fine.drive_contact["g1-g2"] < 1e-6) & (fine.back_contact["g1-g2"] < 1e-6)
    kinetic = 0.5 * J1 * w1 ** 2 + 0.5 * J2 * w2 ** 2
    e0 = 0.5 * J1 * (v / R1) ** 2
    assert np.max(np.abs(kinetic[free] - e0)) < 1e-5 * e0
    # a coarse output grid misses contacts in the samples, not in the integrated indicator variation
    coarse = simulate(net, speed, cycles=1, backlash=True, rtol=1e-9, x0=x0, output_step_deg=3.0)
    c = coarse.contact_summary().loc["g1-g2"]
    assert c["back_impacts_integrated"] == pytest.approx(back, abs=0.6)
    assert c["back_impacts_sampled"] < back


@pytest.mark.parametrize("WD, tol", [(0.05, 1e-5), (0.5, 1e-3)])
def test_damped_impact_restitution_matches_the_kelvin_voigt_limit(WD, tol):
    # linear spring-dashpot contact ending at zero overlap: e = exp(-pi zeta / sqrt(1 - zeta^2))
    # (Schwager & Poeschel 2007, Granular Matter 9:465; see gearopt.dynamics.mesh.restitution_coefficient)
    gap, v, zeta = 0.1e-3, 0.08, 0.1
    net = free_pair(damping_ratio=zeta, backlash_mm=gap * 1e3, width_um=0.002, damping_width_um=WD)
    x0 = np.array([-0.5 * gap / R1 / ANGLE_UNIT_RAD, 0.0, v / R1, 0.0])
    sim = simulate(net, 1000.0, cycles=1, backlash=True, rtol=1e-10, x0=x0, output_step_deg=0.02)
    omega = 1000 * math.pi / 30
    w1 = sim.node_speed_rpm["g1"].to_numpy() * math.pi / 30 - omega
    w2 = sim.node_speed_rpm["g2"].to_numpy() * math.pi / 30 + 0.5 * omega
    rel = R1 * w1 + R2 * w2                              # d(delta)/dt
    t = sim.time_s
    t_first = 0.5 * gap / v                              # first contact (drive flank)
    before = rel[t < 0.9 * t_first][-1]
    after = rel[(t > t_first + 1.5 * math.pi / W_MESH) & (t < t_first + 1.5 * math.pi / W_MESH + 0.2 * gap / v)][0]
    # the dashpot's engagement width w_d (here 0.05 and 0.5 um against a 7 um impact penetration) is the only
    # departure from the Kelvin-Voigt contact; it raises e slightly
    assert -after / before == pytest.approx(restitution_coefficient(zeta), rel=tol)


def test_cvodes_against_a_tight_reference_and_the_other_integrators():
    net = forced_pair(shape=MeshStiffnessShape.from_contact_ratios(1.6))
    ref = simulate(net, 1500.0, cycles=1, backlash=True, rtol=1e-11).mesh_force_N["g1-g2"].to_numpy()
    peak = np.max(np.abs(ref))
    for rtol, bound in ((1e-6, 1e-4), (1e-8, 1e-6)):
        f = simulate(net, 1500.0, cycles=1, backlash=True, rtol=rtol).mesh_force_N["g1-g2"].to_numpy()
        assert np.max(np.abs(f - ref)) / peak < bound
    idas = simulate(net, 1500.0, cycles=1, backlash=True, rtol=1e-8, method="idas").mesh_force_N["g1-g2"]
    assert np.max(np.abs(idas.to_numpy() - ref)) / peak < 2e-6
    # fixed-step methods: number_of_finite_elements counts the whole cycle; step set in degrees
    for method, step, bound in (("rk", 0.05, 2e-6), ("collocation", 0.2, 5e-7)):
        f = simulate(net, 1500.0, cycles=1, backlash=True, method=method, fixed_step_deg=step)
        assert np.max(np.abs(f.mesh_force_N["g1-g2"].to_numpy() - ref)) / peak < bound, method


def test_periodic_steady_state_matches_the_harmonic_balance():
    # independent method: with constant mesh stiffness, no lash and a state-independent load the periodic response
    # of the time integration equals the linear forced response summed over harmonics (modes.forced_response)
    net = forced_pair(ripple_Nm=80.0)
    sim = simulate(net, 1500.0, cycles=1, backlash=False, rtol=1e-10, steady_state_tol=1e-7)
    assert sim.converged and sim.run_in_cycles >= 2
    assert sim.cycle_change[-1] < 1e-7
    fr = forced_response(net, [1500.0], max_order=30.0, samples=360)["summary"].set_index(["quantity", "element"])
    f = sim.mesh_force_N["g1-g2"]
    row = fr.loc[("mesh_force_N", "g1-g2")]
    assert f.mean() == pytest.approx(row["mean"], rel=1e-6)
    assert f.max() == pytest.approx(row["max"], rel=1e-4)
    assert f.min() == pytest.approx(row["min"], rel=1e-4)
    torque = sim.shaft_torque_Nm["g2-load"]
    row = fr.loc[("shaft_torque_Nm", "g2-load")]
    assert torque.max() - torque.min() == pytest.approx(row["peak_to_peak"], rel=1e-3)
    # torque balance: the mean mesh force carries the mean load, T0 / r_b2
    assert f.mean() == pytest.approx(100.0 / R2, rel=1e-6)
    assert sim.boundary_torque_Nm["drive"].mean() == pytest.approx(100.0 * R1 / R2, rel=1e-6)


def test_simulator_input_errors():
    net = forced_pair()
    sim = Simulator(net, lash=True, output_step_deg=1.0)
    with pytest.raises(GearoptInputError, match="speed_rpm=100 rpm is below its limit"):
        sim.run(100.0, 1)
    with pytest.raises(GearoptInputError, match="x0 has 2 entries"):
        sim.run(1500.0, 1, x0=[0.0, 0.0])
    with pytest.raises(GearoptInputError, match="method="):
        Simulator(net, method="euler")
    with pytest.raises(GearoptInputError, match="must divide cycle_deg"):
        Simulator(net, output_step_deg=0.7)
    bare = Simulator(net, lash=True, output_step_deg=1.0, output_functions=False)   # the integrator alone
    assert bare.output_function is None and bare.output_names == []
    with pytest.raises(GearoptInputError, match="output_functions=False"):
        bare.run(1500.0, 1)
    assert sim.max_step_deg == pytest.approx(math.degrees(700 * math.pi / 30 / W_MESH), rel=1e-9)
