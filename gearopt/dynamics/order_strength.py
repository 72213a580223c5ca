"""How hard an engine order drives a mode: the modal excitation of a Campbell crossing.

A crossing of mode m with order o at speed n resonates only as much as the order-o harmonic of the external torques
does work on the mode's shape: the generalised (modal) force ``|phi_m^T T_k(n)|`` with ``T_k`` the complex Fourier
coefficient of harmonic k = o cycle_deg / 360 of the nominal external torques on the free nodes at speed n, and
``phi_m`` the undamped mode shape normalised to a largest |angle| of 1 (so the value is in N m: the equivalent torque
at the mode's dominant node). Standard modal superposition (e.g. Den Hartog, *Mechanical Vibrations*, sec. 5.5, or
Ker Wilson's order-excitation sums); linear model and boundary of :mod:`gearopt.dynamics.modes`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..errors import GearoptInputError
from .modes import _DEFAULT_SAMPLES, _harmonics, _parameter_values, mode_shapes


def crossing_excitation_Nm(net, crossings: pd.DataFrame, parameters: dict | None = None,
                           samples: int = _DEFAULT_SAMPLES) -> np.ndarray:
    """Modal excitation [N m] of every crossing (rows with ``mode``, ``order``, ``speed_rpm``, as
    :func:`gearopt.dynamics.modes.campbell_diagram` returns them) of the network ``net`` with its speed boundary
    held. An order that is not a harmonic of the cycle (order x cycle_deg / 360 not an integer) raises
    :class:`GearoptInputError`."""
    net = getattr(net, "network", net)
    shapes = mode_shapes(net, parameters=parameters).drop(index="frequency_Hz")
    per_cycle = net.cycle_deg / 360.0
    out = np.zeros(len(crossings))
    cache: dict[float, np.ndarray] = {}
    for i, (_, row) in enumerate(crossings.iterrows()):
        k_float = float(row["order"]) * per_cycle
        k = int(round(k_float))
        if abs(k - k_float) > 1e-9 or k < 1:
            raise GearoptInputError(f"order={row['order']:g} is not a harmonic of the {net.cycle_deg:g} deg cycle")
        if 2 * k + 1 > samples:
            raise GearoptInputError(f"samples={samples} too few for order {row['order']:g}")
        speed = float(row["speed_rpm"])
        if speed not in cache:
            p = _parameter_values(net, parameters, speed)
            cache[speed] = _harmonics(net, np.array(list(p.values())), samples)
        phi = shapes[f"mode_{int(row['mode'])}"].to_numpy()
        out[i] = abs(phi @ cache[speed][k])
    return out


__all__ = ["crossing_excitation_Nm"]
