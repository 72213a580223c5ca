"""The data-file schema: every damaged or spoiled file gives one DataFileError naming the file and the key path."""

from __future__ import annotations

import copy
import pathlib
import re

import pytest

from gearopt.data import (default_data_path, load_default_data, load_default_train, schema_markdown,
                          train_from_data, validate_data)
from gearopt.errors import DataFileError, GearoptInputError

ROOT = pathlib.Path(__file__).resolve().parents[2]
DEFAULT_TEXT = default_data_path().read_text(encoding="utf-8")
MINIMAL = default_data_path().parent / "minimal_train.toml"


def _write(tmp_path, text: str | bytes, name: str = "train.toml") -> pathlib.Path:
    path = tmp_path / name
    path.write_bytes(text.encode("utf-8") if isinstance(text, str) else text)
    return path


def _error(path) -> str:
    with pytest.raises(DataFileError) as info:
        load_default_train("spur", path)
    message = str(info.value)
    assert str(path) in message  # the file is named in the message
    return message


def test_default_and_minimal_files_validate_and_build():
    validate_data(load_default_data(), source="default")
    train = load_default_train("spur", MINIMAL)
    row = train.mesh_table().iloc[0]
    # the builder puts the root shift on the pinion and the rest of the ISO 21771 sum on the wheel
    assert row["profile_shift_1"] == pytest.approx(0.2)
    assert row["centre_distance_mm"] == pytest.approx(90.5)


def test_schema_error_is_a_named_input_error():
    assert issubclass(DataFileError, GearoptInputError) and issubclass(DataFileError, ValueError)


@pytest.mark.parametrize("content, words", [
    (b"", "empty"),
    (b"   \n# only a comment\n", "empty"),
    (b"\xff\xfe\x00garbage", "not UTF-8"),
    (DEFAULT_TEXT[: len(DEFAULT_TEXT) // 3].encode(), "not valid TOML"),
    (bytes(range(256)), "not UTF-8"),
])
def test_damaged_files_give_one_clear_error(tmp_path, content, words):
    message = _error(_write(tmp_path, content))
    assert words in message


def test_missing_file_is_named(tmp_path):
    assert "not found" in _error(tmp_path / "nowhere.toml")


def test_unknown_key_suggests_the_nearest_valid_key(tmp_path):
    message = _error(_write(tmp_path, DEFAULT_TEXT.replace("module_mm = 3.0", "modulus_mm = 3.0", 1)))
    assert "rack.modulus_mm: unknown key; did you mean 'module_mm'?" in message
    assert "rack.module_mm: missing key" in message  # the same file: both problems in one error


def test_a_key_with_another_unit_suffix_points_to_the_schema_unit(tmp_path):
    message = _error(_write(tmp_path, DEFAULT_TEXT.replace("face_width_mm = 25.0", "face_width_in = 1.0", 1)))
    assert re.search(r"gears\.\w+\.face_width_in: unknown key; did you mean 'face_width_mm'\?", message)


def test_misspelt_section_is_named(tmp_path):
    message = _error(_write(tmp_path, DEFAULT_TEXT.replace("[rack]", "[rakc]", 1)))
    assert "rakc: unknown key; did you mean 'rack'?" in message and "rack: missing key" in message


@pytest.mark.parametrize("old, new, words", [
    ("teeth = 38", "teeth = 0", "gears.crank.teeth: 0 is below its limit: must be >= 5"),
    ("teeth = 38", "teeth = 38.5", "gears.crank.teeth: 38.5 must be an integer count"),
    ("teeth = 38", 'teeth = "38"', "gears.crank.teeth: must be a number"),
    ("module_mm = 3.0", "module_mm = nan", "rack.module_mm: nan is not a number mm"),
    ("module_mm = 3.0", "module_mm = inf", "rack.module_mm: inf mm is not a finite number"),
    ("module_mm = 3.0", "module_mm = 1e300", "rack.module_mm: 1e+300 mm is not a finite number"),
    ("pressure_angle_deg = 20.0", "pressure_angle_deg = 45.0", "rack.pressure_angle_deg: 45.0 deg exceeds"),
    ("stations = 6", "stations = 1000000000000", "engine.camshaft.stations: 1000000000000 exceeds its limit"),
])
def test_spoiled_values_are_named_with_their_path_and_limit(tmp_path, old, new, words):
    assert old in DEFAULT_TEXT
    assert words in _error(_write(tmp_path, DEFAULT_TEXT.replace(old, new, 1)))


def test_nan_allowance_is_rejected_instead_of_a_nan_backlash():
    data = load_default_data()
    data["gears"]["cam"]["tooth_thickness_lower_allowance_um"] = float("nan")
    with pytest.raises(DataFileError, match=r"<mine>: gears\.cam\.tooth_thickness_lower_allowance_um: nan"):
        train_from_data(data, "spur", source="<mine>")


def test_cross_references_are_checked():
    data = load_default_data()
    spoiled = copy.deepcopy(data)
    spoiled["meshes"]["crank-cam"]["gears"] = ["crank", "camm"]
    spoiled["trains"]["spur"]["root_mesh"] = "crank-cma"
    with pytest.raises(DataFileError) as info:
        validate_data(spoiled, source="x.toml")
    text = str(info.value)
    assert "meshes.crank-cam.gears: 'camm' is not a key of gears" in text
    spoiled = copy.deepcopy(data)
    spoiled["trains"]["spur"]["root_mesh"] = "crank-cma"
    with pytest.raises(DataFileError, match="did you mean 'crank-cam'"):
        validate_data(spoiled, source="x.toml")
    spoiled = copy.deepcopy(data)
    spoiled["engine"]["camshaft"]["station_inertias_kgm2"] = [0.0008] * 5
    with pytest.raises(DataFileError, match="station_inertias_kgm2: has 5 entries"):
        validate_data(spoiled, source="x.toml")
    spoiled = copy.deepcopy(data)
    spoiled["engine"]["firing_order"] = [1, 5, 3, 6, 2, 2]
    with pytest.raises(DataFileError, match="not a permutation"):
        validate_data(spoiled, source="x.toml")


def test_every_problem_line_names_the_source():
    data = load_default_data()
    data["rack"]["module_mm"] = -1.0
    data["gears"]["crank"]["face_width_mm"] = "wide"
    with pytest.raises(DataFileError) as info:
        validate_data(data, source="mine.toml")
    lines = str(info.value).splitlines()
    assert lines[0].startswith("mine.toml: 2 problems")
    assert all(line.startswith("  - mine.toml: ") for line in lines[1:]) and len(lines) == 3


def test_documented_schema_is_current_and_covers_every_default_key():
    doc = (ROOT / "docs" / "data-schema.md").read_text(encoding="utf-8")
    assert doc == schema_markdown(), "regenerate docs/data-schema.md from gearopt.data.schema_markdown()"
    data = load_default_data()
    named = {"gears", "meshes", "materials", "joints", "trains"}

    def keys(table, prefix=""):
        for k, v in table.items():
            if k.endswith("_source"):
                continue
            path = f"{prefix}{k}"
            parts = path.split(".")
            if parts[0] in named and len(parts) > 1:
                parts[1] = "*"
            yield ".".join(parts)
            if isinstance(v, dict) and not path.endswith("thesis_profile_shifts"):
                yield from keys(v, f"{path}.")

    for path in keys(data):
        assert f"| `{path}` |" in doc, path


def test_a_flat_design_torque_of_the_old_layout_says_where_it_goes():
    data = load_default_data()
    data["design_loads"]["pinion_wheel_torque_Nm"] = 120.0
    with pytest.raises(DataFileError, match=r"old.toml: design_loads.pinion_wheel_torque_Nm: design torques are "
                                            r"stated per mesh: move it to \[meshes.<driving>-<driven>\]"):
        validate_data(data, source="old.toml")
