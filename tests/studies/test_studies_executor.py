"""The executor layer: what ``executor=`` accepts, ordered results, failures propagate, progress off off-terminal."""

import math

import pytest

from gearopt.errors import GearoptInputError
from gearopt.studies import Executor, get_executor, using_executor
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
