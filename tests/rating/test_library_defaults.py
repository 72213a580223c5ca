"""The rating layer's lubrication defaults are library constants ([E] typical values), never reads of the packaged
file -- and they equal the packaged file's [lubrication] values, so the two cannot drift apart (this test may read
the packaged file; the library may not)."""

from __future__ import annotations

import ast
import pathlib

import pytest

import gearopt
from gearopt.data import load_system
from gearopt.rating import (DEFAULT_FRICTION_COEFFICIENT, DEFAULT_OIL_TEMPERATURE_C, default_lubricant,
                            flash_temperature_pair_K)


def test_defaults_equal_the_packaged_lubrication():
    lub = load_system().lubrication
    assert DEFAULT_OIL_TEMPERATURE_C == lub.oil_temperature_C == 100.0
    assert DEFAULT_FRICTION_COEFFICIENT == lub.mean_friction_coefficient == 0.06
    assert default_lubricant().oil_temperature_C == DEFAULT_OIL_TEMPERATURE_C


def test_a_caller_passes_its_own_lubrication():
    system = load_system()
    assert default_lubricant(80.0).oil_temperature_C == 80.0
    assert default_lubricant(system.lubrication.oil_temperature_C) == default_lubricant()
    pair = system.train("spur").pairs["crank-cam"]
    rho = 0.1 * float(pair.geometry()["centre_distance_mm"])
    default = flash_temperature_pair_K(pair, 200.0, 2000.0, rho, parts=True)
    own = flash_temperature_pair_K(pair, 200.0, 2000.0, rho, parts=True,
                                   friction=system.lubrication.mean_friction_coefficient,
                                   bulk_temperature_C=system.lubrication.oil_temperature_C)
    assert own["flash_temperature_K"] == default["flash_temperature_K"]
    assert own["contact_temperature_C"] == default["contact_temperature_C"]
    doubled = flash_temperature_pair_K(pair, 200.0, 2000.0, rho, friction=2 * DEFAULT_FRICTION_COEFFICIENT)
    assert doubled == pytest.approx(2.0 * default["flash_temperature_K"], rel=1e-12)


def test_the_rating_layer_does_not_import_the_data_package():
    # no load_default_data/load_system/values from gearopt.data in the rating layer (the material catalogue,
    # rating/materials.py, still merges the packaged [materials] tables through importlib.resources: a catalogue,
    # not a fallback for a caller's missing input)
    rating = pathlib.Path(gearopt.__file__).parent / "rating"
    bad = []
    for path in sorted(rating.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level == 2 and (node.module or "").startswith("data"):
                bad.append(f"{path.name}:{node.lineno}")
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("gearopt.data"):
                bad.append(f"{path.name}:{node.lineno}")
    assert bad == [], "the rating layer reads data files: " + ", ".join(bad)
