"""Walk-off envelope helpers (gearopt.dynamics.walk_off_envelope) and the walk-off Monte Carlo
(gearopt.studies.failure): thrust signs, fit capacities, probability against a closed form, bad input."""

import math

import numpy as np
import pandas as pd
import pytest
from scipy.stats import norm

from gearopt.data import load_system
from gearopt.dynamics.walk_off_envelope import (
    damper_coefficient,
    fit_capacity_N,
    fit_cases,
    thrust_signs,
)
from gearopt.errors import GearoptInputError
from gearopt.joints import walk_off
from gearopt.studies.failure import walk_off_probability

DATA = load_system()


def test_thrust_signs_follow_walk_off_and_vanish_for_spur():
    helical, spur = DATA.train("helical"), DATA.train("spur")
    signs = dict(thrust_signs(helical, "cam"))
    assert set(signs) == {"crank-cam", "cam-ac", "cam-fp"}
    for mesh, sign in signs.items():
        assert sign == math.copysign(1.0, walk_off(helical, {mesh: 250.0}).axial_force_N["cam"])
    assert all(s == 0.0 for _, s in thrust_signs(spur, "cam"))


def test_fit_capacity_matches_the_data_files_calculation():
    # [joints.cam] axial_friction_force_N = 40868 N: mu p pi d l with the Lame pressure at the mean interference
    assert fit_capacity_N(DATA, "cam") == pytest.approx(40868.0, rel=1e-3)
    cases = fit_cases(DATA, "cam", 3000.0)
    assert cases["weakest"] < cases["nominal"] < cases["strongest"]
    with pytest.raises(GearoptInputError, match="friction_coefficient"):
        fit_capacity_N(DATA, "cam", friction_coefficient=-0.1)
    with pytest.raises(GearoptInputError, match="state"):
        damper_coefficient(DATA, "leaking")
    with pytest.raises(GearoptInputError, match="damper coefficient"):
        damper_coefficient(DATA, -5.0)
    assert damper_coefficient(DATA, "degraded") == pytest.approx(0.1 * damper_coefficient(DATA, "nominal"))


def synthetic_envelope(creep_um_per_cycle=0.01, speed=3300.0):
    rows = [{"joint": "cam", "speed_rpm": speed, "damper_state": s, "capacity_N": c,
             "axial_creep_um_per_cycle": creep_um_per_cycle} for s in ("nominal", "degraded", "seized")
            for c in (1e3, 1e6)]
    return pd.DataFrame(rows)


def test_probability_matches_log_normal_closed_form():
    # creep c at 3300 rpm whatever the fit: distance = c x 1650 x 60 x hours; with hours log-normal (median m,
    # sigma s) the walk-off probability is 1 - Phi((ln(h*) - ln m)/s), h* = D / (c x 1650 x 60 x 1e-3)
    c, dist, m, s = 0.01, 1.0, 1.0, 1.5
    res = walk_off_probability(synthetic_envelope(c), DATA, "cam", samples=200_000, seed=1, distance_mm=dist,
                               exposure_hours={"motoring_overspeed": (m, s)})
    h_star = dist / (c * 1650.0 * 60.0 * 1e-3)
    expected = 1.0 - norm.cdf((math.log(h_star) - math.log(m)) / s)
    assert res["walk_off_probability"] == pytest.approx(expected, abs=4e-3)
    assert next(iter(res["drivers"])) == "hours_motoring_overspeed"


def test_no_creep_no_walk_off_and_bad_input():
    res = walk_off_probability(synthetic_envelope(0.0), DATA, "cam", samples=1000)
    assert res["walk_off_probability"] == 0.0
    assert res["p99_distance_mm"] == 0.0
    with pytest.raises(GearoptInputError, match="distance_mm"):
        walk_off_probability(synthetic_envelope(), DATA, "cam", distance_mm=0.0)
    with pytest.raises(GearoptInputError, match="sum to 1"):
        walk_off_probability(synthetic_envelope(), DATA, "cam", damper_probabilities={"nominal": 0.5})
    with pytest.raises(GearoptInputError, match="joint"):
        walk_off_probability(synthetic_envelope(), DATA, "crank")
    assert np.isfinite(res["median_distance_mm"])


def test_joint_demand_on_the_default_model_matches_walk_off_and_the_shaft_torque():
    # independent code paths: the element's thrust against gearopt.joints.walk_off on the simulated mesh torques,
    # and its joint torque (mesh torques - J alpha) against the network's own cam-shaft torque output
    from gearopt.cases.timing_train import default_timing_model
    from gearopt.dynamics.joint_friction import JointSimulator
    from gearopt.dynamics.walk_off_envelope import model_joints
    model = default_timing_model("helical")
    speed = 1500.0
    p = model.parameters_at(speed)
    cam = model_joints(model, "cam")
    res = JointSimulator(model.network, cam, lash=False, output_step_deg=5.0).run(speed, 1, parameters=p,
                                                                                  run_in_cycles=0)
    sim = model.simulate(speed, cycles=1, backlash=False, run_in_cycles=0, output_step_deg=5.0, jit=False)
    torques = {m: sim.mesh_force_N[m].to_numpy() * sim.mesh_base_radii_mm[m][0] * 1e-3
               for m in sim.mesh_force_N.columns}
    axial = walk_off(model.train, torques).axial_force_N["cam"]
    thrust = res.frames["thrust_N"]["cam#0"].to_numpy()
    assert np.max(np.abs(thrust - axial)) < 1e-3 * np.max(np.abs(axial))
    shaft = sim.shaft_torque_Nm["cam-cam_station_1"].to_numpy()  # cam turns against the crank: own sense = -abs
    joint_torque = res.frames["joint_torque_Nm"]["cam#0"].to_numpy()
    assert np.max(np.abs(-joint_torque - shaft)) < 1e-3 * np.max(np.abs(shaft))


def test_regularisation_converges_at_the_envelopes_overstress():
    # the default helical train at 3300 rpm with a seized damper, crank joint at its weakest fit (utilisation ~40:
    # the highest overstress of the envelope, thrust above the capacity) and its nominal fit, V = 10 (the data's)
    # and 100 m/s on one trajectory: the slip path and the gear's axial travel change little with V. The lash model
    # is chaotic, so the trajectory depends on round-off; on five trajectories measured (both integrations, rtol
    # 1e-6/1e-7, two output grids) the slip path per cycle moved 0.1-0.2 % with V, on one with a harder impact 8 %
    import dataclasses

    from gearopt.cases.timing_train import default_timing_model
    from gearopt.dynamics.joint_friction import joint_simulator
    from gearopt.dynamics.walk_off_envelope import (
        DAMPER_PARAMETER,
        gear_mass_kg,
        model_joints,
    )

    model = default_timing_model("helical", system=DATA)
    base = model_joints(model, "crank", 2)
    assert 2.0 < base[0].gear_mass_kg == gear_mass_kg(model, "crank") < 3.0
    joints = base + [dataclasses.replace(j, name=f"fast#{i}", slip_speed_m_s=100.0) for i, j in enumerate(base)]
    sim = joint_simulator(model.network, joints, jit=True, min_speed_rpm=3300.0)
    cases = fit_cases(DATA, "crank", 3300.0)
    p = model.parameters_at(3300.0)
    p[DAMPER_PARAMETER] = damper_coefficient(DATA, "seized")
    for name in ("crank", "fast"):
        p[f"{name}#0.capacity_N"], p[f"{name}#1.capacity_N"] = cases["weakest"], cases["nominal"]
    s = sim.run(3300.0, 2, parameters=p, run_in_cycles=1).summary
    for i in (0, 1):
        slow, fast = s.loc[f"crank#{i}"], s.loc[f"fast#{i}"]
        assert slow["slip_um_per_cycle"] == pytest.approx(fast["slip_um_per_cycle"], rel=0.1)
        assert abs(slow["axial_creep_um_per_cycle"] - fast["axial_creep_um_per_cycle"]) <= \
            0.35 * max(abs(fast["axial_creep_um_per_cycle"]), 1.0)
    # creep is bounded by what the thrust can do against the capacity and the gear's inertia in one cycle
    cycle_s = 120.0 / 3300.0
    f_max = s.loc["crank#0", "max_off_nose_thrust_N"]
    bound_um = 0.5 * (f_max - cases["weakest"]) / base[0].gear_mass_kg * cycle_s ** 2 * 1e6
    assert abs(s.loc["crank#0", "max_cycle_axial_creep_um"]) < bound_um


@pytest.mark.parametrize("joint", ["cam", "crank"])
def test_monte_carlo_capacity_surrogate_matches_the_press_fit_model(joint):
    # the vectorised capacity of the Monte Carlo samples against the press-fit (Lame, DIN 7190) calculation
    from gearopt.studies.failure import sampled_capacity_N
    rng = np.random.default_rng(3)
    delta, smooth, mu = rng.uniform(40.0, 120.0, 8), rng.uniform(4.0, 9.0, 8), rng.uniform(0.08, 0.16, 8)
    for speed in (2500.0, 3300.0):
        fast = sampled_capacity_N(DATA, joint, speed, delta, smooth, mu)
        exact = [fit_capacity_N(DATA, joint, interference_um=d, friction_coefficient=m, smoothing_loss_um=s,
                                speed_rpm=speed) for d, s, m in zip(delta, smooth, mu)]
        assert fast == pytest.approx(exact, rel=1e-6)


def test_envelope_rows_per_level_and_no_simulator_left_behind():
    """One (speed, damper) point of the cam joint: a row per capacity level (the below-tolerance fractions first,
    then the toleranced levels, weakest to strongest, capacities rising), fit cases named; the envelope's simulator
    is dropped from the worker registry when it returns (repeated calls do not accumulate simulators)."""
    from gearopt.cases.timing_train import default_timing_model
    from gearopt.dynamics import walk_off_envelope as env

    model = default_timing_model("spur", system=DATA)
    rows = env.joint_envelope(model, joints=("cam",), speeds_rpm=[2500.0], damper_states=["nominal"], levels=3,
                              cycles=1, run_in_cycles=0)
    assert len(rows) == 3 + len(env.BELOW_TOLERANCE_FRACTIONS) and set(rows["joint"]) == {"cam"}
    assert (np.diff(rows.sort_values("level")["capacity_N"].to_numpy()) > 0).all()
    assert {"weakest", "nominal", "strongest"} <= set(rows["fit_case"])
    assert (rows["axial_creep_um_per_cycle"].abs() < 1e-9).all()          # spur: no thrust, no creep
    assert env._REGISTRY == {}
