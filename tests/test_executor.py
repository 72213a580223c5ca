"""The one executor below every layer: tooth-count candidates (design) and speed sweeps (dynamics) give the same
table on a process pool as serially, in item order; the module ``gearopt.studies.executor`` holds the same objects."""

import numpy as np
import pandas as pd
import pytest

import gearopt as go
from gearopt.design.tooth_counts import enumerate_tooth_counts, tooth_count_study
from gearopt.cases.timing_train import default_timing_model
from gearopt.dynamics import speed_sweep
from gearopt.executor import Executor, using_executor


def _square_after(x):
    import time
    time.sleep(0.05 * (3 - x))        # the first items finish last: the order must still be the items'
    return x * x


def test_studies_executor_module_is_the_bottom_layer_executor():
    import gearopt.studies as studies
    import gearopt.studies.executor as old_path

    assert old_path.Executor is Executor and old_path.using_executor is using_executor
    assert "Executor" not in studies.__all__          # one documented path: gearopt.executor


def test_process_pool_returns_results_in_item_order_also_for_closures():
    offset = 10

    def shifted(x):                   # a closure: serialised by value (cloudpickle)
        return _square_after(x) + offset

    with using_executor("processes", workers=2) as ex:
        assert ex.map(_square_after, [0, 1, 2, 3]) == [0, 1, 4, 9]
        assert ex.map(shifted, [0, 1, 2, 3]) == [10, 11, 14, 19]


def _imported(names):
    import sys
    return [n for n in names if n in sys.modules]


def test_import_leaves_scipy_to_the_functions_that_use_it_and_workers_get_it_from_the_forkserver():
    """``import gearopt`` and its packages do not import SciPy's optimisers and statistics (about half of their
    import time, paid by every process, a CLI call, a test worker); a worker forked from the forkserver has them
    already (imported once in the server, not in each worker)."""
    import subprocess
    import sys

    from gearopt.executor import WORKER_PRELOAD, clean_process_context, process_pool

    packages = "gearopt, gearopt.design, gearopt.studies, gearopt.dynamics, gearopt.report, gearopt.cases.timing_train"
    code = f"import sys, {packages}; print([n for n in {list(WORKER_PRELOAD)!r} if n in sys.modules])"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
    if clean_process_context().get_start_method() == "forkserver":   # a side process, the figure writer
        pool = process_pool(1)
        try:
            assert pool.submit(_imported, WORKER_PRELOAD).result() == list(WORKER_PRELOAD)
        finally:
            pool.shutdown()


@pytest.fixture(scope="module")
def enumeration():
    return enumerate_tooth_counts(go.load_default_train("spur"), default_tolerance_percent=3.0, span=1)


@pytest.mark.parametrize("start, segments", [("previous", 2), ("iso", 1)])
def test_tooth_count_candidates_on_processes_equal_the_serial_study(enumeration, start, segments):
    serial = tooth_count_study(enumeration.train, enumeration=enumeration, top=5, start=start, segments=segments)
    parallel = tooth_count_study(enumeration.train, enumeration=enumeration, top=5, start=start, segments=segments,
                                 executor="processes", workers=2)
    table = serial.table
    assert (table["status"] != "not_solved").sum() == 5 and table["objective_value"].notna().sum() >= 3
    timing = ["solve_time_s"]
    pd.testing.assert_frame_equal(parallel.table.drop(columns=timing), table.drop(columns=timing))
    assert [s["teeth"] for s in parallel.solves] == [s["teeth"] for s in serial.solves]
    starts = [s["start"] for s in serial.solves]
    if start == "previous":            # two pieces of 3 and 2 candidates: each starts cold, the rest warm
        assert starts[0] == starts[3] == "iso" and starts.count("iso") == 2
    else:
        assert set(starts) == {"iso"}


def test_one_segment_is_the_old_single_warm_chain(enumeration):
    study = tooth_count_study(enumeration.train, enumeration=enumeration, top=4)
    starts = [s["start"] for s in study.solves]
    assert starts[0] == "iso" and set(starts[1:]) <= {"previous"}


def test_tooth_count_segments_are_checked(enumeration):
    with pytest.raises(go.GearoptInputError, match="segments=0"):
        tooth_count_study(enumeration.train, enumeration=enumeration, top=2, segments=0)


def test_speed_sweep_on_processes_equals_the_serial_sweep():
    model = default_timing_model("spur")
    kw = dict(backlash=(False,), cycles=1, run_in_cycles=0, output_step_deg=2.0, jit=False, reuse=False)
    speeds = [1200.0, 1800.0, 2400.0]
    serial = speed_sweep(model, speeds, **kw)
    parallel = speed_sweep(model, speeds, executor="processes", workers=2, **kw)
    assert serial["speed_rpm"].unique().tolist() == speeds
    assert (serial.loc[serial["element"] == "joint:cam", "min_torque_margin"] > 0).all()
    pd.testing.assert_frame_equal(parallel.drop(columns="run_time_s"), serial.drop(columns="run_time_s"))
    # the speeds differ in the response: the table is not one row repeated
    peaks = serial.loc[serial["element"] == "crank-cam", "peak_drive_force_N"].to_numpy()
    assert np.ptp(peaks) > 0.0


def test_process_pool_runs_in_this_environment_and_names_bad_arguments(monkeypatch, tmp_path):
    """gearopt.executor.process_pool: its workers read the environment of the pool's start (a forkserver's would
    keep the server's), an initializer runs in each worker after it, and bad arguments are named."""
    import os

    from gearopt.errors import GearoptInputError
    from gearopt.executor import process_pool

    monkeypatch.setenv("GEAROPT_POOL_PROBE", "first")
    with process_pool(1) as pool:
        assert pool.submit(os.getenv, "GEAROPT_POOL_PROBE").result() == "first"
    monkeypatch.setenv("GEAROPT_POOL_PROBE", "second")
    with process_pool(1, initializer=os.chdir, initargs=(str(tmp_path),)) as pool:
        assert pool.submit(os.getenv, "GEAROPT_POOL_PROBE").result() == "second"
        assert pool.submit(os.getcwd).result() == str(tmp_path)          # the initializer ran after it
    for bad in (0, -1, 1.5, True, "2"):
        with pytest.raises(GearoptInputError, match="max_workers"):
            process_pool(bad)
    with pytest.raises(GearoptInputError, match="initializer"):
        process_pool(1, initializer="not callable")
