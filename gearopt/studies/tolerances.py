"""Tolerances of a study: how far a design variable or a datum of a scene may stray from its nominal value.

A :class:`Tolerance` names an input of a solved scene -- a design variable (``"pinion-wheel.tip_relief_1_um"``) or a
datum the parametric build declares (``"torque_Nm[pinion-wheel]@design"``, ``"oil_temperature_C[pinion-wheel]"``, see
``Scene.build(parametric=True)``) -- and its deviation interval ``[lower, upper]`` in the input's unit, with a
uniform distribution over it or a normal one centred in it whose ±3σ span the interval (the usual reading of a
process capable to Cp = 1, ISO 22514-2).

:func:`default_tolerances` gives the tolerances a scene's inputs have by default:

- tip-relief amounts ±2 µm and relief starts ±0.5° roll angle (uniform): engineering estimates for ground profile
  modifications (about the profile form tolerance ``f_fα`` of ISO 1328-1:2013 flank tolerance class 5-6 for these
  gear sizes; the class is an estimate, the values are not read from the standard's tables);
- the oil temperature of a contact-temperature quantity ±10 K (uniform): the data's range of sump/gallery oil
  temperature at rated load (90-110 °C, ``[lubrication] oil_temperature_C``).

Tooth-thickness and centre-distance allowances and tip diameters (the data's ``*_allowance_*`` entries) move the macro
geometry, which the smooth LTCA takes as numbers: they are not inputs of a scene's quantities yet.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..data.requirements import Requirements
from ..errors import GearoptInputError

DISTRIBUTIONS = ("uniform", "normal")

MICROGEOMETRY_TOLERANCES = {f"tip_relief_{g}_{k}": v for g in (1, 2) for k, v in (
    ("um", Requirements().ppte_relief_tolerance_um), ("start_roll_deg", Requirements().ppte_relief_start_tolerance_deg))}
"""Symmetric half-widths of the default microgeometry tolerances (see the module docstring: estimates), the same
as the PPTE requirement's defaults (:class:`gearopt.data.requirements.Requirements`)."""

OIL_TEMPERATURE_SPREAD_K = 10.0
"""Half-width of the default oil-temperature spread [K] (data: 90-110 °C at rated load)."""


@dataclass(frozen=True)
class Tolerance:
    """Deviation ``[lower, upper]`` (input unit) of the input ``name`` from its nominal value; ``distribution``
    ``"uniform"`` or ``"normal"`` (mean at the middle, σ = (upper - lower)/6)."""

    name: str
    lower: float
    upper: float
    distribution: str = "uniform"

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise GearoptInputError(f"Tolerance name={self.name!r} must be a non-empty string")
        for what in ("lower", "upper"):
            v = getattr(self, what)
            if not isinstance(v, (int, float, np.floating)) or not math.isfinite(v):
                raise GearoptInputError(f"Tolerance {self.name!r}: {what}={v!r} must be a finite number")
        if self.upper < self.lower:
            raise GearoptInputError(f"Tolerance {self.name!r}: upper={self.upper!r} < lower={self.lower!r} (a "
                                    f"negative spread); limit: upper >= lower")
        if self.distribution not in DISTRIBUTIONS:
            raise GearoptInputError(f"Tolerance {self.name!r}: distribution={self.distribution!r} must be one of "
                                    f"{DISTRIBUTIONS}")

    @classmethod
    def symmetric(cls, name: str, spread: float, distribution: str = "uniform") -> "Tolerance":
        """``±spread`` about the nominal value (``spread`` >= 0)."""
        if not isinstance(spread, (int, float, np.floating)) or not math.isfinite(spread) or spread < 0:
            raise GearoptInputError(f"Tolerance {name!r}: spread={spread!r} must be a finite number >= 0 (a "
                                    f"negative spread is not a tolerance)")
        return cls(name, -float(spread), float(spread), distribution)

    def deviation(self, u: np.ndarray) -> np.ndarray:
        """Deviations at probabilities ``u`` in [0, 1) (the inverse CDF; normal tails clipped at ±6σ)."""
        u = np.asarray(u, dtype=float)
        if self.distribution == "uniform":
            return self.lower + (self.upper - self.lower) * u
        from scipy.stats import norm

        mid, sigma = 0.5 * (self.lower + self.upper), (self.upper - self.lower) / 6.0
        return mid + sigma * np.clip(norm.ppf(np.clip(u, 1e-12, 1 - 1e-12)), -6.0, 6.0)


def default_tolerances(design_variables: list[str], data_parameters: list[str]) -> list[Tolerance]:
    """The default tolerances of a scene's inputs (see the module docstring); inputs without one are left out."""
    out = []
    for name in design_variables:
        spread = MICROGEOMETRY_TOLERANCES.get(name.split(".", 1)[-1])
        if spread is not None:
            out.append(Tolerance.symmetric(name, spread))
    for name in data_parameters:
        if name.startswith("oil_temperature_C["):
            out.append(Tolerance.symmetric(name, OIL_TEMPERATURE_SPREAD_K))
    return out


__all__ = ["Tolerance", "default_tolerances", "MICROGEOMETRY_TOLERANCES", "OIL_TEMPERATURE_SPREAD_K",
           "DISTRIBUTIONS"]
