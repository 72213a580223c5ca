"""Range checks that also accept numpy arrays (every element must pass); CasADi symbols are not checked."""

from __future__ import annotations

import numpy as np

from .. import numerics as nm
from ..validation import check_range


def check_range_any(name: str, value, low=None, high=None, **kw) -> None:
    """:func:`gearopt.validation.check_range` for a scalar, or for the smallest and largest element of an array."""
    if isinstance(value, (np.ndarray, list, tuple)) and not nm.is_casadi(value):
        arr = np.asarray(value, dtype=float).reshape(-1)
        if arr.size == 0:
            return
        bad = arr[~np.isfinite(arr)]
        check_range(name, bad[0] if bad.size else float(np.min(arr)), low, high, **kw)
        check_range(name, float(np.max(arr)), low, high, **kw)
        return
    check_range(name, value, low, high, **kw)
