"""ISO 6336 rating with computed factors for every mesh of a gear train: one table row per mesh with the load
factors, life and lubrication factors, safety factors, load cycles and lubricant (:func:`iso6336_train_table`)."""

from __future__ import annotations

import warnings

import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from .iso6336 import rate_iso6336
from .lubrication import default_lubricant

DEFAULT_MATERIAL = "20MnCr5"
_PAIR_FACTORS = ("K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha")
_GEAR_FACTORS = ("Z_NT", "Z_L", "Z_v", "Z_R", "Z_W", "Y_NT", "Y_deltarelT", "Y_RrelT", "Y_X")


def iso6336_train_table(train, torques_Nm: dict, root_speed_rpm: float, *, application_factor=1.0,
                        accuracy_grades: dict | None = None, lubricant=None, life_h=None,
                        materials: dict | None = None, **rating_options) -> pd.DataFrame:
    """:func:`rate_iso6336` of every mesh named in ``torques_Nm`` ({mesh: torque [N m] on its driving, first gear})
    of a numeric :class:`~gearopt.geometry.GearTrain` with the root gear at ``root_speed_rpm``.

    ``accuracy_grades``: {gear: ISO 1328-1 grade} (default 6); ``materials``: {gear: material} (default the gear's
    own, else 20MnCr5); ``lubricant`` (default :func:`default_lubricant`), ``life_h`` (default: endurance, N_L =
    1e10), further keywords go to :func:`rate_iso6336`. Columns: ``mesh``, ``gear_1``, ``gear_2``, ``torque_Nm``,
    ``speed_1_rpm``, ``N_L_1``, ``N_L_2``, ``resonance_ratio``, the load factors, ``<factor>_1``/``_2`` per gear,
    ``S_H_1``, ``S_H_2``, ``S_F_1``, ``S_F_2``, ``S_B``, ``S_intS``, ``lubricant`` and ``validity`` (the validity
    warnings of the mesh's rating, collected here instead of emitted; "ok" without)."""
    unknown = sorted(set(torques_Nm) - set(train.pairs))
    if unknown:
        raise GearoptInputError(f"torques_Nm names unknown mesh(es) {unknown}; the train has {sorted(train.pairs)}")
    grades = dict(accuracy_grades or {})
    materials = dict(materials or {})
    lub = default_lubricant() if lubricant is None else lubricant
    f = nm.to_float
    rows = []
    for name, pair in train.pairs.items():
        if name not in torques_Nm:
            continue
        gears = pair.names
        mat = tuple(materials.get(g, train.gears[g].material or DEFAULT_MATERIAL) for g in gears)
        speed = train.gear_speed_rpm(gears[0], root_speed_rpm)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            r = rate_iso6336(pair, torques_Nm[name], speed, driving_gear=1, application_factor=application_factor,
                             accuracy_grade=tuple(grades.get(g, 6) for g in gears), materials=mat, lubricant=lub,
                             life_h=life_h, **rating_options)
        row = {"mesh": name, "gear_1": gears[0], "gear_2": gears[1], "torque_Nm": f(torques_Nm[name]),
               "speed_1_rpm": f(speed), "N_L_1": f(r.load_cycles[0]), "N_L_2": f(r.load_cycles[1]),
               "resonance_ratio": f(r.details["resonance_ratio"])}
        row.update({k: f(r.factors[k]) for k in _PAIR_FACTORS})
        for k in _GEAR_FACTORS:
            row[f"{k}_1"], row[f"{k}_2"] = f(r.factors[k][0]), f(r.factors[k][1])
        for k in ("S_H", "S_F"):
            row[f"{k}_1"], row[f"{k}_2"] = f(r.safety_factors[k][0]), f(r.safety_factors[k][1])
        row["S_B"], row["S_intS"] = f(r.safety_factors["S_B"]), f(r.safety_factors["S_intS"])
        row["lubricant"] = (f"nu40 {lub.viscosity_40C_mm2_s:g} / nu100 {lub.viscosity_100C_mm2_s:g} mm^2/s, "
                            f"{lub.oil_temperature_C:g} C, FZG {lub.fzg_test} stage {lub.fzg_load_stage:g}")
        row["validity"] = "; ".join(dict.fromkeys(str(w.message) for w in caught)) or "ok"
        rows.append(row)
    return pd.DataFrame(rows)


__all__ = ["iso6336_train_table"]
