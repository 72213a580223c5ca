"""Loading and validating the same data again in a process reuses the first result, and never hides a change:
``load_default_data`` keeps each unchanged file's validated data (a copy per caller), ``validate_data`` checks each
content once."""

from __future__ import annotations

import copy
import os

import pytest

from gearopt.data import default_data_path, load_default_data, train_from_data, validate_data
from gearopt.errors import DataFileError


def test_a_second_load_is_equal_but_the_callers_own_copy():
    first = load_default_data()
    first["rack"]["module_mm"] = 99.0                # the caller's copy: a later load does not see this
    first["gears"]["cam"]["teeth"] = 0
    second = load_default_data()
    assert second["rack"]["module_mm"] == 3.0 and second["gears"]["cam"]["teeth"] > 0
    assert second == load_default_data() and second is not load_default_data()


def test_a_changed_file_is_read_again(tmp_path):
    path = tmp_path / "train.toml"
    text = default_data_path().read_text(encoding="utf-8")
    path.write_text(text, encoding="utf-8")
    assert load_default_data(path)["rack"]["module_mm"] == 3.0
    assert "module_mm = 3.0" in text
    path.write_text(text.replace("module_mm = 3.0", "module_mm = 3.25", 1), encoding="utf-8")
    stat = path.stat()
    os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns + 1_000_000))  # a new time even on a coarse clock
    assert load_default_data(path)["rack"]["module_mm"] == 3.25
    path.write_text(text.replace("module_mm = 3.0", "module_mm = nan", 1), encoding="utf-8")
    os.utime(path, ns=(stat.st_atime_ns, stat.st_mtime_ns + 2_000_000))
    with pytest.raises(DataFileError, match=r"rack\.module_mm: nan"):
        load_default_data(path)


def test_validated_content_does_not_let_a_spoiled_copy_or_a_mutation_through():
    data = load_default_data()
    assert validate_data(data) is data and validate_data(data) is data    # checked once, then remembered
    spoiled = copy.deepcopy(data)
    spoiled["gears"]["crank"]["teeth"] = 38.5        # same value, another type: another content
    with pytest.raises(DataFileError, match=r"gears\.crank\.teeth: 38\.5 must be an integer count"):
        validate_data(spoiled)
    data["gears"]["cam"]["tooth_thickness_lower_allowance_um"] = float("nan")   # the remembered object, mutated
    with pytest.raises(DataFileError, match=r"gears\.cam\.tooth_thickness_lower_allowance_um: nan"):
        train_from_data(data, "spur")
    with pytest.raises(DataFileError):                # a failure is not remembered as a pass
        validate_data(data)

