"""Scheduling of the suite under pytest-xdist ``--dist loadfile`` (the README's test command).

xdist hands out whole files, by default those with the most tests first. A file with few but long tests (a problem
script's quick run in a module fixture) then starts last and the other workers idle while it runs: the wall time is
set by that tail. Here the longest units go first (longest-processing-time order; measured on 2 cores, see
:data:`LONGEST_FIRST`), the rest keep xdist's order, and the files whose tests share no fixture beyond a function's
(:data:`PER_TEST`) are split into one unit per test, so their long tests spread over the workers.

A path listed here that no longer exists is reported by ``tests/test_scheduling.py``; an unlisted new file is
scheduled in xdist's order (correct, perhaps late).
"""

from __future__ import annotations

import re

import pytest

from gearopt.data import default_data_path

LONGEST_FIRST: tuple[str, ...] = (
    "tests/problems/test_helix_front_script.py",                    # ~33 s: the helix front's quick run
    "tests/problems/test_cam_gear_walkoff.py",                      # ~20 s: the main job's quick run + side process
    "tests/design/test_scene_codesign.py",
    "tests/design/test_microgeometry_nlp.py",
    "tests/benchmarks/test_benchmarks_quick.py::test_benchmark_quick_mode[bench_studies]",
    "tests/benchmarks/test_benchmarks_quick.py::test_benchmark_quick_mode[bench_stability]",
    "tests/test_readme.py::test_readme_block_runs_alone[1]",        # LTCA + microgeometry NLP
    "tests/test_readme.py::test_docs_example_runs_alone[2]",        # the co-design scene
    "tests/problems/test_studies_scripts.py",
    "tests/problems/test_any_train_scripts.py",                     # ~35 s: six scripts on a renamed pair
    "tests/dynamics/test_train_model.py",
    "tests/benchmarks/test_benchmarks_quick.py::test_benchmark_quick_mode[bench_microgeometry_nlp]",
    "tests/benchmarks/test_benchmarks_quick.py::test_benchmark_quick_mode[bench_dynamics_speed]",
    "tests/test_readme.py::test_readme_block_runs_alone[2]",        # the scene, 8 starts
    "tests/test_readme.py::test_docs_example_runs_alone[1]",        # fronts, Monte Carlo
    "tests/benchmarks/test_benchmarks_quick.py::test_benchmark_quick_mode[bench_codesign]",
    "tests/dynamics/test_dynamics_default_model.py",
    "tests/stability/test_stability_microgeometry.py",
    "tests/test_executor.py",
    "tests/studies/test_studies_pareto.py",
    "tests/robustness/test_properties.py",
)
"""Units (files, or tests of a :data:`PER_TEST` file) by their measured duration, longest first."""

PER_TEST: tuple[str, ...] = ("tests/benchmarks/test_benchmarks_quick.py", "tests/test_readme.py")
"""Files whose tests are independent (each runs its own script or documentation block): one xdist unit per test."""


def rank(scope: str) -> int:
    """Position of an xdist unit in :data:`LONGEST_FIRST` (``len`` for an unlisted one)."""
    for i, entry in enumerate(LONGEST_FIRST):
        if scope == entry or scope.startswith(entry + "::"):
            return i
    return len(LONGEST_FIRST)


def pytest_xdist_make_scheduler(config, log):
    """``--dist loadfile``: xdist's file scheduling, longest units first and :data:`PER_TEST` files split."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class LongestFirst(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return nodeid if nodeid.split("::", 1)[0] in PER_TEST else super()._split_scope(nodeid)

        def _assign_work_unit(self, node) -> None:
            first = min(self.workqueue, key=rank)        # ties: the first in xdist's order
            self.workqueue.move_to_end(first, last=False)
            super()._assign_work_unit(node)

    return LongestFirst(config, log)


RENAMED_GEARS = {"pinion": "sun_gear", "wheel": "drum_gear"}
"""The packaged minimal pair's gears under other names (any train): its mesh is ``sun_gear-drum_gear``."""


@pytest.fixture(scope="module")
def renamed_minimal_path(tmp_path_factory):
    """Path of the packaged minimal pair's data file with its gears renamed (:data:`RENAMED_GEARS`)."""
    text = (default_data_path().parent / "minimal_train.toml").read_text(encoding="utf-8")
    for old, new in RENAMED_GEARS.items():
        text = re.sub(rf"\b{old}\b", new, text)
    path = tmp_path_factory.mktemp("renamed") / "renamed.toml"
    path.write_text(text, encoding="utf-8")
    return path
