"""The validation layer of gearopt's public surface: every entry point checks its inputs with these helpers, and
every public result that could hold a NaN is checked on the way out.

The contract (one rule for the whole package):

- A number must be a real number: ``str`` (numeric strings included), ``bool``, ``None`` and complex values are
  rejected, so ``"3"`` never slips through validation to fail later in arithmetic.
- NaN is a violation everywhere. Infinities are rejected unless the caller says ``allow_inf=True`` where an infinity
  means something (an unbounded limit, "never released"). Magnitudes beyond :data:`MAX_MAGNITUDE` are rejected as
  implausible in every unit gearopt uses, so ``1e300`` gives a named error instead of an ``OverflowError`` or a
  silent ``inf`` downstream.
- Counts are integers (``2.5`` slices is an error; ``3.0`` is accepted as 3).
- Per-gear arguments are a scalar (both gears) or a 2-tuple (gear 1, gear 2); name tuples have the right length.
- CasADi symbols pass through untouched: the caller imposes them as NLP constraints instead.

Every failure raises :class:`~gearopt.errors.GearoptInputError` (a ``ValueError``) naming the parameter, its value,
the violated limit and the unit. A public result holding NaN raises :class:`~gearopt.errors.NonFiniteResultError`
naming the quantity and the inputs that led there (:func:`check_result`).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping, Sequence

import numpy as np

from . import numerics
from .errors import GearoptInputError, NonFiniteResultError

#: Largest magnitude any gearopt input may have, in any of its units (mm, um, N m, N/m, kg m^2, MPa, rpm ...).
#: Physical inputs stay many orders below it; beyond it float arithmetic in the models overflows.
MAX_MAGNITUDE = 1e15


def _kind_error(name: str, value, error) -> GearoptInputError:
    kind = type(value).__name__
    return error(f"{name}={value!r} is not a number (got {kind}; give a real number, not a string, bool or None)")


def as_number(name: str, value, *, error: type[GearoptInputError] = GearoptInputError) -> float:
    """``value`` as a float, rejecting strings, bools, ``None``, complex numbers and non-scalars by name."""
    if type(value) is float:                            # the common case first (every check_range of a model)
        return value
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None or isinstance(value, complex):
        raise _kind_error(name, value, error)
    if isinstance(value, np.ndarray) and value.dtype.kind not in "iuf":
        raise _kind_error(name, value, error)
    if isinstance(value, (tuple, list)):  # even of length 1: arithmetic on a sequence fails later
        raise error(f"{name}={value!r:.80} must be a scalar (got a {type(value).__name__})")
    try:
        return numerics.to_float(value)
    except GearoptInputError:
        raise error(f"{name}={value!r} must be a scalar (got shape {np.shape(value)})") from None
    except (TypeError, ValueError, RuntimeError, OverflowError):
        raise _kind_error(name, value, error) from None


def check_range(name: str, value: float, low: float | None = None, high: float | None = None, *,
                low_inclusive: bool = True, high_inclusive: bool = True, unit: str = "",
                allow_inf: bool = False, error: type[GearoptInputError] = GearoptInputError) -> None:
    """Raise ``error`` naming ``name``, ``value``, the violated limit and ``unit`` when a numeric value is not a real
    number, is NaN, is infinite (unless ``allow_inf``), exceeds :data:`MAX_MAGNITUDE`, or lies outside
    [``low``, ``high``] (open ends with ``*_inclusive=False``).

    Symbolic (CasADi) values are not checked here; the caller reports those as constraints instead.
    """
    if numerics.is_symbolic(value):
        return
    v = as_number(name, value, error=error)
    u = f" {unit}" if unit else ""
    if v != v:
        raise error(f"{name}={value!r} is NaN: a real number is required")
    for lim_name, lim in (("low", low), ("high", high)):
        if lim is not None and lim != lim:
            raise error(f"the {lim_name} limit of {name} is NaN: a real limit is required")
    if math.isinf(v):
        if not allow_inf:
            raise error(f"{name}={v}{u} is infinite: a finite number is required"
                        + (f" (limits {_limits_text(low, high, u)})" if low is not None or high is not None else ""))
    elif abs(v) > MAX_MAGNITUDE:
        raise error(f"{name}={v:g}{u} is beyond the plausible magnitude {MAX_MAGNITUDE:g}{u}")
    if low is not None and (v < low or (v == low and not low_inclusive)):
        rel = ">=" if low_inclusive else ">"
        raise error(f"{name}={v:g}{u} is below its limit: must be {rel} {low:g}{u}")
    if high is not None and (v > high or (v == high and not high_inclusive)):
        rel = "<=" if high_inclusive else "<"
        raise error(f"{name}={v:g}{u} exceeds its limit: must be {rel} {high:g}{u}")


def _limits_text(low, high, u) -> str:
    lo = f"{low:g}{u}" if low is not None else "-inf"
    hi = f"{high:g}{u}" if high is not None else "+inf"
    return f"[{lo}, {hi}]"


def check_int(name: str, value, low: int | None = None, high: int | None = None, *,
              error: type[GearoptInputError] = GearoptInputError) -> int:
    """An integer count in [``low``, ``high``]: integral floats (``3.0``) are accepted, ``2.5``, bools, strings,
    NaN and infinities are not. Returns the ``int``."""
    if isinstance(value, numbers.Integral) and not isinstance(value, (bool, np.bool_)):
        v = int(value)
    else:
        f = as_number(name, value, error=error)
        if not math.isfinite(f) or not f.is_integer():
            raise error(f"{name}={value!r} must be an integer count")
        v = int(f)
    if low is not None and v < low:
        raise error(f"{name}={v} is below its limit: must be >= {low}")
    if high is not None and v > high:
        raise error(f"{name}={v} exceeds its limit: must be <= {high}")
    return v


def per_gear(value, name: str) -> tuple:
    """A per-gear argument as a 2-tuple (gear 1, gear 2): a scalar applies to both gears; any other length raises
    ``GearoptInputError`` naming the parameter."""
    if isinstance(value, (tuple, list, np.ndarray)) and not numerics.is_casadi(value):
        if len(value) != 2:
            raise GearoptInputError(f"{name}={value!r} must be a scalar or a 2-tuple (gear 1, gear 2)")
        return tuple(value)
    return (value, value)


def check_per_gear(name: str, value, low: float | None = None, high: float | None = None, **kw) -> tuple:
    """:func:`per_gear` with :func:`check_range` on both entries (named ``name[0]``, ``name[1]``)."""
    pair = per_gear(value, name)
    for i, v in enumerate(pair):
        check_range(f"{name}[{i}]", v, low, high, **kw)
    return pair


def check_names(name: str, value, count: int = 2) -> tuple[str, ...]:
    """A tuple of ``count`` non-empty strings (e.g. the two gear names)."""
    if isinstance(value, str) or not isinstance(value, Sequence) or len(value) != count:
        raise GearoptInputError(f"{name}={value!r} must be a tuple of {count} names")
    for i, v in enumerate(value):
        if not isinstance(v, str) or not v:
            raise GearoptInputError(f"{name}[{i}]={v!r} must be a non-empty string")
    return tuple(value)


def check_choice(name: str, value, choices) -> None:
    """``value`` must be one of ``choices`` (compared with ``==``; bools are not taken for 0/1)."""
    if isinstance(value, (bool, np.bool_)) and not any(isinstance(c, bool) for c in choices):
        raise GearoptInputError(f"{name}={value!r} must be one of {tuple(choices)!r}")
    def same(c) -> bool:
        try:
            return bool(value == c)
        except Exception:  # noqa: BLE001 - arrays or odd types compare badly: they are not a choice either
            return False

    ok = any(same(c) for c in choices)
    if not ok:
        raise GearoptInputError(f"{name}={value!r} must be one of {tuple(choices)!r}")


def check_array(name: str, value, low: float | None = None, high: float | None = None, *, shape=None,
                min_size: int = 0, allow_inf: bool = False, unit: str = "") -> np.ndarray:
    """A numeric array (list, tuple or ndarray; CasADi ``DM`` allowed) as a float ndarray, every element finite
    (unless ``allow_inf``) and in [``low``, ``high``], of ``shape`` if given (``None`` entries match any length) and
    at least ``min_size`` elements. Symbolic values are returned unchanged."""
    if numerics.is_symbolic(value):
        return value
    if isinstance(value, (str, bytes)) or value is None:
        raise _kind_error(name, value, GearoptInputError)
    try:
        if numerics.is_casadi(value):
            arr = np.asarray(value.full(), dtype=float).squeeze()
        else:
            raw = np.asarray(value)
            if raw.dtype.kind not in "iuf":
                raise TypeError
            arr = raw.astype(float)
    except (TypeError, ValueError):
        raise GearoptInputError(f"{name} must be an array of real numbers (got {value!r:.80})") from None
    if shape is not None:
        if arr.ndim != len(shape) or any(s is not None and s != a for s, a in zip(shape, arr.shape)):
            want = "x".join("n" if s is None else str(s) for s in shape)
            raise GearoptInputError(f"{name} has shape {arr.shape}: expected {want}")
    if arr.size < min_size:
        raise GearoptInputError(f"{name} has {arr.size} elements: at least {min_size} required")
    if arr.size:
        flat = arr.reshape(-1)
        bad = np.flatnonzero(~np.isfinite(flat) if not allow_inf else np.isnan(flat))
        if bad.size:
            check_range(f"{name}[{int(bad[0])}]", float(flat[bad[0]]), low, high, unit=unit, allow_inf=allow_inf)
        for idx in (int(np.argmin(flat)), int(np.argmax(flat))):
            check_range(f"{name}[{idx}]", float(flat[idx]), low, high, unit=unit, allow_inf=allow_inf)
    return arr


def _describe(inputs: Mapping | None) -> str:
    if not inputs:
        return ""
    parts = []
    for k, v in inputs.items():
        text = repr(v)
        parts.append(f"{k}={text if len(text) <= 60 else text[:57] + '...'}")
    return " (inputs: " + ", ".join(parts) + ")"


def check_result(quantity: str, value, inputs: Mapping | None = None, *, allow_inf: bool = False):
    """Return ``value`` if it holds no NaN (and no infinity unless ``allow_inf``); otherwise raise
    :class:`~gearopt.errors.NonFiniteResultError` naming ``quantity`` and the ``inputs`` that led there.

    Scalars, arrays, tuples/lists and dicts (checked per key, named ``quantity.key``) are accepted; strings, ``None``
    and CasADi symbols pass through."""
    if isinstance(value, float):  # fast path: most results are plain floats
        if value == value and (allow_inf or value - value == 0.0):
            return value
        _raise_nonfinite(quantity, np.asarray(value), inputs, allow_inf)
    if isinstance(value, Mapping):
        for k, v in value.items():
            check_result(f"{quantity}.{k}", v, inputs, allow_inf=allow_inf)
        return value
    if value is None or isinstance(value, (str, bytes, bool)) or numerics.is_symbolic(value):
        return value
    if isinstance(value, (tuple, list)):
        if all(type(v) is float and v - v == 0.0 for v in value):
            return value
        for i, v in enumerate(value):
            check_result(f"{quantity}[{i}]", v, inputs, allow_inf=allow_inf)
        return value
    try:
        arr = np.asarray(value.full() if numerics.is_casadi(value) else value, dtype=float)
    except (TypeError, ValueError):
        return value
    bad = np.isnan(arr) if allow_inf else ~np.isfinite(arr)
    if np.any(bad):
        _raise_nonfinite(quantity, arr, inputs, allow_inf)
    return value


def _raise_nonfinite(quantity: str, arr: np.ndarray, inputs, allow_inf: bool):
    bad = np.isnan(arr) if allow_inf else ~np.isfinite(arr)
    what = "NaN" if np.any(np.isnan(arr)) else "an infinity"
    where = f" at index {np.unravel_index(int(np.argmax(bad)), arr.shape)}" if arr.ndim else ""
    raise NonFiniteResultError(f"{quantity} is {what}{where}: the model has no finite answer here"
                               f"{_describe(inputs)}")


__all__ = ["MAX_MAGNITUDE", "as_number", "check_range", "check_int", "per_gear", "check_per_gear",
           "check_names", "check_choice", "check_array", "check_result"]
