"""Figure files written in the background: a long report renders its PNGs in a worker process while the caller
goes on computing.

Rendering a figure (layout, text, rasterising: 0.2-0.6 s for the report's multi-panel figures) is pure output work
that nothing downstream reads. Inside :func:`background_figures`, :func:`save` pickles the finished figure, closes
it and hands the pickle to one worker process that renders and writes it; leaving the block waits for every file
and re-raises the first error of a worker. Outside the block :func:`save` writes at once. The files are the same
either way (the worker unpickles the very figure the caller built).
"""

from __future__ import annotations

import contextlib
import json
import os
import pickle
from concurrent.futures import Future, ProcessPoolExecutor
from pathlib import Path

from ..errors import GearoptInputError
from ..executor import process_pool

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

_POOL: ProcessPoolExecutor | None = None
_PENDING: list[Future] = []
DEFAULT_DPI = 120
_DPI = DEFAULT_DPI          # resolution of a figure saved without one (background_figures(dpi=...) sets it)


CHECKS_ENV = "GEAROPT_FIGURE_CHECKS"
"""Environment variable: a file path; when set, every figure written (in this process or a worker) is checked by
:func:`gearopt.report.figure_checks.readability_issues` first and one JSON line appended to that file: ``file``,
``issues``, ``figure_legends`` (legends of the figure), ``axes_legends`` (of its axes), ``suptitle``. The tests
set it to check every figure a script writes, whichever process draws it."""


def _write(fig, path: str | Path, dpi: int) -> None:
    log = os.environ.get(CHECKS_ENV)
    if log:
        from .figure_checks import readability_issues

        record = {"file": Path(path).name, "issues": readability_issues(fig),
                  "figure_legends": len(fig.legends),
                  "axes_legends": sum(a.get_legend() is not None for a in fig.axes),
                  "suptitle": bool(fig.get_suptitle()) if hasattr(fig, "get_suptitle") else False}
        with open(log, "a", encoding="utf-8") as f:     # one short line per write: appends do not interleave
            f.write(json.dumps(record) + "\n")
    fig.savefig(path, dpi=dpi)
    plt.close(fig)


def _render(payload: bytes, path: str, dpi: int) -> str:
    _write(pickle.loads(payload), path, dpi)
    return path


def save(fig, path: str | Path, dpi: int | None = None) -> Path:
    """Write ``fig`` to ``path`` (directories created) and close it; inside :func:`background_figures` the
    rendering happens in the worker and the file exists when the block ends. ``dpi``: default
    :data:`DEFAULT_DPI`, or the block's."""
    dpi = _DPI if dpi is None else dpi
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if _POOL is None:
        _write(fig, path, dpi)
        return path
    payload = pickle.dumps(fig)
    plt.close(fig)
    _PENDING.append(_POOL.submit(_render, payload, str(path), dpi))
    return path


def _build_render(builder, args: tuple, kwargs: dict, path: str, dpi: int) -> str:
    _write(builder(*args, **kwargs), path, dpi)
    return path


def plot_later(builder, path: str | Path, *args, dpi: int | None = None, **kwargs) -> Path:
    """Write the figure ``builder(*args, **kwargs)`` to ``path``; inside :func:`background_figures` the worker
    builds it too (then ``builder`` must be a module-level function and its arguments picklable: the caller pays
    for neither the plotting nor the rendering). Outside the block it is built and written at once."""
    dpi = _DPI if dpi is None else dpi
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if _POOL is None:
        return save(builder(*args, **kwargs), path, dpi)
    _PENDING.append(_POOL.submit(_build_render, builder, args, kwargs, str(path), dpi))
    return path


@contextlib.contextmanager
def background_figures(enabled: bool = True, *, dpi: int | None = None):
    """Render the figures saved inside the block in one worker process (``enabled=False``: at once, in this
    process). The worker is started by :func:`gearopt.executor.process_pool` (no fork of a process holding solver
    threads; this process's environment) and needs only matplotlib. Leaving the block waits for every figure; a
    failed one raises here. ``dpi``: the resolution of the figures saved in the block without one (e.g. lower for a
    quick run)."""
    global _POOL, _DPI
    if dpi is not None:
        if isinstance(dpi, bool) or not isinstance(dpi, int) or not 20 <= dpi <= 1200:
            raise GearoptInputError(f"dpi={dpi!r} must be an integer in [20, 1200]")
    previous_dpi = _DPI
    _DPI = previous_dpi if dpi is None else dpi
    if not enabled or _POOL is not None:
        try:
            yield
        finally:
            _DPI = previous_dpi
        return
    _POOL = process_pool(1)
    failed = False
    try:
        yield
    except BaseException:               # an error or a signal in the block: the figures are not waited for
        failed = True
        raise
    finally:
        _DPI = previous_dpi
        pool, pending = _POOL, list(_PENDING)
        _POOL = None
        _PENDING.clear()
        if failed:
            pool.shutdown(wait=False, cancel_futures=True)
        else:
            try:
                for future in pending:
                    future.result()
            finally:
                pool.shutdown(wait=True)


__all__ = ["save", "plot_later", "background_figures"]
