"""Independent stages of a long script in a second process, beside the main one.

A script whose stages do not depend on each other (the main job: the co-design, the failure reproduction and the
trade-off study need only the data) runs some of them in a side process while it computes the others: on a machine
with two cores the run takes about the longer of the two chains instead of their sum. Inside
:func:`side_process`, :meth:`SideProcess.submit` returns a :class:`concurrent.futures.Future`; leaving the block
waits for what is still running. Nothing here schedules work: it is one :class:`~concurrent.futures.ProcessPoolExecutor`
worker, started by :func:`gearopt.executor.process_pool` (no fork of a process holding solver or plotting threads: a
fresh server process imports the program once and forks the workers, each with this process's environment).

A function of a script (a file run as ``__main__`` or loaded from its path, not importable by name) is found in the
worker by loading that file again (its ``if __name__ == "__main__"`` block does not run); a function of an
importable module is pickled by reference as usual. Arguments and results must pickle. The worker logs at INFO to
standard error with a ``[side]`` prefix, so each stage's progress still shows as it goes.

``enabled=False`` runs each submitted function at once in this process (same results, no second process).
"""

from __future__ import annotations

import contextlib
import importlib
import importlib.util
import inspect
import logging
import os
import sys
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path
from typing import Any, Callable, Iterator

from ..executor import helper_process_ids, process_pool

__all__ = ["SideProcess", "side_process", "terminate_descendants", "children_die_with_this_process"]


class SideProcess:
    """Submits functions to the side process (see the module docstring)."""

    def __init__(self, pool: ProcessPoolExecutor | None):
        self._pool = pool

    @property
    def enabled(self) -> bool:
        """True when submitted work runs in the second process."""
        return self._pool is not None

    def submit(self, fn: Callable, *args: Any, **kwargs: Any) -> Future:
        """Run ``fn(*args, **kwargs)`` in the side process (at once when disabled); its future."""
        if self._pool is None:
            future: Future = Future()
            try:
                future.set_result(fn(*args, **kwargs))
            except Exception as exc:  # noqa: BLE001  (re-raised by future.result(), as from the worker)
                future.set_exception(exc)
            return future
        if _importable(fn):
            return self._pool.submit(_call, fn, args, kwargs)
        return self._pool.submit(_call_from_file, _script_of(fn), fn.__qualname__, args, kwargs)


@contextlib.contextmanager
def side_process(enabled: bool = True, *, workers: int = 1) -> Iterator[SideProcess]:
    """A :class:`SideProcess` for the block; leaving it waits for the submitted work (a failure is raised by
    the future's ``result()``). ``workers`` > 1: that many side processes, the submitted functions spread over
    them in order of submission."""
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        from ..errors import GearoptInputError
        raise GearoptInputError(f"workers={workers!r} must be an integer >= 1")
    if not enabled:
        yield SideProcess(None)
        return
    pool = process_pool(workers, initializer=_configure_logging)
    try:
        yield SideProcess(pool)
    except BaseException:              # an error or a signal in the block: do not wait for the side's work
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True, cancel_futures=True)


def terminate_descendants(grace_s: float = 3.0) -> int:
    """Terminate every descendant process of this one (side processes, their workers, the figure writer): SIGTERM,
    then SIGKILL for those still alive after ``grace_s`` seconds. Returns how many there were. Multiprocessing's
    idle helpers (:func:`gearopt.executor.helper_process_ids`: the forkserver the workers are forked from, the
    resource tracker) are left: they compute nothing, end with this process, and a later pool of this process (a
    notebook, a script that goes on after a failed stage) needs them."""
    import psutil

    helpers = helper_process_ids()
    procs = [p for p in psutil.Process().children(recursive=True) if p.pid not in helpers]
    for proc in procs:
        with contextlib.suppress(psutil.NoSuchProcess):
            proc.terminate()
    _, alive = psutil.wait_procs(procs, timeout=grace_s)
    for proc in alive:
        with contextlib.suppress(psutil.NoSuchProcess):
            proc.kill()
    return len(procs)


@contextlib.contextmanager
def children_die_with_this_process() -> Iterator[None]:
    """A block whose child processes do not outlive it: ``SIGTERM`` (a timeout, a scheduler, ``kill``) and
    ``SIGINT`` terminate every descendant process (:func:`terminate_descendants`) and end this process at once with
    exit code 128 + the signal (143, 130) and a one-line message; an error leaving the block terminates the
    descendants too. Signal handlers are installed in the main thread only (elsewhere the block only cleans up after
    an error)."""
    import signal
    import threading

    previous = {}

    def stop(signum, frame):
        # exit at once: an exception raised here could be caught on its way (inside a solver callback, by a
        # multistart that goes on after a failed start) and the job would run on
        count = terminate_descendants()
        sys.stderr.write(f"stopped by {signal.Signals(signum).name}: this process and its {count} child process(es)\n")
        sys.stderr.flush()
        os._exit(128 + signum)

    if threading.current_thread() is threading.main_thread():
        for sig in (signal.SIGTERM, signal.SIGINT):
            previous[sig] = signal.signal(sig, stop)
    try:
        yield
    except BaseException:
        terminate_descendants()
        raise
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _importable(fn: Callable) -> bool:
    module = getattr(fn, "__module__", None)
    if not module or module == "__main__" or "<locals>" in getattr(fn, "__qualname__", ""):
        return False
    try:
        return getattr(importlib.import_module(module), fn.__qualname__.split(".")[0], None) is not None
    except ImportError:
        return False


def _script_of(fn: Callable) -> str:
    """The file a function that is not importable by name is loaded from in the side process; a
    :class:`~gearopt.errors.GearoptInputError` naming it when the side process could not find it there."""
    from ..errors import GearoptInputError

    name = getattr(fn, "__qualname__", repr(fn))
    try:
        path = inspect.getfile(fn)
    except TypeError:
        path = ""
    if "<locals>" in name or "<lambda>" in name or not os.path.isfile(path):
        where = ("is nested in another function or a lambda" if "<locals>" in name or "<lambda>" in name
                 else f"has no source file ({path or 'none'}: python -c, an interactive session or exec'd code)")
        raise GearoptInputError(f"side_process: {name!r} cannot be found by a side process: it {where}; define it "
                                f"at the top level of a module or a script file, or use side_process(enabled=False)")
    return path


def _configure_logging() -> None:
    if not logging.getLogger().handlers:
        logging.basicConfig(level=logging.INFO, format="[side] %(message)s")


def _call(fn: Callable, args: tuple, kwargs: dict) -> Any:
    return fn(*args, **kwargs)


def _call_from_file(path: str, qualname: str, args: tuple, kwargs: dict) -> Any:
    spec = importlib.util.spec_from_file_location(f"_side_{Path(path).stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    obj: Any = module
    for part in qualname.split("."):
        obj = getattr(obj, part)
    return obj(*args, **kwargs)
