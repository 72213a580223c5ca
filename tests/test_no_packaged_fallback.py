"""The library never reads the packaged data behind the caller's back: every engine model and report table takes its
data (the System of a file) as a required argument, no data is an error naming the argument, a raw dict is an error
naming the conversion, data without the section it needs raise MissingSectionError naming the file and section, and
with explicit data no function touches the packaged file."""

from __future__ import annotations

import inspect
import re

import pytest

import gearopt as go
from gearopt import data as data_pkg
from gearopt.cases.timing_train import quasi_static_load_case
from gearopt.data import load_system, require_section, system_from_data
from gearopt.design.tooth_counts import enumerate_tooth_counts, reference_speed_ratios
from gearopt.engine import (AccessoryTorque, CylinderPressure, EngineExcitation, air_compressor_torque_Nm,
                            camshaft_torque_Nm, fuel_pump_torque_Nm, ideal_compressor_cycle, lube_pump_torque_Nm,
                            peak_pressure_bar)
from gearopt.engine.pressure import double_wiebe_cycle
from gearopt.errors import GearoptInputError, MissingSectionError
from gearopt.report.joint_tables import blank_table, joint_table, web_table

SYSTEM = load_system()
DATA = SYSTEM.data

# name -> (function, call with data d); the data-first functions whose `system` has no default
ENGINE_CALLS = {
    "EngineExcitation.from_data": (EngineExcitation.from_data, lambda d: EngineExcitation.from_data(d, speed_rpm=2000.0)),
    "AccessoryTorque.camshaft": (AccessoryTorque.camshaft, lambda d: AccessoryTorque.camshaft(d)),
    "AccessoryTorque.fuel_pump": (AccessoryTorque.fuel_pump, lambda d: AccessoryTorque.fuel_pump(d)),
    "AccessoryTorque.air_compressor": (AccessoryTorque.air_compressor, lambda d: AccessoryTorque.air_compressor(d)),
    "AccessoryTorque.lube_pump": (AccessoryTorque.lube_pump, lambda d: AccessoryTorque.lube_pump(d)),
    "ideal_compressor_cycle": (ideal_compressor_cycle, lambda d: ideal_compressor_cycle(d)),
    "camshaft_torque_Nm": (camshaft_torque_Nm, lambda d: camshaft_torque_Nm(0.3, d)),
    "fuel_pump_torque_Nm": (fuel_pump_torque_Nm, lambda d: fuel_pump_torque_Nm(0.3, d)),
    "air_compressor_torque_Nm": (air_compressor_torque_Nm, lambda d: air_compressor_torque_Nm(0.3, d)),
    "lube_pump_torque_Nm": (lube_pump_torque_Nm, lambda d: lube_pump_torque_Nm(0.3, d)),
    "CylinderPressure.from_data": (CylinderPressure.from_data, lambda d: CylinderPressure.from_data(d, harmonics=16)),
    "peak_pressure_bar": (peak_pressure_bar, lambda d: peak_pressure_bar(2000.0, 1.0, d)),
}
REPORT_CALLS = {
    "joint_table": (joint_table, lambda d: joint_table(d, "spur", "design")),
    "blank_table": (blank_table, lambda d: blank_table(d, "spur")),
    "web_table": (web_table, lambda d: web_table(d, "helical", "design")),
}
ALL_CALLS = {**ENGINE_CALLS, **REPORT_CALLS}


@pytest.mark.parametrize("name", sorted(ALL_CALLS))
def test_signature_requires_data(name):
    fun, _ = ALL_CALLS[name]
    param = inspect.signature(fun).parameters["system"]
    assert param.default is inspect.Parameter.empty, f"{name}: system must be required"


@pytest.mark.parametrize("name", sorted(ALL_CALLS))
def test_data_none_names_the_argument(name):
    _, call = ALL_CALLS[name]
    with pytest.raises(GearoptInputError, match=re.escape(name) + r": data is required .*gearopt\.load_system"):
        call(None)


@pytest.mark.parametrize("name", sorted(ENGINE_CALLS))
def test_missing_engine_names_file_and_section(name):
    _, call = ENGINE_CALLS[name]
    no_engine = {k: v for k, v in DATA.items() if k != "engine"}
    system = system_from_data(no_engine, source="no_engine.toml")
    with pytest.raises(MissingSectionError, match=r"no_engine\.toml: \[engine\] is missing: " + re.escape(name)):
        call(system)


def test_missing_joints_and_engine_of_the_report_tables():
    no_joints = system_from_data({k: v for k, v in DATA.items() if k != "joints"}, source="no_joints.toml")
    with pytest.raises(MissingSectionError, match=r"no_joints\.toml: \[joints\] is missing: joint_table"):
        joint_table(no_joints, "spur")
    no_engine = system_from_data({k: v for k, v in DATA.items() if k != "engine"})
    with pytest.raises(MissingSectionError, match=r"\[engine\] is missing: the quasi-static accessory load case"):
        quasi_static_load_case(no_engine, "spur")   # the timing case's accessory peaks come from [engine]


def test_double_wiebe_without_data_needs_every_argument():
    with pytest.raises(GearoptInputError, match="premixed_fraction not given and no data given"):
        double_wiebe_cycle(start_of_combustion_deg_atdc=-5.0)
    # every argument given: no data needed, the same cycle as the data's
    args = {k: v for k, v in DATA["engine"]["combustion"].items() if not k.endswith("_source")}
    e = DATA["engine"]
    full = dict(args, bore_mm=e["bore_mm"], stroke_mm=e["stroke_mm"], rod_length_mm=e["connecting_rod_length_mm"],
                compression_ratio=e["compression_ratio"], samples=1024)
    assert double_wiebe_cycle(**full)["peak_bar"] == pytest.approx(
        double_wiebe_cycle(system=SYSTEM, samples=1024)["peak_bar"], rel=1e-12)


def test_reference_speed_ratios_need_data_for_data_references():
    train = go.load_default_train("spur")
    for ref in ("data", "helical_original"):
        with pytest.raises(GearoptInputError, match=rf"reference='{ref}' reads the data file: pass system="):
            reference_speed_ratios(train, ref)
        with pytest.raises(GearoptInputError, match="pass system="):
            enumerate_tooth_counts(train, reference=ref, span=1, precheck=False)
    assert reference_speed_ratios(train, "teeth")["cam"] == 0.5          # "teeth" needs none
    assert reference_speed_ratios(train, "helical_original", SYSTEM)["lpi"] == pytest.approx(37 / 24, rel=1e-6)


@pytest.mark.parametrize("name", sorted(ALL_CALLS))
def test_a_raw_dict_names_the_function_and_the_conversion(name):
    _, call = ALL_CALLS[name]
    with pytest.raises(GearoptInputError, match=re.escape(name) + r": got a dict .*gearopt\.load_system\(path\).*"
                                                 r"gearopt\.data\.system_from_data\(d\)"):
        call(DATA)


def test_data_access_helpers():
    assert require_section(SYSTEM, "lubrication")["oil_temperature_C"] == 100.0
    with pytest.raises(MissingSectionError, match=r"<data>: \[excitation\] is missing: my study"):
        require_section(system_from_data(DATA), "excitation", "my study")
    with pytest.raises(GearoptInputError, match="my study: got a dict"):
        require_section(DATA, "excitation", "my study")


def test_explicit_data_never_touches_the_packaged_file(monkeypatch):
    # with the data given, no library function may locate (let alone read) the packaged file
    def forbidden(*_, **__):
        raise AssertionError("the library read the packaged data behind the caller's back")

    monkeypatch.setattr(data_pkg, "default_data_path", forbidden)
    monkeypatch.setattr(data_pkg, "load_default_data", forbidden)
    monkeypatch.setattr(data_pkg, "load_default_train", forbidden)
    for name, (_, call) in ALL_CALLS.items():
        call(SYSTEM)
    train = data_pkg.train_from_data(DATA, "spur")
    reference_speed_ratios(train, "data", SYSTEM)
    # the rating layer's defaults are library constants, not reads of the file
    from gearopt.rating import default_lubricant, flash_temperature_pair_K
    assert default_lubricant().oil_temperature_C == 100.0
    pair = train.pairs["crank-cam"]
    flash_temperature_pair_K(pair, 200.0, 2000.0, 0.5 * float(pair.geometry()["centre_distance_mm"]) * 0.2,
                             parts=True)
