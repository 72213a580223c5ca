"""Range checks that also accept numpy arrays (every element must pass); CasADi symbols are not checked."""

from __future__ import annotations

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..validation import check_array, check_range


def check_range_any(name: str, value, low=None, high=None, **kw) -> None:
    """:func:`gearopt.validation.check_range` for a scalar, or for the smallest and largest element of an array."""
    if isinstance(value, (list, tuple)):  # arithmetic on a tuple fails later: arrays must be numpy arrays
        raise GearoptInputError(f"{name}={value!r:.80} must be a number or a numpy array, not a {type(value).__name__}")
    if isinstance(value, np.ndarray) and not nm.is_casadi(value):
        arr = check_array(name, value, allow_inf=True)  # element type; finiteness by check_range below
        arr = arr.reshape(-1)
        if arr.size == 0:
            return
        bad = arr[~np.isfinite(arr)]
        check_range(name, bad[0] if bad.size else float(np.min(arr)), low, high, **kw)
        check_range(name, float(np.max(arr)), low, high, **kw)
        return
    check_range(name, value, low, high, **kw)
