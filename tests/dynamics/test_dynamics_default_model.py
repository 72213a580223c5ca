"""The packaged default timing-system model, the speed sweep and sensitivities through the integrator."""

import math

import numpy as np
import pytest
from dynamics_networks import J1, R1, forced_pair

from gearopt.data import load_system
from gearopt.cases.timing_train import default_timing_model
from gearopt.dynamics.mesh import MeshStiffnessShape
from gearopt.dynamics.sensitivity import response_sensitivities
from gearopt.dynamics.simulate import Simulator, node_accelerations
from gearopt.dynamics.sweep import cycle_spread, simulation_statistics, speed_sweep, walk_off_history
from gearopt.engine import AccessoryTorque, EngineExcitation
from gearopt.errors import GearoptInputError
from gearopt.joints import walk_off
from gearopt.joints.walk_off import quasi_static_mesh_torques_Nm

MESHES = ["crank-cam", "cam-ac", "cam-fp", "crank-lpi", "lpi-lpg"]


@pytest.fixture(scope="module")
def spur():
    return default_timing_model("spur")


@pytest.fixture(scope="module")
def spur_run(spur):
    # the acceptance call (issue 5), short: two engine cycles without lash; statistics over the second
    return spur.simulate(speed_rpm=2500, cycles=1, backlash=False, rtol=1e-6, run_in_cycles=1, output_step_deg=1.0,
                         external_torques=True, jit=False)


def test_acceptance_interface(spur, spur_run):
    sim = spur_run
    assert list(sim.mesh_force_N.columns) == MESHES
    assert sim.time_s.shape == sim.crank_angle_deg.shape == (720,)
    assert sim.crank_angle_deg[-1] == pytest.approx(720.0)
    assert sim.time_s[-1] == pytest.approx(720.0 / (2500 * 6.0))          # one cycle at 2500 rpm = 48 ms
    assert np.all(np.isfinite(sim.mesh_force_N.to_numpy()))
    by_angle = sim.frame("mesh_force_N", index="crank_angle_deg")
    assert by_angle.index[0] == pytest.approx(1.0) and by_angle.index.name == "crank_angle_deg"
    np.testing.assert_array_equal(by_angle.to_numpy(), sim.mesh_force_N.to_numpy())


def test_mesh_table_matches_the_data_backlash(spur):
    # default_train.toml [meshes.*] backlash_min/max_mm are [C] circumferential backlash at the working circle of the
    # spur train (computed there independently); along the line of action j_bt = j_wt cos(alpha_wt)
    data = load_system().data
    for mesh in MESHES:
        m = data["meshes"][mesh]
        pair = spur.train.pairs[mesh]
        alpha_wt = math.radians(pair.geometry()["working_pressure_angle_deg"])
        expected = 0.5 * (m["backlash_min_mm"] + m["backlash_max_mm"]) * math.cos(alpha_wt)
        assert spur.mesh_table.loc[mesh, "backlash_line_of_action_mm"] == pytest.approx(expected, abs=1.5e-3)
    assert (spur.mesh_table["damping_ratio"] == 0.08).all()


def test_cylinder_and_accessory_torques_are_the_engine_models(spur):
    # the network's torques along the nominal motion against gearopt.engine at the same operating point
    speed = 2500.0
    exc = EngineExcitation.from_data(load_system(), speed_rpm=speed)             # pressure scaled to the speed-load map
    eq = spur.network.equations(lash=False)
    pvec = spur.network.parameter_vector(speed, spur.parameters_at(speed))
    tau = np.radians(np.arange(0.0, 720.0, 7.5))
    omega = speed * math.pi / 30
    torques = np.array(eq.nominal_torques.map(tau.size)(tau[None, :], np.repeat(pvec[:, None], tau.size, 1)))
    free = eq.free_nodes
    ref = np.array(exc.cylinder_torques_Nm(tau, omega))
    for i in range(6):
        np.testing.assert_allclose(torques[free.index(f"throw_{i + 1}")], ref[i], rtol=1e-9, atol=1e-6)
    valve = AccessoryTorque.camshaft(load_system())
    np.testing.assert_allclose(torques[free.index("cam_station_3")], valve(0.5 * tau) / 6.0, rtol=1e-12)
    # absolute sign convention: the cam turns backwards, its load torque is positive in absolute terms
    pump = AccessoryTorque.fuel_pump(load_system())
    np.testing.assert_allclose(torques[free.index("fp_pump")], -pump(0.5 * tau), rtol=1e-12)


def test_mean_torque_balance(spur, spur_run):
    # rigid-body (virtual work) balance of a periodic state: internal shaft and mesh torques do no work on the rigid
    # motion, so sum |r_i| mean(T_i) + reaction = 0; the mean crank-cam force carries the accessory loads referred to
    # the cam gear (valve train and fuel pump at cam speed, air compressor at twice it), gearopt.engine's means
    sim = spur_run
    ext = sim.external_torque_Nm.mean()
    valve, pump = AccessoryTorque.camshaft(load_system()), AccessoryTorque.fuel_pump(load_system())
    comp, lube = AccessoryTorque.air_compressor(load_system()), AccessoryTorque.lube_pump(load_system())
    r_cam = spur.mesh_table.loc["crank-cam", "base_radius_2_mm"] * 1e-3
    cam_load = valve.mean_Nm + pump.mean_Nm + 2.0 * comp.mean_Nm
    assert sim.mesh_force_N["crank-cam"].mean() * r_cam == pytest.approx(cam_load, rel=5e-3)
    crank_load = 0.5 * cam_load + 38.0 / 24.0 * lube.mean_Nm
    cylinders = sum(ext[f"cylinder_{i}"] for i in range(1, 7))
    assert cylinders - crank_load + sim.boundary_torque_Nm["flywheel"].mean() == pytest.approx(0.0, abs=0.5)
    # the applied cylinder torques include the reciprocating masses' response to the vibration (-m s'^2 theta'' and
    # the speed-dependent term): their mean differs from the constant-speed indicated torque by under 1 %
    nominal = EngineExcitation.from_data(load_system(), speed_rpm=2500.0).mean_torque_Nm()
    assert cylinders == pytest.approx(nominal, rel=0.01)


def test_helical_model_reports_axial_forces():
    helical = default_timing_model("helical")
    beta_b = helical.mesh_table.loc["crank-cam", "base_helix_angle_deg"]
    assert 5.0 < beta_b < 6.0
    sim = helical.simulate(speed_rpm=1500, cycles=1, backlash=False, output_step_deg=2.0, jit=False)
    f, fa = sim.mesh_force_N["crank-cam"], sim.axial_force_N["crank-cam"]
    np.testing.assert_allclose(fa, f * math.tan(math.radians(beta_b)), rtol=1e-12)
    # independent derivation (gearopt.joints.walk_off: F_z = -h tan(beta_w) F_theta at the working circle, from the
    # torque 2000 T / d_w): the crank-cam mesh's thrust on the cam gear has the magnitude of F_bt tan(beta_b)
    torques = {m: sim.mesh_force_N[m].to_numpy() * sim.mesh_base_radii_mm[m][0] * 1e-3 for m in MESHES}
    contributions = walk_off(helical.train, torques).contributions
    on_cam = next(c for c in contributions if c["mesh"] == "crank-cam" and c["gear"] == "cam")
    np.testing.assert_allclose(np.abs(on_cam["axial_force_N"]), np.abs(fa), rtol=1e-9)
    w = walk_off_history(helical, sim, "cam")
    total = sum(c["axial_force_N"] for c in contributions if c["gear"] == "cam")
    np.testing.assert_allclose(w["axial_force_N"], total, rtol=1e-12)
    np.testing.assert_allclose(w["joint_torque_Nm"], sim.shaft_torque_Nm["cam-cam_station_1"])
    assert 0 < w["max_slip_utilisation"] < 1 and w["min_combined_margin"] == pytest.approx(
        1 / w["max_slip_utilisation"])
    with pytest.raises(GearoptInputError, match="no shaft element"):
        walk_off_history(helical, sim, "lpi")          # the idler's hub torque is not resolved by the model
    crank = walk_off_history(helical, sim, "crank")
    on_crank = sum(c["axial_force_N"] for c in contributions if c["gear"] == "crank")
    np.testing.assert_allclose(crank["axial_force_N"], on_crank, rtol=1e-12)
    assert np.max(np.abs(crank["axial_force_N"])) > 100.0
    with pytest.raises(GearoptInputError, match="kind='bevel'"):
        default_timing_model("bevel")


def test_speed_sweep_rows_and_statistics(spur, spur_run):
    stats = simulation_statistics(spur_run, shafts=("cam-cam_station_1",))
    row = stats.set_index("element").loc["crank-cam"]
    r2 = spur.mesh_table.loc["crank-cam", "base_radius_2_mm"] * 1e-3
    assert row["peak_gear_2_torque_Nm"] == pytest.approx(spur_run.mesh_force_N["crank-cam"].abs().max() * r2)
    assert row["drive_separations_per_cycle"] == 0.0             # linear meshes never separate
    sweep = speed_sweep(spur, [1200.0], backlash=(False,), cycles=1, run_in_cycles=0, output_step_deg=2.0, jit=False,
                        joints=("crank", "cam", "ac", "fp"))
    assert set(sweep["element"]) == set(MESHES) | {"cam-cam_station_1", "joint:crank", "joint:cam", "joint:ac",
                                                   "joint:fp"}
    crank = sweep.set_index("element").loc["joint:crank"]
    assert 0.0 < crank["peak_torque_Nm"] < np.inf and crank["min_torque_margin"] > 1.0
    joint = sweep.set_index("element").loc["joint:cam"]
    assert joint["peak_axial_force_N"] == 0.0                       # spur: no thrust, the margin is the torque's
    assert joint["min_combined_margin"] == pytest.approx(joint["min_torque_margin"], rel=1e-12)
    assert (sweep["speed_rpm"] == 1200.0).all() and not sweep["backlash"].any()
    # one recorded cycle: its worst is every statistic of the per-cycle spread, and it is the sweep's minimum
    assert crank["cycles"] == 1
    assert crank["torque_margin_cycle_worst"] == crank["torque_margin_cycle_median"] == \
        crank["torque_margin_cycle_best"] == pytest.approx(crank["min_torque_margin"], rel=1e-12)


def test_cycle_spread_of_a_margin_history():
    """Per-cycle worst margins: a periodic history gives one number thrice; a history whose third cycle dips gives
    that dip as the worst, the median of the per-cycle minima and the best cycle's minimum."""
    periodic = np.tile(2.0 + np.sin(np.linspace(0.0, 2 * np.pi, 40, endpoint=False)), 4)
    assert cycle_spread(periodic, 4) == pytest.approx({"worst": 1.0, "median": 1.0, "best": 1.0}, abs=1e-12)
    cycles = np.array([[3.0, 2.0, 4.0], [5.0, 2.5, 6.0], [0.5, 9.0, 9.0], [7.0, 3.0, 8.0]])
    assert cycle_spread(cycles.ravel(), 4) == {"worst": 0.5, "median": 2.25, "best": 3.0}
    assert cycle_spread(5.0, 3) == {"worst": 5.0, "median": 5.0, "best": 5.0}      # a constant margin (spur axial)


def test_sensitivities_through_the_integrator_match_finite_differences():
    # CasADi forward sensitivities (CVODES) of the peak and RMS mesh force over a periodic lash response against
    # central differences of the same integration (the rattle here is periodic: cycle change ~1e-4)
    net = forced_pair(ripple_Nm=1000.0, shape=MeshStiffnessShape.from_contact_ratios(1.6))
    sim = Simulator(net, lash=True, rtol=1e-8, output_step_deg=1.0)
    df = response_sensitivities(sim, 1500.0, ["g1-g2.backlash_mm", "g1-g2.damping_N_s_per_m"],
                                output=("mesh_force_N", "g1-g2"), cycles=1, run_in_cycles=3)
    assert (df["fd_relative_error"] < 0.02).all()
    assert abs(df.set_index("parameter").loc["g1-g2.backlash_mm", "d_peak"]) > 1e3    # N per mm: a real effect
    with pytest.raises(GearoptInputError, match="unknown parameters"):
        response_sensitivities(sim, 1500.0, ["nope"])


# ---------------------------------------------------------------------------------------------------------------
# crank-gear joint torque (the crank gear is lumped in the crankshaft's gear node)
# ---------------------------------------------------------------------------------------------------------------

def test_node_accelerations_are_the_equations_of_motion():
    # independent of the equations' own assembly: J_g1 alpha_g1 = T_shaft(drive-g1) - F_mesh r_b1 (free-body
    # balance of g1 from the recorded outputs), and a finite difference of the recorded speed on a fine grid
    net = forced_pair(ripple_Nm=400.0, shape=MeshStiffnessShape.from_contact_ratios(1.6))
    sim = Simulator(net, lash=False, rtol=1e-9, output_step_deg=0.05).run(1500.0, 1, run_in_cycles=1)
    acc = node_accelerations(net, sim)
    balance = (sim.shaft_torque_Nm["drive-g1"] - sim.mesh_force_N["g1-g2"] * R1).to_numpy() / J1
    np.testing.assert_allclose(acc["g1"].to_numpy(), balance, rtol=0, atol=1e-7 * np.max(np.abs(balance)))
    speed = sim.node_speed_rpm["g2"].to_numpy() * math.pi / 30.0
    fd = np.gradient(speed, sim.time_s)[2:-2]
    a2 = acc["g2"].to_numpy()[2:-2]
    assert np.max(np.abs(fd - a2)) < 0.01 * np.max(np.abs(a2)) and np.max(np.abs(a2)) > 1e3


def test_crank_joint_torque_is_the_mesh_torque_sum_minus_the_gear_inertia_torque(spur, spur_run):
    sim = spur_run
    r_cc = sim.mesh_base_radii_mm["crank-cam"][0] * 1e-3
    r_cl = sim.mesh_base_radii_mm["crank-lpi"][0] * 1e-3
    mesh_sum = -(sim.mesh_force_N["crank-cam"] * r_cc + sim.mesh_force_N["crank-lpi"] * r_cl).to_numpy()
    bare = walk_off_history(spur, sim, "crank", gear_inertia_kgm2=0.0)
    assert bare["joint_torque_method"] == "mesh_sum"
    np.testing.assert_allclose(bare["joint_torque_Nm"], mesh_sum, rtol=1e-12)      # exact without gear inertia
    full = walk_off_history(spur, sim, "crank")
    j_g = load_system().data["gears"]["crank"]["solid_disc_inertia_kgm2"]
    assert full["gear_inertia_kgm2"] == j_g
    alpha = node_accelerations(spur.network, sim)["crank_gear_node"].to_numpy()
    np.testing.assert_allclose(full["joint_torque_Nm"], mesh_sum - j_g * alpha, rtol=1e-12)
    assert np.max(np.abs(j_g * alpha)) > 1.0                                        # a real correction (N m)
    # rigid-body balance of the mean (thesis-free): the crank gear supplies half the cam-gear load plus the lube
    # pump load referred to the crank (gearopt.engine means), as the crank-cam mean in test_mean_torque_balance
    valve, pump = AccessoryTorque.camshaft(load_system()), AccessoryTorque.fuel_pump(load_system())
    comp, lube = AccessoryTorque.air_compressor(load_system()), AccessoryTorque.lube_pump(load_system())
    demand = 0.5 * (valve.mean_Nm + pump.mean_Nm + 2.0 * comp.mean_Nm) + 38.0 / 24.0 * lube.mean_Nm
    assert -full["joint_torque_Nm"].mean() == pytest.approx(demand, rel=1e-2)
    with pytest.raises(GearoptInputError, match="gear_inertia_kgm2"):
        walk_off_history(spur, sim, "crank", gear_inertia_kgm2=-1.0)


def test_crank_joint_torque_is_quasi_static_at_low_speed(spur):
    # no lash, 150 rpm, no gas torque (pressure scale 0; the reciprocating inertia at 150 rpm is small): the train
    # moves quasi-statically, so the crank joint carries the accessory demands at that instant, referred through
    # the tooth ratios -- computed independently with gearopt.joints.quasi_static_mesh_torques_Nm and walk_off
    # from the gearopt.engine load maps. Second half of the first cycle (the start transient has decayed).
    sim = spur.simulate(150.0, cycles=1, backlash=False, rtol=1e-5, output_step_deg=2.0, jit=False,
                        min_speed_rpm=100.0, parameters={"cylinders.pressure_scale": 0.0})
    joint = walk_off_history(spur, sim, "crank")["joint_torque_Nm"]
    tau = np.radians(sim.crank_angle_deg) + sim.angle_offset_rad
    r = spur.network.speed_ratios()
    loads = {"cam": AccessoryTorque.camshaft(load_system())(abs(r["cam"]) * tau),
             "fp": AccessoryTorque.fuel_pump(load_system())(abs(r["fp"]) * tau),
             "ac": AccessoryTorque.air_compressor(load_system())(abs(r["ac"]) * tau),
             "lpg": AccessoryTorque.lube_pump(load_system())(abs(r["lpg"]) * tau)}
    expected = walk_off(spur.train, quasi_static_mesh_torques_Nm(spur.train, loads)).joint_torque_Nm["crank"]
    late = sim.crank_angle_deg > 360.0
    assert np.ptp(expected) > 100.0                                                 # a real load history (N m)
    assert np.max(np.abs(joint - expected)[late]) < 0.03 * np.max(np.abs(expected))


def test_default_model_periodic_state_by_shooting(spur):
    # no lash, rated speed: the chord shooting converges in a few cycles and reproduces the run-in limit. The
    # lube-pump ripple (rotor order 7 at 38/24 crank speed) repeats only every 6 engine cycles, so one-cycle
    # states differ by up to ~0.2 % of the peak force from cycle to cycle (measured) -- the tolerance here.
    shot = spur.simulate(2500.0, cycles=1, backlash=False, steady_state="shooting", output_step_deg=2.0, jit=False)
    assert shot.steady_state_method == "shooting" and shot.shooting["converged"]
    assert shot.shooting["iterations"] <= 5 and shot.shooting["relative_residual"] < 1e-4
    assert shot.shooting["neutral_directions"] == 1                 # the viscous damper ring's angle
    limit = spur.simulate(2500.0, cycles=1, backlash=False, run_in_cycles=6, output_step_deg=2.0, jit=False)
    f, f_ref = shot.mesh_force_N.to_numpy(), limit.mesh_force_N.to_numpy()
    assert np.max(np.abs(f - f_ref)) < 3e-3 * np.max(np.abs(f_ref))
