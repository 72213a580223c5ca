"""The torsional model of any train with a generic ``[excitation]`` (gearopt.dynamics.train_model), checked against
results nobody here wrote: the natural frequency of two geared inertias, static equilibrium of the mean mesh force,
the textbook disc inertia and ISO 6336-1's typical mesh stiffness; it runs on renamed gears, on an idler train
(with and without backlash, driven from either end or the middle) and under speed_sweep with the joints' margins."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import gearopt
from gearopt.data import default_data_path
from gearopt.cases import torsional_model
from gearopt.dynamics import TrainModel, speed_sweep, train_model, walk_off_history
from gearopt.errors import GearoptInputError, MissingSectionError

MINIMAL = default_data_path().parent / "minimal_train.toml"
RUN = dict(cycles=1, run_in_cycles=1, steady_state_tol=1e-4, rtol=1e-6, jit=False)
NO_HARMONICS = {"excitation.harmonic_1_amplitude_Nm": 0.0, "excitation.harmonic_2_amplitude_Nm": 0.0}

IDLER = """
schema_version = 1
title = "three-gear idler train A-B-C"

[rack]
module_mm = 3.0
pressure_angle_deg = 20.0
addendum_coefficient = 1.0
dedendum_coefficient = 1.25
root_radius_coefficient = 0.38

[trains.spur]
helix_angle_deg = 0.0
root_mesh = "A-B"
root_gear = "A"
root_profile_shift = 0.2

[gears.A]
teeth = 20
face_width_mm = 20.0
tooth_thickness_upper_allowance_um = -40.0
tooth_thickness_lower_allowance_um = -80.0
material = "20MnCr5"

[gears.B]
teeth = 31
face_width_mm = 18.0
tooth_thickness_upper_allowance_um = -40.0
tooth_thickness_lower_allowance_um = -80.0
material = "20MnCr5"
inertia_kgm2 = 0.002

[gears.C]
teeth = 40
face_width_mm = 20.0
tooth_thickness_upper_allowance_um = -40.0
tooth_thickness_lower_allowance_um = -80.0
material = "20MnCr5"

[meshes.A-B]
gears = ["A", "B"]
centre_distance_mm = 77.0

[meshes.B-C]
gears = ["B", "C"]
centre_distance_mm = 107.0

[excitation]
gear = "A"
mean_torque_Nm = 80.0
harmonic_orders = [1.0, 0.5]
harmonic_amplitudes_Nm = [10.0, 0.0]
harmonic_phases_deg = [0.0, 0.0]
speed_rpm = 1200.0
"""


@pytest.fixture(scope="module")
def minimal():
    system = gearopt.load_system(MINIMAL)
    return system, train_model(system)


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return gearopt.load_system(path)


# --- (a) natural frequency of two geared inertias -----------------------------------------------------------------

def test_pair_natural_frequency_is_the_two_inertia_result(minimal):
    system, model = minimal
    assert isinstance(model, TrainModel)
    row = model.mesh_table.loc["pinion-wheel"]
    k = row["mean_stiffness_N_per_m"]
    r1, r2 = row["base_radius_1_mm"] * 1e-3, row["base_radius_2_mm"] * 1e-3
    j1, j2 = model.gear_inertia_kgm2("pinion")[0], model.gear_inertia_kgm2("wheel")[0]
    # reduced to the pinion: J2' = J2 / i^2 (i = r2/r1 = z2/z1), torsional mesh stiffness k r1^2
    i = system.gears["wheel"].teeth / system.gears["pinion"].teeth
    f = math.sqrt(k * r1 ** 2 * (1.0 / j1 + i ** 2 / j2)) / (2.0 * math.pi)
    assert r2 / r1 == pytest.approx(i, rel=1e-12)
    freqs = model.natural_frequencies_Hz()
    assert freqs.shape == (1,)
    assert freqs[0] == pytest.approx(f, rel=1e-9)
    assert model.natural_frequencies_Hz(rigid_body=True)[0] == pytest.approx(0.0, abs=1e-3)
    # the inputs themselves: ISO 6336-1's typical c_gamma_alpha ~ 20 N/(mm um) of steel spur gears (15..25 here),
    # and the textbook solid disc rho pi b d^4 / 32 at the reference diameter (the blank has teeth and a bore: 10 %)
    assert 15.0 < k / 1e6 / 20.0 < 25.0
    for gear, j in (("pinion", j1), ("wheel", j2)):
        d = system.gears[gear].teeth * system.rack.module_mm * 1e-3
        disc = 7850.0 * math.pi * system.gears[gear].face_width_mm * 1e-3 * d ** 4 / 32.0
        assert j == pytest.approx(disc, rel=0.1)


# --- (b) static equilibrium of the mean mesh force ----------------------------------------------------------------

@pytest.mark.parametrize("lash", [False, True])
def test_mean_mesh_force_is_mean_torque_over_base_radius(minimal, lash):
    system, model = minimal
    sim = model.simulate(1500.0, backlash=lash, parameters=NO_HARMONICS, **RUN)
    r_b1 = model.mesh_table.loc["pinion-wheel", "base_radius_1_mm"] * 1e-3
    t = system.excitation.mean_torque_Nm
    assert sim.summary().loc["pinion-wheel", "mean_force_N"] == pytest.approx(t / r_b1, rel=1e-6)
    # the train runs at the requested speed (the load balances the mean power)
    assert sim.node_speed_rpm["pinion"].mean() == pytest.approx(1500.0, rel=1e-6)
    assert sim.node_speed_rpm["wheel"].mean() == pytest.approx(-750.0, rel=1e-6)


def test_harmonics_keep_the_mean_and_the_zero_amplitude_runs(minimal):
    system, model = minimal
    sim = model.simulate(1500.0, backlash=False, **RUN)
    r_b1 = model.mesh_table.loc["pinion-wheel", "base_radius_1_mm"] * 1e-3
    f = sim.mesh_force_N["pinion-wheel"]
    assert f.mean() == pytest.approx(system.excitation.mean_torque_Nm / r_b1, rel=1e-4)
    assert f.max() - f.min() > 0.1 * f.mean()  # the harmonics do act
    one_zero = model.simulate(1500.0, backlash=True, parameters={"excitation.harmonic_2_amplitude_Nm": 0.0}, **RUN)
    assert np.all(np.isfinite(one_zero.mesh_force_N.to_numpy()))


# --- (c) any names, any tree --------------------------------------------------------------------------------------

def test_renamed_copy_of_the_minimal_example(tmp_path, minimal):
    _, original = minimal
    text = re.sub(r"\bpinion\b", "sun", MINIMAL.read_text())
    text = re.sub(r"\bwheel\b", "ring", text)
    system = _write(tmp_path, "renamed.toml", text)
    assert set(system.gears) == {"sun", "ring"} and set(system.meshes) == {"sun-ring"}
    model = train_model(system)
    assert model.natural_frequencies_Hz() == pytest.approx(original.natural_frequencies_Hz(), rel=1e-12)
    for lash in (False, True):
        sim = model.simulate(1500.0, backlash=lash, parameters=NO_HARMONICS, **RUN)
        assert list(sim.mesh_force_N.columns) == ["sun-ring"]
        r_b1 = model.mesh_table.loc["sun-ring", "base_radius_1_mm"] * 1e-3
        assert sim.mesh_force_N["sun-ring"].mean() == pytest.approx(120.0 / r_b1, rel=1e-6)


@pytest.mark.parametrize("lash", [False, True])
def test_idler_train_a_drives_b_drives_c(tmp_path, lash):
    system = _write(tmp_path, "idler.toml", IDLER)
    model = train_model(system)
    assert dict(model.gear_table["role"]) == {"A": "drive", "B": "idler", "C": "load"}
    assert model.network.cycle_deg == 720.0  # the half order repeats every two revolutions of A
    assert model.gear_inertia_kgm2("B") == (0.002, "gears.B.inertia_kgm2")
    assert any("mesh damping ratio 0.08" in n for n in model.notes)  # no [dynamics]: the stated default
    # the load on C takes the whole mean power: T_C = T_A z_C / z_A
    assert model.gear_table.loc["C", "load_torque_Nm"] == pytest.approx(80.0 * 40 / 20)
    assert len(model.natural_frequencies_Hz()) == 2
    sim = model.simulate(backlash=lash, **RUN)
    r_ba = model.mesh_table.loc["A-B", "base_radius_1_mm"] * 1e-3
    mean = sim.summary()["mean_force_N"]
    # the idler passes the force on unchanged (its own equilibrium: F_AB r_bB = F_BC r_bB)
    assert mean["A-B"] == pytest.approx(80.0 / r_ba, rel=1e-4)
    assert mean["B-C"] == pytest.approx(80.0 / r_ba, rel=1e-4)
    assert sim.node_speed_rpm["C"].mean() == pytest.approx(1200.0 * 20 / 40, rel=1e-6)


def test_idler_train_driven_from_the_middle_and_against_the_mesh_order(tmp_path):
    # driven from B: A and C are both loads (equal shares: no design torques), the power flows B -> A against the
    # data's order of A-B (its back flanks carry the load: a negative mesh force)
    system = _write(tmp_path, "middle.toml", IDLER.replace('[excitation]\ngear = "A"', '[excitation]\ngear = "B"'))
    model = train_model(system)
    assert dict(model.gear_table["role"]) == {"B": "drive", "A": "load", "C": "load"}
    sim = model.simulate(1000.0, backlash=True, parameters={"excitation.harmonic_1_amplitude_Nm": 0.0}, **RUN)
    r_bb = model.mesh_table.loc["B-C", "base_radius_1_mm"] * 1e-3
    mean = sim.summary()["mean_force_N"]
    assert mean["A-B"] == pytest.approx(-0.5 * 80.0 / r_bb, rel=1e-4)
    assert mean["B-C"] == pytest.approx(0.5 * 80.0 / r_bb, rel=1e-4)
    # driven from C: both meshes run on their back flanks
    system = _write(tmp_path, "reverse.toml", IDLER.replace('[excitation]\ngear = "A"', '[excitation]\ngear = "C"'))
    model = train_model(system)
    assert dict(model.gear_table["role"]) == {"C": "drive", "B": "idler", "A": "load"}
    sim = model.simulate(1000.0, backlash=False, parameters={"excitation.harmonic_1_amplitude_Nm": 0.0}, **RUN)
    r_bc = model.mesh_table.loc["B-C", "base_radius_2_mm"] * 1e-3
    assert sim.summary()["mean_force_N"].to_numpy() == pytest.approx([-80.0 / r_bc] * 2, rel=1e-4)


def test_helical_train_has_axial_forces(minimal):
    system, _ = minimal
    model = train_model(system, "helical")
    sim = model.simulate(1500.0, backlash=False, parameters=NO_HARMONICS, **RUN)
    beta_b = math.radians(model.mesh_table.loc["pinion-wheel", "base_helix_angle_deg"])
    f = sim.mesh_force_N["pinion-wheel"].mean()
    assert sim.axial_force_N["pinion-wheel"].mean() == pytest.approx(f * math.tan(beta_b), rel=1e-9)


# --- (d) speed sweep with the joints' margins ---------------------------------------------------------------------

def test_speed_sweep_gives_joint_rows(minimal):
    system, model = minimal
    sweep = speed_sweep(model, [1000.0, 1500.0], backlash=(False,), joints=tuple(system.joints), cycles=1,
                        run_in_cycles=1, rtol=1e-5, jit=False)
    joints = sweep[sweep["element_type"] == "joint"]
    assert sorted(joints["element"].unique()) == ["joint:pinion", "joint:wheel"]
    assert len(joints) == 4
    for col in ("min_torque_margin", "min_axial_margin", "max_slip_utilisation", "peak_torque_Nm"):
        assert joints[col].notna().all()
    assert (joints["min_torque_margin"] > 0).all()
    # spur: no thrust on the joints
    assert (joints["peak_axial_force_N"] == 0.0).all()
    # the pinion's joint carries the driving torque: its peak is the torque's (mean + both harmonics)
    exc = system.excitation
    theta = np.linspace(0.0, 2.0 * np.pi, 100001)
    peak = np.max(exc.mean_torque_Nm + sum(a * np.cos(n * theta + math.radians(p)) for n, a, p in zip(
        exc.harmonic_orders, exc.harmonic_amplitudes_Nm, exc.harmonic_phases_deg)))
    pinion = joints[joints["element"] == "joint:pinion"]
    assert pinion["peak_torque_Nm"].to_numpy() == pytest.approx([peak] * 2, rel=1e-3)
    # the default joints of the sweep are the system's
    default = speed_sweep(model, [1500.0], backlash=(False,), cycles=1, run_in_cycles=1, rtol=1e-5, jit=False)
    assert sorted(default.loc[default["element_type"] == "joint", "element"]) == ["joint:pinion", "joint:wheel"]


def test_walk_off_history_joint_torques_are_the_drive_and_the_load(minimal):
    system, model = minimal
    sim = model.simulate(1500.0, backlash=False, **RUN)
    drive = walk_off_history(model, sim, "pinion")
    assert drive["joint_torque_method"] == "mesh_sum"
    assert drive["gear_inertia_kgm2"] == model.gear_inertia_kgm2("pinion")[0]
    # the gear's equilibrium: its shaft delivers the driving torque (negative: the shaft drives the gear)
    t = np.asarray(drive["joint_torque_Nm"])
    theta = np.radians(sim.crank_angle_deg + np.degrees(sim.angle_offset_rad))
    exc = system.excitation
    expected = exc.mean_torque_Nm + sum(a * np.cos(n * theta + math.radians(p)) for n, a, p in zip(
        exc.harmonic_orders, exc.harmonic_amplitudes_Nm, exc.harmonic_phases_deg))
    assert t == pytest.approx(-expected, abs=1e-3 * exc.mean_torque_Nm)
    load = walk_off_history(model, sim, "wheel")
    assert np.mean(load["joint_torque_Nm"]) == pytest.approx(2.0 * exc.mean_torque_Nm, rel=1e-4)


# --- bad input ----------------------------------------------------------------------------------------------------

def test_missing_excitation_names_the_file_and_section(tmp_path):
    text = MINIMAL.read_text()
    start = text.index("[excitation]")
    text = text[:start] + text[text.index("[dynamics]"):]
    system = _write(tmp_path, "no_excitation.toml", text)
    with pytest.raises(MissingSectionError, match=r"no_excitation\.toml.*\[excitation\]"):
        train_model(system)
    with pytest.raises(MissingSectionError, match=r"\[excitation\]"):
        torsional_model(system)


def test_speeds_must_be_positive(minimal):
    system, model = minimal
    for speed in (0.0, -100.0):
        with pytest.raises(GearoptInputError, match="speed_rpm"):
            model.simulate(speed, cycles=1, jit=False)
        with pytest.raises(GearoptInputError, match="speed_rpm"):
            train_model(system, speed_rpm=speed)
    with pytest.raises(GearoptInputError, match="kind"):
        train_model(system, "bevel")


def test_zero_harmonic_amplitudes_in_the_data(tmp_path):
    text = MINIMAL.read_text().replace("harmonic_amplitudes_Nm = [20.0, 10.0]", "harmonic_amplitudes_Nm = [0.0, 0.0]")
    model = train_model(_write(tmp_path, "zero.toml", text))
    sim = model.simulate(1500.0, backlash=True, **RUN)
    r_b1 = model.mesh_table.loc["pinion-wheel", "base_radius_1_mm"] * 1e-3
    assert sim.mesh_force_N["pinion-wheel"].mean() == pytest.approx(120.0 / r_b1, rel=1e-6)


def test_torsional_model_picks_the_engine_model_for_engine_data():
    from gearopt.cases.timing_train import TimingModel
    model = torsional_model(gearopt.load_system())
    assert isinstance(model, TimingModel)


def test_actual_angle_excitation_rectifies_into_a_lower_mean_speed(minimal):
    system, _ = minimal
    model = train_model(system, excitation_angle="actual")
    sim = model.simulate(1500.0, cycles=1, run_in_cycles=2, backlash=False, rtol=1e-5, jit=False)
    # the light pinion dwells where the harmonics brake it: a mean braking torque, a lower mean speed (docstring)
    assert 1400.0 < sim.node_speed_rpm["pinion"].mean() < 1499.0
    with pytest.raises(GearoptInputError, match="excitation_angle"):
        train_model(system, excitation_angle="exact")


def test_zero_mean_torque_keeps_the_speed(tmp_path):
    text = MINIMAL.read_text().replace("mean_torque_Nm = 120.0", "mean_torque_Nm = 0.0")
    model = train_model(_write(tmp_path, "zero_mean.toml", text))
    assert any("zero mean torque" in n for n in model.notes)
    assert model.gear_table.loc["wheel", "load_slope_Nms_per_rad"] > 0.0
    sim = model.simulate(1500.0, backlash=False, **RUN)
    assert sim.node_speed_rpm["pinion"].mean() == pytest.approx(1500.0, rel=1e-4)
    assert abs(sim.mesh_force_N["pinion-wheel"].mean()) < 1e-3 * sim.mesh_force_N["pinion-wheel"].abs().max()
