"""Shared fixture of the problem-script tests: run a script of ``problems/`` in-process with ``--quick``."""

import importlib.util
import json
from pathlib import Path

import pytest

from gearopt.report.figure_writer import CHECKS_ENV

FIGURE_CHECKS = "figure_checks.jsonl"

PROBLEMS = Path(__file__).resolve().parents[2] / "problems"


def load_script(name: str):
    """Import ``problems/<name>.py`` as a module (the scripts are not a package)."""
    spec = importlib.util.spec_from_file_location(f"problem_{name}", PROBLEMS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="session")
def run_quick(tmp_path_factory):
    """``run_quick(name)``: run ``problems/<name>.py --quick --out <tmp>`` (once per session), assert exit code 0 or
    1 (1: a requirement fails; ``run_quick.exit_codes[name]`` holds it), return the output directory."""
    done: dict[str, Path] = {}
    codes: dict[str, int] = {}

    def run(name: str) -> Path:
        if name in done:                   # one quick run per script and session, shared by its test modules
            return done[name]
        out = done[name] = tmp_path_factory.mktemp(name)
        with pytest.MonkeyPatch.context() as mp:     # every figure checked where it is drawn (any process)
            mp.setenv(CHECKS_ENV, str(out / FIGURE_CHECKS))
            codes[name] = load_script(name).main(["--quick", "--out", str(out)])
        assert codes[name] in (0, 1), codes[name]
        return out
    run.exit_codes = codes
    return run


def figure_checks(out: Path) -> dict[str, dict]:
    """``{file name: check record}`` of the figures a ``run_quick`` run wrote (:data:`CHECKS_ENV`)."""
    path = out / FIGURE_CHECKS
    if not path.exists():
        return {}
    return {r["file"]: r for r in map(json.loads, path.read_text().splitlines())}
