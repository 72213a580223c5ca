"""Shared data of the design tests: the packaged minimal pair with its gears renamed (any train)."""

import re

import pytest

from gearopt.data import default_data_path

RENAMED_GEARS = {"pinion": "sun_gear", "wheel": "drum_gear"}
"""The minimal pair's gears under other names: its mesh is ``sun_gear-drum_gear``."""


@pytest.fixture(scope="module")
def renamed_minimal_path(tmp_path_factory):
    """Path of the packaged minimal pair's data file with its gears renamed (:data:`RENAMED_GEARS`)."""
    text = (default_data_path().parent / "minimal_train.toml").read_text(encoding="utf-8")
    for old, new in RENAMED_GEARS.items():
        text = re.sub(rf"\b{old}\b", new, text)
    path = tmp_path_factory.mktemp("renamed") / "renamed.toml"
    path.write_text(text, encoding="utf-8")
    return path
