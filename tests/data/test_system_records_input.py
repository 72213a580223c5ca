"""Library functions take a System (the validated dict still converts, once, through gearopt.data.system_of): the
same numbers from either, and a joint or material the file lacks names the file and the key path."""

from __future__ import annotations

import copy

import numpy as np
import pytest

import gearopt as go
from gearopt.blank import blank_from_data
from gearopt.cases.timing_train import accessory_load_torques_Nm, quasi_static_load_case
from gearopt.data import data_of, system_from_data, system_of
from gearopt.design.blank_sizing import BlankSpec, web_demand_from_loads
from gearopt.design.joint_sizing import PressFitSpec, TaperFitSpec
from gearopt.dynamics.walk_off_envelope import (capacity_levels_N, damper_coefficient, envelope_speeds_rpm,
                                                fit_capacity_N, fit_cases)
from gearopt.errors import DataFileError, GearoptInputError
from gearopt.joints import joint_capacities, joint_capacity
from gearopt.report.joint_tables import joint_table
from gearopt.studies.failure import sample_inputs, sampled_capacity_N

SYSTEM = go.load_system()
DATA = go.load_default_data()


def test_system_of_is_the_one_conversion_point():
    assert system_of(SYSTEM) is SYSTEM
    converted = system_of(DATA)
    assert set(converted.joints) == set(SYSTEM.joints) and converted.materials == SYSTEM.materials
    with pytest.raises(GearoptInputError, match=r"joint_capacity: data is required"):
        system_of(None, "joint_capacity")
    with pytest.raises(GearoptInputError, match="must be a System"):
        system_of(3.0, "joint_capacity")


def test_system_and_dict_give_identical_numbers():
    train = go.load_default_train("spur")
    rows = {k: c.as_row() for k, c in joint_capacities(SYSTEM, speed_rpm=2500.0).items()}
    assert rows == {k: c.as_row() for k, c in joint_capacities(DATA, speed_rpm=2500.0).items()}
    assert list(rows) == list(SYSTEM.joints)
    assert blank_from_data(SYSTEM, train, "cam")[0] == blank_from_data(DATA, train, "cam")[0]
    assert fit_capacity_N(SYSTEM, "cam", speed_rpm=3000.0) == fit_capacity_N(DATA, "cam", speed_rpm=3000.0)
    assert fit_cases(SYSTEM, "crank", 2500.0) == fit_cases(DATA, "crank", 2500.0)
    np.testing.assert_array_equal(capacity_levels_N(SYSTEM, "cam", 2500.0, 5), capacity_levels_N(DATA, "cam", 2500.0, 5))
    assert damper_coefficient(SYSTEM, "seized") == damper_coefficient(DATA, "seized")
    assert envelope_speeds_rpm(SYSTEM) == envelope_speeds_rpm(DATA)
    assert sample_inputs(SYSTEM, "cam", 50, 3).equals(sample_inputs(DATA, "cam", 50, 3))
    x = np.array([40.0, 60.0])
    np.testing.assert_array_equal(sampled_capacity_N(SYSTEM, "cam", 2500.0, x, 0.0 * x, 0.1 + 0 * x),
                                  sampled_capacity_N(DATA, "cam", 2500.0, x, 0.0 * x, 0.1 + 0 * x))
    assert PressFitSpec.from_data(SYSTEM, "cam") == PressFitSpec.from_data(DATA, "cam")
    assert TaperFitSpec.from_data(SYSTEM, "ac") == TaperFitSpec.from_data(DATA, "ac")
    assert BlankSpec.from_data(SYSTEM, train, "cam") == BlankSpec.from_data(DATA, train, "cam")
    assert web_demand_from_loads(SYSTEM, train, "cam") == web_demand_from_loads(DATA, train, "cam")
    assert accessory_load_torques_Nm(SYSTEM, "mean") == accessory_load_torques_Nm(DATA, "mean")


def test_missing_joint_and_material_name_file_and_key_path():
    with pytest.raises(DataFileError, match=r"default_train\.toml: joints\.nope is missing: joint_capacity"):
        joint_capacity(SYSTEM, "nope")
    with pytest.raises(DataFileError, match=r"joints\.nope is missing"):
        fit_capacity_N(SYSTEM, "nope")
    data = copy.deepcopy(data_of(SYSTEM))
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
