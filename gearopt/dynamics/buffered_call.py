"""Calls of CasADi Functions on numpy arrays without conversion, through ``casadi.FunctionBuffer``.

A plain call ``f(x0=..., p=...)`` converts every numpy argument to a ``casadi.DM`` and every result back with
``.full()``; both go element by element through SWIG, about 75 ns per entry (measured here with CasADi 3.8). One
cycle of the default train's lash simulation moves 46 states x 2880 output points out of the integrator, then those
and the parameters (59 x 2880) into the output function and 59 x 2880 outputs back: 30-40 ms of conversions per
cycle, more than the integrator spends evaluating its right-hand side and Jacobian (about 18 ms at 4 700 steps).
:class:`BufferedFunction` hands CasADi the numpy memory itself (``FunctionBuffer.set_arg``/``set_res`` with a
memoryview of a contiguous float64 array, column-major as CasADi stores a dense matrix), so the same call costs
the evaluation alone. Results are the same numbers as the plain call's (tested in
``tests/dynamics/test_dynamics_buffered_call.py``).

Only dense inputs and outputs are supported (every nonzero of the sparsity is an entry of the matrix). Inputs that
are not named are passed as null pointers, which CasADi reads as zeros; outputs that are not named are not
computed. A failing evaluation raises the same ``RuntimeError`` as a plain call. Results are column-major
(Fortran-ordered) arrays, as CasADi writes them: the same values as ``.full()``, whose arrays are row-major; a sum
along an axis may round differently between the two layouts (``np.ascontiguousarray`` first where that matters).

A :class:`BufferedFunction` holds one checked-out memory of the Function (not thread-safe: make one per thread or
per run; making one costs about 0.1 ms). Its :meth:`~BufferedFunction.stats` are those of that memory, with the
evaluation counters and timers of the last call alone (CasADi accumulates them over the calls of one memory,
and a released memory is handed to the next buffer with its totals).
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca
import numpy as np

_CUMULATIVE_PREFIXES = ("n_call_", "t_wall_", "t_proc_")


class BufferedFunction:
    """``fun`` evaluated on numpy arrays through a ``casadi.FunctionBuffer`` (module docstring).

    ``inputs``/``outputs``: names (or indices) of the inputs given to :meth:`__call__`, in that order, and of the
    outputs it returns (each a float64 array of the output's shape, freshly allocated per call)."""

    def __init__(self, fun: ca.Function, inputs: Sequence[str | int], outputs: Sequence[str | int]):
        self.fun = fun
        self._in = [fun.index_in(i) if isinstance(i, str) else int(i) for i in inputs]
        self._out = [fun.index_out(i) if isinstance(i, str) else int(i) for i in outputs]
        for i in self._in:
            if not fun.sparsity_in(i).is_dense():
                raise ValueError(f"input {fun.name_in(i)!r} of {fun.name()!r} is sparse; BufferedFunction needs "
                                 f"dense inputs")
        for i in self._out:
            if not fun.sparsity_out(i).is_dense():
                raise ValueError(f"output {fun.name_out(i)!r} of {fun.name()!r} is sparse; BufferedFunction needs "
                                 f"dense outputs")
        self._sizes_in = [fun.nnz_in(i) for i in self._in]
        self._shapes_out = [(fun.size1_out(i), fun.size2_out(i)) for i in self._out]
        self._buffer, self._eval = fun.buffer()
        self._totals: dict = {}
        self._last: dict = {}
        try:  # the checked-out memory may have been used before: its counters start from there
            self._totals = {k: v for k, v in dict(self._buffer.stats()).items()
                            if k.startswith(_CUMULATIVE_PREFIXES) and isinstance(v, (int, float))}
        except RuntimeError:  # a fresh memory (no statistics yet) or a Function without them
            pass

    def __call__(self, *args) -> list[np.ndarray]:
        """Evaluate on ``args`` (array-likes of the inputs' sizes, matrices read column-major: pass a matrix as
        an array of its shape); returns the outputs as arrays of their shapes."""
        if len(args) != len(self._in):
            raise ValueError(f"{self.fun.name()!r} takes {len(self._in)} buffered inputs, got {len(args)}")
        keep = []  # the memory CasADi reads must live until the evaluation ends
        for i, size, a in zip(self._in, self._sizes_in, args):
            flat = np.ascontiguousarray(np.asarray(a, dtype=float).ravel(order="F"))
            if flat.size != size:
                raise ValueError(f"input {self.fun.name_in(i)!r} of {self.fun.name()!r} has {size} entries, got "
                                 f"{flat.size}")
            self._buffer.set_arg(i, memoryview(flat))
            keep.append(flat)
        outs = []
        for i, (rows, cols) in zip(self._out, self._shapes_out):
            flat = np.empty(rows * cols)
            self._buffer.set_res(i, memoryview(flat))
            outs.append(flat.reshape((rows, cols), order="F"))
        self._eval()
        self._update_stats()
        return outs

    def _update_stats(self) -> None:
        try:
            stats = dict(self._buffer.stats())
        except RuntimeError:  # a Function without statistics
            self._last = {}
            return
        last = {}
        for key, value in stats.items():
            if key.startswith(_CUMULATIVE_PREFIXES) and isinstance(value, (int, float)):
                last[key] = value - self._totals.get(key, 0)
                self._totals[key] = value
            else:
                last[key] = value
        self._last = last

    def stats(self) -> dict:
        """Statistics of the last call (module docstring; empty before the first call)."""
        return dict(self._last)


__all__ = ["BufferedFunction"]
