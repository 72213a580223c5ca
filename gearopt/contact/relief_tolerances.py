"""The flank variants of a pair's tip reliefs at the corners of their manufacturing tolerances.

A ground tip relief is made to an amount C_a [um] and a start (roll angle [deg]) within tolerances; the PPTE the
pair runs with is that of the relief as made. :func:`relief_variants` lists every combination of each relieved
gear's amount ``± amount_um`` and start ``± start_deg`` (``2^(2 r)`` corners for ``r`` relieved gears), each with
the start blended as designed and, with ``sharp_start``, a sharp start too. Amounts stay >= 0; starts stay inside
the active profile (0.05 deg from its start and end). Dual-typed: amounts and starts may be CasADi expressions (the
design NLP's corners, :class:`~gearopt.design.scene_contact.ContactModels`), and then so are the variants'.

One definition serves the verdict (:func:`gearopt.design.requirements.evaluate_requirements`, exact LTCA at every
variant) and the design NLP (the smooth LTCA at the blended corners), so the optimiser holds the limit the verdict
judges.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass
from typing import Any, Sequence

from .. import numerics as nm
from ..validation import check_range
from .microgeometry import Microgeometry

PROFILE_MARGIN_DEG = 0.05
"""A varied start stays this far inside the active profile (roll angle [deg] from its start and its end)."""


@dataclass(frozen=True)
class ReliefTolerances:
    """Half-widths of the tip-relief tolerances: ``amount_um`` [um] on each relief amount, ``start_deg`` [deg roll]
    on each start; ``sharp_start``: the start both blended as designed and sharp (a grinding that does not blend)."""

    amount_um: float = 2.0
    start_deg: float = 0.5
    sharp_start: bool = True

    def __post_init__(self):
        check_range("relief tolerance amount_um", self.amount_um, 0.0, 50.0, unit="um")
        check_range("relief tolerance start_deg", self.start_deg, 0.0, 10.0, unit="deg")

    @property
    def varies(self) -> bool:
        return self.amount_um > 0.0 or self.start_deg > 0.0 or self.sharp_start


@dataclass(frozen=True)
class ReliefVariant:
    """One variant: ``signs`` (per relieved gear, amount sign then start sign: -1, 0 or +1), ``sharp`` (start not
    blended) and its ``microgeometry``."""

    signs: tuple[float, ...]
    sharp: bool
    microgeometry: Microgeometry


def start_roll_deg(mods: Microgeometry, geometry: Any, i: int):
    """The tip-relief start of gear ``i`` as a roll angle [deg] (from the start diameter where only that is given;
    None where neither is)."""
    s = mods.tip_relief_start_roll_deg[i]
    d = mods.tip_relief_start_diameter_mm[i]
    if s is None and d is not None:
        d_b = geometry["base_diameter_mm"][i]
        s = nm.sqrt(d * d - d_b * d_b) / d_b * (180.0 / math.pi)
    return s


def relief_variants(mods: Microgeometry, geometry: Any, tolerances: ReliefTolerances, relieved: Sequence[int], *,
                    sharp: bool | None = None) -> list[ReliefVariant]:
    """Every variant of ``mods`` over ``tolerances`` (module docstring) for the gears ``relieved`` (indices 0/1 of
    the gears whose tip relief is made); ``geometry``: the pair's geometry (``eap_roll_deg``, ``sap_roll_deg``,
    ``base_diameter_mm``), numeric or symbolic. ``sharp``: override ``tolerances.sharp_start`` (False: the
    blended variants only -- the smooth NLP's). Empty when nothing varies."""
    relieved = list(relieved)
    da, ds = float(tolerances.amount_um), float(tolerances.start_deg)
    blends = [False] + ([True] if (tolerances.sharp_start if sharp is None else sharp)
                        and _blended(mods.relief_smoothing_deg) else [])
    if not relieved or (da == 0.0 and ds == 0.0 and len(blends) == 1):
        return []
    eap, sap = geometry["eap_roll_deg"], geometry["sap_roll_deg"]
    starts = [start_roll_deg(mods, geometry, i) for i in (0, 1)]
    steps = [(-1.0, 1.0) if (da or ds) else (0.0,)] * (2 * len(relieved))
    out = []
    for combo in itertools.product(*steps):
        amounts, st = list(mods.tip_relief_um), list(starts)
        for k, i in enumerate(relieved):
            amounts[i] = nm.fmax(amounts[i] + combo[2 * k] * da, 0.0)
            st[i] = nm.fmin(nm.fmax(st[i] + combo[2 * k + 1] * ds, sap[i] + PROFILE_MARGIN_DEG),
                            eap[i] - PROFILE_MARGIN_DEG)
        for is_sharp in blends:
            out.append(ReliefVariant(tuple(combo), is_sharp, dataclasses.replace(
                mods, tip_relief_um=tuple(amounts), tip_relief_start_roll_deg=tuple(st),
                tip_relief_start_diameter_mm=(None, None),
                relief_smoothing_deg=0.0 if is_sharp else mods.relief_smoothing_deg)))
    return out


def _blended(width) -> bool:
    return nm.is_numeric(width) and nm.to_float(width) > 0.0


__all__ = ["ReliefTolerances", "ReliefVariant", "relief_variants", "start_roll_deg", "PROFILE_MARGIN_DEG"]
