"""Tip relief as a drawing gives it: start diameter and relief length in mm, from the start roll angle the LTCA and
the microgeometry NLP use.

On an involute, the point at roll angle xi (roll length rho = r_b xi on the line of action) sits on the diameter
``d = 2 sqrt(r_b^2 + rho^2)`` (ISO 21771:2007, 4.3, involute relations; :mod:`gearopt.geometry.involute`). A linear
tip relief from roll angle xi_s to the end of the active profile (EAP, xi_E) therefore starts on
``d_Ca = d_b sqrt(1 + xi_s^2)`` and is ``L_Ca = r_b (xi_E - xi_s)`` long measured along the line of action (the
"length of relief" of ISO 21771:2007, 8.4.2, and of gear drawings), or ``(d_a - d_Ca) / 2`` high radially.
"""

from __future__ import annotations

import math

from ..errors import GearoptInputError
from ..geometry import involute as inv


def tip_relief_dimensions(pair, gear: int, start_roll_deg: float, amount_um: float | None = None) -> dict:
    """Start diameter and lengths of the tip relief of ``gear`` (1 or 2) of a numeric :class:`GearPair` that starts
    at roll angle ``start_roll_deg`` [deg] and runs to the end of the active profile.

    Returns ``start_roll_deg``, ``start_diameter_mm`` (d_Ca), ``relief_length_mm`` (L_Ca, roll length along the line
    of action from the start to the EAP), ``relief_height_mm`` (radial, from d_Ca to the tip diameter),
    ``eap_diameter_mm``, ``tip_diameter_mm`` and, if given, ``amount_um``. Raises :class:`GearoptInputError` if the
    start lies outside the active profile (below SAP or above EAP)."""
    if gear not in (1, 2):
        raise GearoptInputError(f"gear={gear!r} must be 1 or 2")
    g = pair.geometry()
    i = gear - 1
    d_b = float(g["base_diameter_mm"][i])
    sap, eap = float(g["sap_roll_deg"][i]), float(g["eap_roll_deg"][i])
    start = float(start_roll_deg)
    if not (sap - 1e-9 <= start <= eap + 1e-9):
        raise GearoptInputError(f"start_roll_deg={start:g} deg of gear {gear} lies outside its active profile "
                                f"[{sap:.3f}, {eap:.3f}] deg (SAP..EAP)")
    rho = 0.5 * d_b * math.radians(start)
    d_start = float(inv.diameter_at_roll_length(rho, d_b))
    out = {"start_roll_deg": start, "start_diameter_mm": d_start,
           "relief_length_mm": 0.5 * d_b * math.radians(eap - start),
           "relief_height_mm": 0.5 * (float(g["tip_diameter_mm"][i]) - d_start),
           "eap_diameter_mm": float(g["eap_diameter_mm"][i]), "tip_diameter_mm": float(g["tip_diameter_mm"][i])}
    if amount_um is not None:
        out["amount_um"] = float(amount_um)
    return out


__all__ = ["tip_relief_dimensions"]
