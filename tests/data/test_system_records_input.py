"""Library functions take a System, never the raw dict of a data file: ``gearopt.data.system_of`` is the check of
every one of them (a dict, None or another type raises naming the function, the type and the conversion), and a
joint or material the file lacks names the file and the key path."""

from __future__ import annotations

import copy
import re

import numpy as np
import pytest

import gearopt as go
from gearopt.blank import blank_from_data
from gearopt.cases.timing_train import (accessory_load_torques_Nm, codesign_study, default_timing_model,
                                        failure_reproduction, quasi_static_load_case, timing_model)
from gearopt.data import system_from_data, system_of
from gearopt.design import DesignVariable, Objective, Scene
from gearopt.design.blank_sizing import BlankSpec, web_demand_from_loads
from gearopt.design.joint_sizing import JointDemand, PressFitSpec, TaperFitSpec, size_joint
from gearopt.design.scene_file import scene_from_data
from gearopt.design.tooth_counts import enumerate_tooth_counts, reference_speed_ratios
from gearopt.dynamics import train_model
from gearopt.dynamics.walk_off_envelope import (capacity_levels_N, damper_coefficient, envelope_speeds_rpm,
                                                fit_capacity_N, fit_cases)
from gearopt.engine import EngineExcitation
from gearopt.errors import DataFileError, GearoptInputError
from gearopt.joints import joint_capacities, joint_capacity
from gearopt.report.joint_tables import design_load_torques_Nm, joint_table
from gearopt.studies import relief_scene_from_data
from gearopt.studies.calibration import calibrated_system, field_record
from gearopt.studies.failure import sample_inputs, sampled_capacity_N

SYSTEM = go.load_system()
DATA = SYSTEM.data                                  # the validated dict of the same file
TRAIN = go.load_default_train("spur")

# the name each function gives in its message -> a call of it with data ``d``
DICT_CALLS = {
    "joint_capacity": lambda d: joint_capacity(d, "cam"),
    "joint_capacities": lambda d: joint_capacities(d),
    "blank_from_data": lambda d: blank_from_data(d, TRAIN, "cam"),
    "fit_capacity_N": lambda d: fit_capacity_N(d, "cam"),
    "fit_cases": lambda d: fit_cases(d, "cam", 2500.0),
    "capacity_levels_N": lambda d: capacity_levels_N(d, "cam", 2500.0, 3),
    "damper_coefficient": lambda d: damper_coefficient(d, "seized"),
    "envelope_speeds_rpm": lambda d: envelope_speeds_rpm(d),
    "sample_inputs": lambda d: sample_inputs(d, "cam", 10),
    "sampled_capacity_N": lambda d: sampled_capacity_N(d, "cam", 2500.0, 50.0, 0.0, 0.1),
    "PressFitSpec.from_data": lambda d: PressFitSpec.from_data(d, "cam"),
    "TaperFitSpec.from_data": lambda d: TaperFitSpec.from_data(d, "ac"),
    "size_joint": lambda d: size_joint(d, "cam", JointDemand(100.0)),
    "BlankSpec.from_data": lambda d: BlankSpec.from_data(d, TRAIN, "cam"),
    "web_demand_from_loads": lambda d: web_demand_from_loads(d, TRAIN, "cam"),
    "accessory_load_torques_Nm": lambda d: accessory_load_torques_Nm(d),
    "quasi_static_load_case": lambda d: quasi_static_load_case(d, "spur"),
    "design_load_torques_Nm": lambda d: design_load_torques_Nm(d),
    "joint_table": lambda d: joint_table(d, "spur", "design"),
    "EngineExcitation.from_data": lambda d: EngineExcitation.from_data(d),
    "default_timing_model": lambda d: default_timing_model("spur", system=d),
    "timing_model": lambda d: timing_model(d),
    "train_model": lambda d: train_model(d),
    "codesign_study": lambda d: codesign_study(d),
    "failure_reproduction": lambda d: failure_reproduction(d),
    "field_record": lambda d: field_record(d),
    "calibrated_system": lambda d: calibrated_system(d, {}),
    "relief_scene_from_data": lambda d: relief_scene_from_data(d, TRAIN, "crank-cam"),
    "reference_speed_ratios": lambda d: reference_speed_ratios(TRAIN, "data", d),
    "enumerate_tooth_counts": lambda d: enumerate_tooth_counts(TRAIN, reference="data", system=d, span=1),
    "Scene(data=...)": lambda d: Scene("s", train=TRAIN, data=d, variables=[DesignVariable("profile_shift_1",
                                       "crank-cam")], objectives=[Objective("min_tip_thickness_mm", "crank-cam",
                                                                            sense="max")]).build(),
    "scene_from_data(train_data=...)": lambda d: scene_from_data({"scenes": {"s": {"train": "spur"}}}, "s",
                                                                 train_data=d),
}
#: the name a function's message gives where it differs from the function's (the check it delegates to)
NAMED = {"enumerate_tooth_counts": "reference_speed_ratios(reference='data')",
         "reference_speed_ratios": "reference_speed_ratios(reference='data')"}


def test_system_of_takes_a_system_only():
    assert system_of(SYSTEM) is SYSTEM
    with pytest.raises(GearoptInputError, match=r"joint_capacity: data is required \(got None\)"):
        system_of(None, "joint_capacity")
    with pytest.raises(GearoptInputError, match=r"joint_capacity: got a float; it must be a System"):
        system_of(3.0, "joint_capacity")
    with pytest.raises(GearoptInputError) as err:
        system_of(DATA, "joint_capacity")
    assert str(err.value) == ("joint_capacity: got a dict (the raw data of a file); library functions take a System: "
                              "pass gearopt.load_system(path), or convert a validated dict with "
                              "gearopt.data.system_from_data(d)")


@pytest.mark.parametrize("name", sorted(DICT_CALLS))
def test_a_raw_dict_names_the_function_and_how_to_convert_it(name):
    with pytest.raises(GearoptInputError, match=re.escape(NAMED.get(name, name)) + r": got a dict .*"
                                                r"gearopt\.load_system\(path\).*gearopt\.data\.system_from_data\(d\)"):
        DICT_CALLS[name](DATA)


def test_the_converted_dict_gives_the_systems_numbers():
    converted = system_from_data(DATA)
    rows = {k: c.as_row() for k, c in joint_capacities(SYSTEM, speed_rpm=2500.0).items()}
    assert rows == {k: c.as_row() for k, c in joint_capacities(converted, speed_rpm=2500.0).items()}
    assert list(rows) == list(SYSTEM.joints)
    assert fit_cases(SYSTEM, "crank", 2500.0) == fit_cases(converted, "crank", 2500.0)
    np.testing.assert_array_equal(capacity_levels_N(SYSTEM, "cam", 2500.0, 5),
                                  capacity_levels_N(converted, "cam", 2500.0, 5))
    assert accessory_load_torques_Nm(SYSTEM, "mean") == accessory_load_torques_Nm(converted, "mean")


def test_missing_joint_and_material_name_file_and_key_path():
    with pytest.raises(DataFileError, match=r"default_train\.toml: joints\.nope is missing: joint_capacity"):
        joint_capacity(SYSTEM, "nope")
    with pytest.raises(DataFileError, match=r"joints\.nope is missing"):
        fit_capacity_N(SYSTEM, "nope")
    data = SYSTEM.data                                  # a deep copy
    data["materials"]["Unobtainium"] = copy.deepcopy(data["materials"][data["joints"]["cam"]["hub_material"]])
    data["joints"]["cam"]["hub_material"] = "Unobtainium"
    system = system_from_data(data, source="renamed.toml")
    assert joint_capacity(system, "cam").as_row() == joint_capacity(SYSTEM, "cam").as_row()
    del data["materials"]["Unobtainium"]
    system = system_from_data(data, source="renamed.toml")
    with pytest.raises(DataFileError, match=r"renamed\.toml: materials\.Unobtainium is missing "
                                            r"\(joints\.cam\.hub_material = 'Unobtainium'\): joint_capacity"):
        joint_capacity(system, "cam")
    with pytest.raises(DataFileError, match=r"materials\.Unobtainium is missing \(joints\.cam\.hub_material"):
        PressFitSpec.from_data(system, "cam")
    with pytest.raises(DataFileError, match=r"materials\.Unobtainium is missing \(joints\.cam\.hub_material"):
        fit_capacity_N(system, "cam")


def test_report_tables_take_the_load_case_of_a_case_package():
    with pytest.raises(GearoptInputError, match="torques_Nm is required .*quasi_static_load_case"):
        joint_table(SYSTEM, "spur")
    torques, case = quasi_static_load_case(SYSTEM, "helical")
    assert joint_table(SYSTEM, "helical", (torques, case)).attrs["load_case"] == case
    assert joint_table(SYSTEM, "helical", torques).equals(joint_table(SYSTEM, "helical", (torques, case)))
