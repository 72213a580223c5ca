"""Sample points of a scene's design problems: pure helpers, below every scene module (no import of the design
package), shared by the scene's model graph and its refinement.

- mesh positions (fractions of a base pitch) of the semi-infinite refinement: the exact TE's peaks and troughs
  (:func:`extreme_fractions`), the peaks of stresses and temperatures (:func:`peak_fractions`), the ones not yet in a
  set (:func:`new_fractions`);
- the room of a tip-relief start on a gear's profile (:func:`start_bounds`) and the thesis' minimum tip relief as
  a design (:func:`min_tip_relief_design`, the default start of a free relief);
- the corners of a box of named bounds (:func:`corner_values`), for bounding a quantity over a design space.
"""

from __future__ import annotations

import itertools
from typing import Mapping

import numpy as np

from ..contact.microgeometry import Microgeometry
from ..contact.tip_relief import min_tip_relief_um
from ..errors import GearoptInputError


def extreme_fractions(te: np.ndarray, fractions: np.ndarray, per_side: int = 3, band: float = 0.25,
                      neighbours: int = 6) -> tuple:
    """Mesh positions of the TE's peaks and troughs: the global maximum and minimum first, then further local
    maxima (minima) in the top (bottom) ``band`` of the range, most extreme first, up to ``per_side`` each, each with
    ``neighbours`` grid points on either side (an extreme moves a little when the design does; its neighbours keep
    the NLP from sliding it between two samples). The TE is periodic over the base pitch."""
    te = np.asarray(te, dtype=float)
    lo, hi = te.min(), te.max()
    span = max(hi - lo, 1e-12)
    prev, nxt = np.roll(te, 1), np.roll(te, -1)
    is_peak = (te >= prev) & (te >= nxt) & (te >= hi - band * span)
    is_trough = (te <= prev) & (te <= nxt) & (te <= lo + band * span)
    by_height, by_depth = np.argsort(-te), np.argsort(te)      # the order of the former per-index filter
    peaks = by_height[is_peak[by_height]][:per_side]
    troughs = by_depth[is_trough[by_depth]][:per_side]
    idx = [int(np.argmax(te)), int(np.argmin(te))] + [int(i) for i in peaks] + [int(i) for i in troughs]
    return _with_neighbours(idx, fractions, neighbours)


def peak_fractions(arrays, fractions: np.ndarray, neighbours: int) -> tuple:
    """Mesh positions (``fractions``) where each of ``arrays`` (positions first, e.g. (P, K, J) stresses of every
    spring; NaN off the path) peaks over the cycle, each with ``neighbours`` grid points either side (periodic)."""
    idx = [int(np.nanargmax(np.nanmax(np.asarray(a, dtype=float).reshape(len(fractions), -1), axis=1)))
           for a in arrays]
    return _with_neighbours(idx, fractions, neighbours)


def _with_neighbours(indices, fractions, neighbours: int) -> tuple:
    """The grid fractions at ``indices`` and ``neighbours`` points either side of each (periodic), each once, in
    order."""
    out: list[float] = []
    for i in indices:
        for j in range(i - neighbours, i + neighbours + 1):
            f = float(fractions[j % len(fractions)])
            if f not in out:
                out.append(f)
    return tuple(out)


def new_fractions(existing: np.ndarray, candidates, tol: float = 1e-9) -> list[float]:
    """The ``candidates`` not yet in ``existing`` (periodic distance over tol), each once, in order."""
    out = []
    for f in candidates:
        d = np.abs(np.asarray(existing) - f)
        if np.min(np.minimum(d, 1.0 - d)) > tol and all(abs(f - o) > tol for o in out):
            out.append(float(f))
    return out


def start_bounds(g: dict, gear: int, margin_deg: float) -> tuple[float, float]:
    """Room of a tip-relief start of ``gear`` (0 or 1) on the geometry ``g`` (:meth:`GearPair.geometry`): from the
    working pitch point to ``margin_deg`` below the tip, as roll angles [deg]."""
    lo = float(g["pitch_point_roll_deg"][gear])
    hi = float(g["eap_roll_deg"][gear]) - margin_deg
    if hi <= lo:
        raise GearoptInputError(f"tip relief start of gear {gear + 1}: no room between the pitch point "
                                f"({lo:.3f} deg) and the tip ({hi + margin_deg:.3f} deg)")
    return lo, hi


def corner_values(bounds: Mapping[str, tuple[float, float]]) -> list[dict[str, float]]:
    """Every corner of a box of named bounds (and its centre), for bounding a quantity over a design space."""
    names = list(bounds)
    out = [dict(zip(names, c)) for c in itertools.product(*[bounds[n] for n in names])]
    out.append({n: 0.5 * (lo + hi) for n, (lo, hi) in bounds.items()})
    return out




def min_tip_relief_design(pair, torque_Nm: float, *, driving_gear: int = 1) -> Microgeometry:
    """The thesis' minimum tip relief (Eq. 3.38, amounts at the pitch point, :func:`~gearopt.contact.tip_relief.
    min_tip_relief_um`) of a spur :class:`~gearopt.geometry.pair.GearPair` at ``torque_Nm`` [N m] on the driving gear,
    as a linear relief starting at each gear's single-contact boundary next to its tip (the 'long' relief of the
    double-contact zone)."""
    amounts = min_tip_relief_um(pair, torque_Nm, driving_gear)
    g = pair.geometry()
    starts = tuple(max(float(g["lpstc_roll_deg"][i]), float(g["hpstc_roll_deg"][i])) for i in range(2))
    return Microgeometry(tip_relief_um=tuple(float(a) for a in amounts), tip_relief_start_roll_deg=starts,
                         relief_shape="linear")


__all__ = ["extreme_fractions", "peak_fractions", "new_fractions", "start_bounds", "corner_values",
           "min_tip_relief_design"]
