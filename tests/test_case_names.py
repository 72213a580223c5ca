"""The library knows no train by name (issue 26's acceptance interface): no module under ``gearopt/`` outside the
case package (``gearopt/cases/``) holds the timing train's mesh names (crank-cam, cam-ac, cam-fp, crank-lpi,
lpi-lpg) or its idler/pump gear names (lpi, lpg) in a string literal -- docstrings included. A library function
takes the names from the user's system."""

from __future__ import annotations

import ast
import pathlib
import re

import gearopt

PACKAGE = pathlib.Path(gearopt.__file__).parent
CASE_NAMES = re.compile(r"crank-cam|cam-ac|cam-fp|crank-lpi|lpi-lpg|\blpi\b|\blpg\b", re.IGNORECASE)


def _literals_with_case_names(path: pathlib.Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return [f"{path}:{node.lineno}: {CASE_NAMES.search(node.value).group(0)!r}"
            for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and CASE_NAMES.search(node.value)]


def test_no_library_module_names_the_timing_train():
    hits = [hit for path in sorted(PACKAGE.rglob("*.py")) if "cases" not in path.relative_to(PACKAGE).parts
            for hit in _literals_with_case_names(path)]
    assert hits == [], "the timing train's names outside gearopt/cases:\n" + "\n".join(hits)


def test_the_check_sees_a_name_in_a_docstring_and_in_code(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text('"""Example: the crank-cam mesh."""\nMESH = "LPI-lpg"\nOTHER = "pinion-wheel"\n')
    assert len(_literals_with_case_names(sample)) == 2
