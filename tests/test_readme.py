"""The README ships runnable documentation: every ```python block of the README and of ``docs/examples.md`` runs on
its own (fresh namespace, no state from the blocks before it), and the Python version the README states is the one
pyproject.toml requires."""

from __future__ import annotations

import re
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
PYTHON_BLOCK = re.compile(r"^```python\n(.*?)^```", flags=re.S | re.M)
BLOCKS = PYTHON_BLOCK.findall(README)
EXAMPLES = PYTHON_BLOCK.findall((ROOT / "docs" / "examples.md").read_text())


def test_readme_has_python_blocks():
    assert len(BLOCKS) >= 3 and len(EXAMPLES) >= 1


def _run_alone(source: str, name: str, tmp_path, monkeypatch) -> None:
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)          # a block that writes files writes them here
    exec(compile(source, name, "exec"), {"__name__": name.replace(" ", "_").replace(".", "_")})


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_block_runs_alone(index, tmp_path, monkeypatch):
    _run_alone(BLOCKS[index], f"README.md python block {index + 1}", tmp_path, monkeypatch)


@pytest.mark.parametrize("index", range(len(EXAMPLES)))
def test_docs_example_runs_alone(index, tmp_path, monkeypatch):
    _run_alone(EXAMPLES[index], f"docs/examples.md python block {index + 1}", tmp_path, monkeypatch)


def test_stated_python_version_is_the_required_one():
    required = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["requires-python"]
    minimum = re.fullmatch(r">=\s*3\.(\d+)", required)
    assert minimum, f"requires-python {required!r}: expected '>=3.N'"
    assert f"Python ≥ 3.{minimum.group(1)}" in README
    assert sys.version_info >= (3, int(minimum.group(1)))
    # the package imports tomllib (3.11+): a lower minimum would install and then fail on import
    uses_tomllib = any("import tomllib" in p.read_text() for p in (ROOT / "gearopt").rglob("*.py"))
    assert not uses_tomllib or int(minimum.group(1)) >= 11
