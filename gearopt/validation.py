"""Validation of public inputs: range checks that name the parameter, its value and the violated limit, and the
per-gear 2-tuple convention. Symbols (CasADi) pass through untouched; the caller imposes them as constraints."""

from __future__ import annotations

from . import numerics
from .errors import GearoptInputError


def check_range(name: str, value: float, low: float | None = None, high: float | None = None, *,
                low_inclusive: bool = True, high_inclusive: bool = True, unit: str = "",
                error: type[GearoptInputError] = GearoptInputError) -> None:
    """Raise ``error`` naming ``name``, ``value`` and the violated limit when a numeric value is out of range.

    Symbolic (CasADi) values are not checked here; the caller reports those as constraints instead.
    """
    if numerics.is_symbolic(value):
        return
    try:
        v = numerics.to_float(value)
    except (TypeError, ValueError, RuntimeError):
        raise error(f"{name}={value!r} is not a number") from None
    u = f" {unit}" if unit else ""
    if v != v:
        raise error(f"{name}={value!r} is NaN")
    if low is not None and (v < low or (v == low and not low_inclusive)):
        rel = ">=" if low_inclusive else ">"
        raise error(f"{name}={v:g}{u} is below its limit: must be {rel} {low:g}{u}")
    if high is not None and (v > high or (v == high and not high_inclusive)):
        rel = "<=" if high_inclusive else "<"
        raise error(f"{name}={v:g}{u} exceeds its limit: must be {rel} {high:g}{u}")


def per_gear(value, name: str) -> tuple:
    """A per-gear argument as a 2-tuple (gear 1, gear 2): a scalar applies to both gears; any other length raises
    ``GearoptInputError`` naming the parameter."""
    if isinstance(value, (tuple, list)):
        if len(value) != 2:
            raise GearoptInputError(f"{name}={value!r} must be a scalar or a 2-tuple (gear 1, gear 2)")
        return tuple(value)
    return (value, value)
