"""Geometric validity the ISO 6336 ratings assume, checked before a numeric rating is computed.

- ISO 6336-1:2006 / ISO 6336-2:2006 clause 1 (scope): the formulas hold for transverse contact ratios
  1 <= eps_alpha < 2.5 (the pitting part states the virtual contact ratio limit 2.5 explicitly); below 1 there is no
  continuous contact, above 2.5 Z_eps = sqrt((4 - eps_alpha)/3) and the single-contact factors leave their range
  (Z_eps is NaN past 4).
- Every tip circle must lie above its base circle (the involute starts at the base circle; ISO 21771 5.2).
- ISO 6336-3 method B's critical section assumes a root generated without undercut (clause 6.2; the 30 deg
  tangent construction of a trochoid that undercuts the involute is not covered): a warning, not an error, as a
  slight undercut changes the result little.

Symbolic pairs are not checked here: impose ``GearPair.constraints()`` in the NLP instead.
"""

from __future__ import annotations

import warnings

from .. import numerics as nm
from ..errors import GeometryError
from ..validation import check_result

CONTACT_RATIO_RANGE = (1.0, 2.5)


class RatingValidityWarning(UserWarning):
    """A rating was computed outside the validity or an assumption a clause of its standard states (the value is
    still computed; it is then an approximation)."""


def check_rating_validity(pair, standard: str, *, undercut: bool = False) -> None:
    """Raise :class:`GeometryError` naming the clause when a numeric ``pair`` lies outside the validity of
    ``standard`` (a label such as ``"ISO 6336-2:2006"``): contact ratio range, tip above base circle and, with
    ``undercut=True``, no undercut (a :class:`RatingValidityWarning` only: the result is then an approximation)."""
    if pair.is_symbolic:
        return
    g = pair.geometry()
    label = f"{pair._label()}: {standard}"
    for i in range(2):
        d_a, d_b = g["tip_diameter_mm"][i], g["base_diameter_mm"][i]
        if not d_a > d_b:
            raise GeometryError(f"{label} needs the tip above the base circle (ISO 21771 5.2): gear {i + 1} tip "
                                f"diameter {d_a:.4f} mm <= base diameter {d_b:.4f} mm")
    eps = g["transverse_contact_ratio"]
    lo, hi = CONTACT_RATIO_RANGE
    if not lo <= eps < hi:
        raise GeometryError(f"{label} is valid for transverse contact ratios {lo:g} <= eps_alpha < {hi:g} "
                            f"(ISO 6336-1/-2 clause 1, scope): eps_alpha = {eps:.4f}")
    if undercut:
        for i in range(2):
            x, x_min = nm.to_float(pair.profile_shifts[i]), g["undercut_limit_profile_shift"][i]
            if x < x_min - 1e-9:
                warnings.warn(f"{label} assumes no undercut (ISO 6336-3 clause 6.2): gear {i + 1} profile "
                              f"shift x={x:.4f} is below the undercut limit {x_min:.4f}; the root stress is an "
                              f"approximation", RatingValidityWarning, stacklevel=3)


def checked_rating(quantity: str, result: dict, pair, **inputs) -> dict:
    """``result`` if it holds no NaN or infinity; else :class:`~gearopt.errors.NonFiniteResultError` naming the
    quantity and the inputs (numeric pairs only; symbolic results pass)."""
    if pair.is_symbolic:
        return result
    check_result(quantity, {k: v for k, v in result.items() if k != "method"}, dict(pair._inputs(), **inputs))
    return result


__all__ = ["CONTACT_RATIO_RANGE", "RatingValidityWarning", "check_rating_validity", "checked_rating"]
