"""Harris map: peak-to-peak transmission error of one microgeometry over a torque range (Harris 1958).

A tip relief removes the TE variation only near the load whose tooth deflection it matches; the Harris map shows
PPTE against torque so a design can be judged over its whole load range. Two implementations of the same physics:

- ``method="exact"``: the exact numeric LTCA (:func:`gearopt.contact.ltca.ltca`) at each torque;
- ``method="smooth"``: one call of the smooth CasADi LTCA (:class:`gearopt.contact.ltca_smooth.LTCAModel`) with all
  torques mapped as load cases. With a symbolic microgeometry it returns the :class:`SmoothLTCAResult` whose
  ``transmission_error_um`` is the (positions x torques) TE matrix expression, ready for epigraph PPTE bounds.
"""

from __future__ import annotations

from typing import Any, Sequence

import numpy as np
import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from ..geometry.pair import GearPair
from .ltca import ltca
from .ltca_smooth import LTCAModel
from .microgeometry import Microgeometry


def harris_map(pair: GearPair, microgeometry: Microgeometry | None, torques_Nm: Sequence[float], *,
               method: str = "exact", model: LTCAModel | None = None, driving_gear: int = 1, **options: Any):
    """PPTE [um], maximum contact stress [MPa] and loaded contact ratio over ``torques_Nm`` [N m, driving gear].

    ``options`` go to :func:`ltca` (exact) or to :class:`LTCAModel` (smooth, unless ``model`` is given).
    Returns a DataFrame (columns ``torque_Nm``, ``ppte_um``, ``max_contact_stress_MPa``,
    ``loaded_contact_ratio``), or for a symbolic microgeometry with ``method="smooth"`` the smooth result.
    """
    torques = np.asarray(torques_Nm, dtype=float).reshape(-1)
    if torques.size == 0:
        raise GearoptInputError("torques_Nm is empty: give at least one torque")
    mods = microgeometry or Microgeometry()
    if method == "exact":
        rows = []
        for t in torques:
            r = ltca(pair, float(t), driving_gear=driving_gear, microgeometry=mods, **options)
            rows.append((t, r.ppte_um, r.max_contact_stress_MPa, r.loaded_contact_ratio))
    elif method == "smooth":
        model = model or LTCAModel(pair, driving_gear=driving_gear,
                                   lead_modification=mods.has_lead_modification, **options)
        res = model.evaluate(mods, list(torques))
        if nm.is_symbolic(res.transmission_error_um):
            return res
        te = np.asarray(res.transmission_error_um).reshape(-1, torques.size, order="F")   # (positions, torques)
        s2 = np.asarray(res.contact_stress_squared_MPa2)
        s2 = s2.reshape(s2.shape[0], torques.size, -1)                                     # (springs, torques, P)
        lcr = np.atleast_1d(res.loaded_contact_ratio)
        rows = [(t, float(np.ptp(te[:, i])), float(np.sqrt(s2[:, i, :].max())), float(lcr[i]))
                for i, t in enumerate(torques)]
    else:
        raise GearoptInputError(f"method={method!r} must be 'exact' or 'smooth'")
    return pd.DataFrame(rows, columns=["torque_Nm", "ppte_um", "max_contact_stress_MPa", "loaded_contact_ratio"])


__all__ = ["harris_map"]
