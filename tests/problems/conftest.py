"""Shared fixture of the problem-script tests: run a script of ``problems/`` in-process with ``--quick``."""

import importlib.util
from pathlib import Path

import pytest

PROBLEMS = Path(__file__).resolve().parents[2] / "problems"


def load_script(name: str):
    """Import ``problems/<name>.py`` as a module (the scripts are not a package)."""
    spec = importlib.util.spec_from_file_location(f"problem_{name}", PROBLEMS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def run_quick(tmp_path_factory):
    """``run_quick(name)``: run ``problems/<name>.py --quick --out <tmp>``, assert exit code 0, return the output
    directory."""
    def run(name: str) -> Path:
        out = tmp_path_factory.mktemp(name)
        assert load_script(name).main(["--quick", "--out", str(out)]) == 0
        return out
    return run
