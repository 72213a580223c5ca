"""Validity the loaded tooth contact analyses need, checked before a layout is built (numeric pairs).

- Every tip circle above its base circle: the involute starts at the base circle (ISO 21771 5.2); a tip below it
  has no involute flank to contact.
- Roll lengths of the start and end of active profile >= 0: a tip reaching past the mating base circle's tangent
  point interferes with the mating root; the LTCA's involute contact does not model it.
- Transverse contact ratio >= 1: otherwise some mesh position carries no tooth pair.
- A layout of at most :data:`MAX_LTCA_SPRINGS` springs (positions x tooth pairs x slices): huge tips give contact
  ratios of tens and a layout that would not fit in memory or time.
"""

from __future__ import annotations

import math

from ..errors import GearoptInputError, GeometryError
from ..validation import check_choice, check_range

#: Largest LTCA layout (positions x tooth pairs x slices) solved without complaint: ~0.5 GB of float arrays.
MAX_LTCA_SPRINGS = 5_000_000


def check_ltca_inputs(pair, driving_gear, E_MPa, poisson, bulk_temperature_C, friction_coefficient) -> None:
    """Secondary inputs of :func:`ltca` and the validity the exact LTCA needs: every tip above its base circle
    (the involute starts there, ISO 21771 5.2) and a transverse contact ratio of at least 1 (otherwise some mesh
    position carries no pair)."""
    check_choice("driving_gear", driving_gear, (1, 2))
    check_range("E_MPa", E_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    check_range("poisson", poisson, 0.0, 0.5, low_inclusive=False, high_inclusive=False)
    check_range("bulk_temperature_C", bulk_temperature_C, -273.15, 1000.0, unit="degC")
    check_range("friction_coefficient", friction_coefficient, 0.0, 1.0, high_inclusive=False)
    if pair.is_symbolic:
        return  # the layout refuses symbolic macro geometry with its own message
    g = pair.geometry()
    for i in range(2):
        d_a, d_b = g["tip_diameter_mm"][i], g["base_diameter_mm"][i]
        if not d_a > d_b:
            raise GeometryError(f"{pair._label()}: the LTCA needs the tip above the base circle (ISO 21771 5.2): "
                                f"gear {i + 1} tip diameter {d_a:.4f} mm <= base diameter {d_b:.4f} mm")
    for key in ("sap_roll_length_mm", "eap_roll_length_mm"):
        if min(g[key]) < 0.0:
            raise GeometryError(f"{pair._label()}: {key}={g[key]} is negative: a tip reaches past the mating base "
                                f"circle's tangent point (interference), outside the LTCA's involute contact")
    eps = g["transverse_contact_ratio"]
    if eps < 1.0:
        raise GeometryError(f"{pair._label()}: transverse_contact_ratio={eps:.4f} is below 1: the LTCA needs "
                            f"continuous contact")


def check_ltca_size(pair, positions: int, slices: int) -> None:
    """Raise :class:`GearoptInputError` naming positions and slices when the layout would exceed its limit."""
    if pair.is_symbolic:
        return
    g = pair.geometry()
    pairs = math.ceil(g["total_contact_ratio"]) + 3
    size = positions * pairs * slices
    if size > MAX_LTCA_SPRINGS:
        raise GearoptInputError(f"LTCA size positions x tooth pairs x slices = {positions} x {pairs} x {slices} = "
                                f"{size} exceeds its limit MAX_LTCA_SPRINGS={MAX_LTCA_SPRINGS} (total contact ratio "
                                f"{g['total_contact_ratio']:.3g}); reduce positions or slices")


__all__ = ["MAX_LTCA_SPRINGS", "check_ltca_inputs", "check_ltca_size"]
