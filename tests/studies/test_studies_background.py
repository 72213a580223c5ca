"""The side process of a long script: a function of a script file (not importable by name) and one of a module
run in a second process and give what they give in this one; a failure reaches the caller; disabled, the work
runs at once here."""

import importlib.util
import math
import os

import pytest

from gearopt.errors import GearoptInputError
from gearopt.studies.background import side_process
from gearopt.validation import check_range

SCRIPT = '''
import os

def stage(x, *, scale=1.0):
    return {"value": x * scale, "pid": os.getpid()}

def broken(x):
    raise ValueError(f"bad stage input {x}")
'''


@pytest.fixture(scope="module")
def script(tmp_path_factory):
    path = tmp_path_factory.mktemp("script") / "a_script.py"
    path.write_text(SCRIPT)
    spec = importlib.util.spec_from_file_location("loaded_from_its_path", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_functions_run_in_a_second_process_with_the_same_results_and_failures_reach_the_caller(script):
    with side_process() as side:          # one worker for the whole test: its start imports gearopt
        assert side.enabled
        there = side.submit(script.stage, 3.0, scale=2.0)
        hyp = side.submit(math.hypot, 3.0, 4.0)
        failed = side.submit(script.broken, 7)
        assert there.result()["value"] == script.stage(3.0, scale=2.0)["value"] == 6.0
        assert there.result()["pid"] != os.getpid()
        assert hyp.result() == 5.0
        with pytest.raises(ValueError, match="bad stage input 7"):
            failed.result()


def test_disabled_runs_here_at_once(script):
    with side_process(enabled=False) as side:
        assert not side.enabled
        assert side.submit(script.stage, 1.5).result() == {"value": 1.5, "pid": os.getpid()}
        with pytest.raises(GearoptInputError, match="speed_rpm"):
            side.submit(check_range, "speed_rpm", -1.0, 0.0, None).result()


def test_bad_worker_count_is_named():
    with pytest.raises(GearoptInputError, match="workers=0"):
        with side_process(workers=0):
            pass


def test_a_side_process_sees_the_environment_of_its_start_not_of_an_earlier_worker_server(monkeypatch):
    """Side processes fork from one server started with the first of them (gearopt.executor.process_pool): a
    variable set after that server started (e.g. GEAROPT_THREADS for a quick run, or the figure checks' log a test
    sets) still reaches a later side process, as it reached a freshly spawned one."""
    with side_process() as side:          # the worker server is running from here on
        assert side.submit(os.getenv, "GEAROPT_ENV_PROBE").result() is None
    monkeypatch.setenv("GEAROPT_ENV_PROBE", "set after the server started")
    with side_process() as side:
        assert side.submit(os.getenv, "GEAROPT_ENV_PROBE").result() == "set after the server started"
    monkeypatch.delenv("GEAROPT_ENV_PROBE")
    with side_process() as side:
        assert side.submit(os.getenv, "GEAROPT_ENV_PROBE").result() is None


def test_side_processes_still_start_after_the_descendants_were_terminated():
    """terminate_descendants (an error leaving children_die_with_this_process) ends the side processes but not the
    idle server they fork from, so this process can start side processes again (a notebook, a script that goes on
    after a failed stage); the workers it ended are gone."""
    import psutil

    from gearopt.studies.background import terminate_descendants

    with side_process() as side:
        first = side.submit(os.getpid).result()
    terminate_descendants(grace_s=1.0)
    assert not psutil.pid_exists(first) or psutil.Process(first).status() == psutil.STATUS_ZOMBIE
    with side_process() as side:
        assert side.submit(math.hypot, 3.0, 4.0).result() == 5.0


def test_spawn_can_be_chosen_for_the_workers(monkeypatch):
    """GEAROPT_START_METHOD=spawn: fresh interpreters instead of the forkserver's forks; a bad value is named."""
    import multiprocessing

    from gearopt.executor import clean_process_context

    monkeypatch.setenv("GEAROPT_START_METHOD", "spawn")
    assert clean_process_context().get_start_method() == "spawn"
    with side_process() as side:
        assert side.submit(math.hypot, 6.0, 8.0).result() == 10.0
    monkeypatch.setenv("GEAROPT_START_METHOD", "vfork")
    with pytest.raises(GearoptInputError, match="GEAROPT_START_METHOD='vfork'"):
        clean_process_context()
    monkeypatch.delenv("GEAROPT_START_METHOD")
    expected = "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"
    assert clean_process_context().get_start_method() == expected


def test_a_function_a_side_process_cannot_find_is_named_at_once():
    """A function with no source file (python -c, exec'd code) or without a name in its module (a nested function,
    a lambda) cannot be loaded by the side process: submit names it with what to do, instead of the worker's
    AttributeError."""
    namespace = {}
    exec("def made_by_exec(x):\n    return x\n", namespace)
    nested = (lambda: (lambda x: x))()

    def inner(x):
        return x

    with side_process() as side:
        for fn, why in ((namespace["made_by_exec"], "has no source file"), (nested, "nested in another function"),
                        (inner, "nested in another function")):
            with pytest.raises(GearoptInputError, match=why):
                side.submit(fn, 1)
        assert side.submit(math.hypot, 3.0, 4.0).result() == 5.0          # the side process is still fine
