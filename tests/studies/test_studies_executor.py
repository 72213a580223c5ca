"""The executor layer: what ``executor=`` accepts, ordered results, failures propagate, progress off off-terminal,
a front split into segments gives the same points on the process pool as serially."""

import math

import numpy as np
import pytest

import gearopt as go
from gearopt.design.scene import DesignVariable, Limit, Objective, Scene
from gearopt.errors import GearoptInputError
from gearopt.executor import Executor, get_executor, using_executor
from gearopt.studies import pareto_front
from gearopt.studies.pareto import OK
from gearopt.studies.executor import _progress_bar


def _fail_on_three(x):
    if x == 3:
        raise ZeroDivisionError("three")
    return x


@pytest.mark.parametrize("bad", ["threads", 3, None, object()])
def test_unknown_executor_is_refused(bad):
    with pytest.raises(GearoptInputError, match="executor"):
        get_executor(bad)


def test_bad_worker_count_is_refused():
    with pytest.raises(GearoptInputError, match="workers=0"):
        Executor("processes", workers=0)


def test_serial_map_keeps_order_and_propagates_failures():
    with using_executor("serial") as ex:
        assert ex.map(math.sqrt, [9.0, 4.0, 1.0]) == [3.0, 2.0, 1.0]
        with pytest.raises(ZeroDivisionError):
            ex.map(_fail_on_three, range(5))


def test_a_given_executor_is_not_closed_by_a_study():
    ex = Executor("serial")
    with using_executor(ex) as inner:
        assert inner is ex
    assert ex.kind == "serial"


def test_progress_bar_is_off_when_stderr_is_not_a_terminal():
    # pytest captures stderr (not a tty): tqdm's disable=None turns the bar off
    bar = _progress_bar(10, "x", None)
    assert getattr(bar, "disable", True)
    assert type(_progress_bar(10, "x", False)).__name__ == "_NoBar"


def test_front_segments_on_processes_equal_the_serial_front():
    # a front through the executor (this file runs before the Dask test, so the pool forks): the cam blank,
    # minimum inertia against rim backup ratio (fast); two ε segments run as two tasks
    blank = Scene("blank", train=go.load_default_train("spur"), data=go.load_system(),
                  variables=[DesignVariable("web_thickness_mm", "cam", 4.0, 20.0),
                             DesignVariable("rim_thickness_mm", "cam", 4.0, 20.0)],
                  objectives=[Objective("inertia_kgm2", "cam")], limits=[Limit("rim_backup_ratio", "cam", lower=1.2)])
    serial = pareto_front(blank, "rim_backup_ratio", "cam", points=6, segments=2, refine=False)
    parallel = pareto_front(blank, "rim_backup_ratio", "cam", points=6, segments=2, refine=False,
                            executor="processes", workers=2)
    cols = ["epsilon", "status", serial.objective_column, serial.quantity_column, "cam.rim_thickness_mm"]
    assert len(serial.table) == 6 and (serial.table["status"] == OK).all()
    np.testing.assert_allclose(parallel.table[cols[2:]].to_numpy(float), serial.table[cols[2:]].to_numpy(float),
                               rtol=1e-9)
