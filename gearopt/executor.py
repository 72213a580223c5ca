"""One executor for every batch: serial, local processes, or a Dask distributed cluster.

A bottom-layer unit (it imports only :mod:`gearopt.errors`), so that every layer can take an ``executor=``
argument: the dynamics' speed sweeps, the tooth-count candidates of the design layer, and the studies' Pareto
segments and Monte Carlo chunks (``gearopt.studies.executor`` re-exports it). Every batch goes through
:meth:`Executor.map`, which applies a picklable function to a list of items and returns the results *in the order
of the items* whoever ran them -- so a study gives the same table with every executor. Nothing here schedules work
itself: ``"processes"`` is :class:`concurrent.futures.ProcessPoolExecutor` (forked workers from a single-threaded
process, ones forked from a fresh server (:func:`clean_process_context`) from a process holding threads -- a Dask
client -- so that either starts safely), ``"dask"``
a :class:`distributed.LocalCluster` (one thread per worker process), and a :class:`distributed.Client` (or a
scheduler address ``"tcp://host:port"``) runs the batch on that cluster.

Long batches show a tqdm progress bar; it is off when standard error is not a terminal (tqdm's ``disable=None``).

Example::

    with using_executor("dask", workers=2) as ex:
        squares = ex.map(pow2, range(100))
"""

from __future__ import annotations

import multiprocessing
import os
import pickle
import sys
import threading
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from typing import Any, Callable, Iterable, Iterator, Sequence

from .errors import GearoptInputError

KINDS = ("serial", "processes", "dask")


class Executor:
    """Runs ``fn`` over items serially, in local processes or on a Dask cluster (see the module docstring).

    Args:
        kind: ``"serial"``, ``"processes"`` or ``"dask"`` (a local cluster started here, closed by :meth:`close`).
        workers: worker processes for ``"processes"``/``"dask"`` (default: the machine's CPU count, at most 4).
        client: a running :class:`distributed.Client` (then ``kind`` is ``"dask"`` and the client stays open).
        progress: show a progress bar (``None``: only when standard error is a terminal).
    """

    def __init__(self, kind: str = "serial", *, workers: int | None = None, client: Any = None,
                 progress: bool | None = None):
        if client is not None:
            kind = "dask"
        if kind not in KINDS:
            raise GearoptInputError(f"executor={kind!r} is not one of {KINDS} (or a dask.distributed.Client)")
        if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
            raise GearoptInputError(f"workers={workers!r} must be an integer >= 1")
        self.kind = kind
        self.workers = workers or min(os.cpu_count() or 1, 4)
        self.progress = progress
        self._client = client
        self._own_client = False
        self._pool: ProcessPoolExecutor | None = None

    # -- lifetime ------------------------------------------------------------------------------------------------

    def __enter__(self) -> "Executor":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Shut down what this executor started (a process pool, a local cluster); a given client stays open."""
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None
        if self._own_client and self._client is not None:
            cluster = self._client.cluster
            self._client.close()
            if cluster is not None:
                cluster.close()
            self._client = None
            self._own_client = False

    @property
    def client(self):
        """The :class:`distributed.Client` (started on first use for ``"dask"``)."""
        if self.kind != "dask":
            return None
        if self._client is None:
            from distributed import Client, LocalCluster

            cluster = LocalCluster(n_workers=self.workers, threads_per_worker=1, processes=True,
                                   dashboard_address=None)
            self._client = Client(cluster)
            self._own_client = True
        return self._client

    # -- running ---------------------------------------------------------------------------------------------------

    def map(self, fn: Callable[[Any], Any], items: Iterable[Any], *, desc: str = "") -> list[Any]:
        """``[fn(item) for item in items]``, run by this executor, in the order of ``items``. For ``"processes"``
        and ``"dask"``, ``fn`` and the items are serialised by cloudpickle (Dask's serialiser, also used here for the
        process pool): module-level functions go by reference, closures and lambdas by value (a timing model with
        its excitation closures travels whole; CasADi graphs inside a CasADi pickle context). An exception raised
        by ``fn`` propagates (catch failures inside ``fn`` to record them instead)."""
        items = list(items)
        if self.kind == "processes" and self._pool is None and items:
            self._pool = process_pool(self.workers, _process_context())
        bar = _progress_bar(len(items), desc, self.progress)
        try:
            if self.kind == "serial" or not items:
                out = []
                for item in items:
                    out.append(fn(item))
                    bar.update(1)
                return out
            if self.kind == "processes":
                return self._map_processes(fn, items, bar)
            return self._map_dask(fn, items, bar)
        finally:
            bar.close()

    def _map_processes(self, fn, items: Sequence[Any], bar) -> list[Any]:
        futures = {self._pool.submit(_call, _dumps(fn, item)): i for i, item in enumerate(items)}
        out: list[Any] = [None] * len(items)
        for fut in as_completed(futures):
            out[futures[fut]] = fut.result()
            bar.update(1)
        return out

    def _map_dask(self, fn, items: Sequence[Any], bar) -> list[Any]:
        from distributed import as_completed as dask_completed

        client = self.client
        futures = client.map(_call, [_dumps(fn, item) for item in items], pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        out: list[Any] = [None] * len(items)
        for fut in dask_completed(futures):
            out[index[fut.key]] = fut.result()
            bar.update(1)
        return out

    def __repr__(self) -> str:
        return f"Executor({self.kind!r}, workers={self.workers})"


def get_executor(executor: "str | Executor | Any" = "serial", *, workers: int | None = None,
                 progress: bool | None = None) -> Executor:
    """An :class:`Executor` from what a study's ``executor=`` argument accepts: ``"serial"``, ``"processes"``,
    ``"dask"`` (a local cluster), a scheduler address (``"tcp://host:8786"``: a client connects to it), a
    :class:`distributed.Client` or an :class:`Executor` (returned as is)."""
    if isinstance(executor, Executor):
        return executor
    if isinstance(executor, str):
        if "://" in executor:
            from distributed import Client
            ex = Executor(client=Client(executor), workers=workers, progress=progress)
            ex._own_client = True         # our connection; closing it leaves the remote cluster running
            return ex
        return Executor(executor, workers=workers, progress=progress)
    if type(executor).__name__ == "Client" and hasattr(executor, "map") and hasattr(executor, "gather"):
        return Executor(client=executor, workers=workers, progress=progress)
    raise GearoptInputError(f"executor={executor!r} must be one of {KINDS}, a scheduler address, a "
                            f"dask.distributed.Client or a gearopt Executor")


@contextmanager
def using_executor(executor: "str | Executor | Any" = "serial", *, workers: int | None = None,
                   progress: bool | None = None) -> Iterator[Executor]:
    """:func:`get_executor` for the length of a ``with`` block: what it started (a pool, a local cluster, a
    connection) is closed at the end; an :class:`Executor` or a client given by the caller stays open."""
    ex = get_executor(executor, workers=workers, progress=progress)
    try:
        yield ex
    finally:
        if ex is not executor:
            ex.close()


def _dumps(fn: Callable[[Any], Any], item: Any) -> bytes:
    """``(fn, item)`` serialised by cloudpickle inside a CasADi pickle context (CasADi SX graphs -- e.g. the
    integrator a timing model built in this process -- pickle only inside one; the payload carries its own)."""
    import casadi as ca
    import cloudpickle

    with ca.global_pickle_context():
        return cloudpickle.dumps((fn, item))


def _call(payload: bytes) -> Any:
    """A worker task: ``fn(item)`` from a :func:`_dumps` payload (loaded by the standard unpickler)."""
    import casadi as ca

    with ca.global_unpickle_context():
        fn, item = pickle.loads(payload)
    return fn(item)


def _process_context():
    """``fork`` (workers start at once, nothing re-imported) when this process runs no other thread and the platform
    forks; else :func:`clean_process_context` (safe with threads -- a Dask client, a CasADi thread pool)."""
    others = [t for t in threading.enumerate()
              if t is not threading.current_thread() and type(t).__name__ != "TMonitor"]   # tqdm's idle monitor
    if "fork" in multiprocessing.get_all_start_methods() and not others:
        return multiprocessing.get_context("fork")
    return clean_process_context()


START_METHOD_ENV = "GEAROPT_START_METHOD"
"""Environment variable: ``spawn`` starts worker processes by ``spawn`` instead of the forkserver
(:func:`clean_process_context`)."""


def process_pool(max_workers: int, context=None, *, initializer: Callable | None = None,
                 initargs: tuple = ()) -> ProcessPoolExecutor:
    """A :class:`~concurrent.futures.ProcessPoolExecutor` of ``max_workers`` started from ``context`` (default
    :func:`clean_process_context`) whose workers run with this process's environment as it is now: a forkserver's
    workers would otherwise see the environment of the moment the server started (``GEAROPT_THREADS``, the compile
    cache's settings, a test's ``GEAROPT_FIGURE_CHECKS`` set later). ``initializer(*initargs)`` runs in each worker
    after that (a module-level function)."""
    if isinstance(max_workers, bool) or not isinstance(max_workers, int) or max_workers < 1:
        raise GearoptInputError(f"process_pool: max_workers={max_workers!r} must be an integer >= 1")
    if initializer is not None and not callable(initializer):
        raise GearoptInputError(f"process_pool: initializer={initializer!r} must be callable or None")
    return ProcessPoolExecutor(max_workers=max_workers, mp_context=context or clean_process_context(),
                               initializer=_with_environment, initargs=(dict(os.environ), initializer, initargs))


def _with_environment(environment: dict, initializer: Callable | None, initargs: tuple) -> None:
    """Worker initializer of :func:`process_pool`: the parent's environment, then ``initializer``."""
    os.environ.clear()
    os.environ.update(environment)
    if initializer is not None:
        initializer(*initargs)


#: Modules the forkserver imports besides the program's gearopt modules: SciPy's optimisers and statistics, which
#: gearopt imports only where it uses them (about 0.8 s at every ``import gearopt`` otherwise) but which a worker's
#: solves and samples need -- imported once in the server, not once per worker.
WORKER_PRELOAD = ("scipy.optimize", "scipy.stats")


def clean_process_context():
    """The start method for worker processes of a process that may hold threads (solver or plotting threads, which
    a plain ``fork`` would copy mid-flight): ``forkserver`` where the platform has it -- one fresh server process
    imports the program's gearopt modules once and every worker is forked from it, so a job's side processes and
    figure writer do not each import it again (about 3 CPU-s each for the main job) -- else ``spawn`` (each worker
    a fresh interpreter). ``GEAROPT_START_METHOD=spawn`` forces ``spawn``.

    With the forkserver, a worker runs the code and the import-time settings of the moment the server started (at
    the first worker of the first pool; it stays up, idle, until this process exits): a gearopt module edited
    later, or a variable a library reads once at import (``OMP_NUM_THREADS``, ``OPENBLAS_NUM_THREADS``,
    ``MPLCONFIGDIR``) set later, reaches new workers only under ``spawn``. The environment itself is passed to each
    pool's workers by :func:`process_pool`. Modules the program asked the forkserver to preload are kept."""
    method = os.environ.get(START_METHOD_ENV, "").strip().lower()
    if method not in ("", "forkserver", "spawn"):
        raise GearoptInputError(f"{START_METHOD_ENV}={method!r} must be 'forkserver' or 'spawn'")
    if method == "spawn" or "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    # the server imports what this program has imported of gearopt (and so numpy, CasADi, pandas ...) before its
    # first fork (Python 3.11's forkserver does not preload __main__ itself) besides what the program asked for;
    # set before the server starts, which is at the first worker of the first pool
    server = getattr(sys.modules.get("multiprocessing.forkserver"), "_forkserver", None)
    asked = [m for m in getattr(server, "_preload_modules", None) or [] if isinstance(m, str)]
    ours = sorted(name for name in sys.modules if name.split(".")[0] == "gearopt")
    context.set_forkserver_preload(list(dict.fromkeys(asked + ours + list(WORKER_PRELOAD))))
    return context


def helper_process_ids() -> set[int]:
    """Process ids of multiprocessing's own idle helpers of this process while they run: the forkserver the
    workers are forked from (:func:`clean_process_context`) and the resource tracker. Both compute nothing and end
    with this process; a later pool of this process needs them."""
    pids = set()
    for module, attribute, field in (("multiprocessing.forkserver", "_forkserver", "_forkserver_pid"),
                                     ("multiprocessing.resource_tracker", "_resource_tracker", "_pid")):
        pid = getattr(getattr(sys.modules.get(module), attribute, None), field, None)
        if isinstance(pid, int):
            pids.add(pid)
    return pids


class _NoBar:
    def update(self, n: int) -> None:
        pass

    def close(self) -> None:
        pass


def _progress_bar(total: int, desc: str, progress: bool | None):
    if progress is False or total <= 1:
        return _NoBar()
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc or None, disable=None if progress is None else not progress, leave=False)


__all__ = ["Executor", "get_executor", "using_executor", "KINDS", "process_pool", "clean_process_context",
           "helper_process_ids", "START_METHOD_ENV"]
