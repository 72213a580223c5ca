"""ISO 6336 rating table of a gear train: one table row per rated mesh (:func:`iso6336_train_table`), the one place
that rates a train's meshes. Two kinds of table:

* ``factors="computed"``: :func:`rate_iso6336` with every factor computed -- load factors, life and lubrication
  factors, safety factors, load cycles and lubricant;
* ``factors="given"``: ISO 6336-2 contact stress and ISO 6336-3 (method B) root stress with given load factors and
  the life and other factors 1 (:func:`contact_stress_iso6336`, :func:`root_stress_iso6336`), as
  :func:`gearopt.report.rating_tables.rating_table` shows it.
"""

from __future__ import annotations

import warnings

import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from .contact_stress import ISO_CONTACT_METHOD, contact_stress_iso6336
from .iso6336 import rate_iso6336
from .lubrication import default_lubricant
from .root_stress import ISO_ROOT_METHOD, root_stress_iso6336

#: Material used when a gear of the train names none.
DEFAULT_MATERIAL = "20MnCr5"
FACTOR_MODES = ("computed", "given")
_PAIR_FACTORS = ("K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha")
_GEAR_FACTORS = ("Z_NT", "Z_L", "Z_v", "Z_R", "Z_W", "Y_NT", "Y_deltarelT", "Y_RrelT", "Y_X")
_GIVEN_LOAD_FACTORS = ("K_v", "K_Hbeta", "K_Halpha", "K_Fbeta", "K_Falpha")


def iso6336_train_table(train, torques_Nm: dict, root_speed_rpm: float | None = None, *, factors: str = "computed",
                        application_factor=1.0, accuracy_grades: dict | None = None, lubricant=None, life_h=None,
                        materials: dict | None = None, **rating_options) -> pd.DataFrame:
    """ISO 6336 rating of every mesh named in ``torques_Nm`` ({mesh: torque [N m] on its driving, first gear}) of a
    numeric :class:`~gearopt.geometry.GearTrain`, one row per rated mesh in the train's order.

    ``materials``: {gear: material name or Material} (default the gear's own, else 20MnCr5);
    ``application_factor``: K_A.

    ``factors="computed"`` (default): :func:`rate_iso6336` with the root gear at ``root_speed_rpm`` [rpm] (required).
    ``accuracy_grades``: {gear: ISO 1328-1 grade} (default 6); ``lubricant`` (default :func:`default_lubricant`),
    ``life_h`` (default: endurance, N_L = 1e10), further keywords go to :func:`rate_iso6336` (e.g. ``K_v=1.0``).
    Columns: ``mesh``, ``gear_1``, ``gear_2``, ``torque_Nm``, ``speed_1_rpm``, ``N_L_1``, ``N_L_2``,
    ``resonance_ratio``, the load factors, ``<factor>_1``/``_2`` per gear, ``S_H_1``, ``S_H_2``, ``S_F_1``,
    ``S_F_2``, ``S_B``, ``S_intS``, ``lubricant`` and ``validity`` (the validity warnings of the mesh's rating,
    collected here instead of emitted; "ok" without).

    ``factors="given"``: :func:`contact_stress_iso6336` (ISO 6336-2 method B, with Z_B/Z_D) and
    :func:`root_stress_iso6336` (ISO 6336-3 method B) with the load factors ``K_v``, ``K_Hbeta``, ``K_Halpha``,
    ``K_Fbeta``, ``K_Falpha`` given as keywords (default 1) and the life and other factors 1 (S = strength /
    stress); ``root_speed_rpm`` is not used and ``accuracy_grades``, ``lubricant``, ``life_h`` do not apply.
    Columns: ``mesh``, ``gear_1``, ``gear_2``, ``torque_Nm``, ``F_t_N``, ``sigma_H0_MPa``, ``sigma_H_MPa`` (larger
    of the two gears), ``S_H`` (smaller), ``sigma_H_1_MPa``, ``sigma_H_2_MPa``, ``S_H_1``, ``S_H_2``,
    ``sigma_F_1_MPa``, ``sigma_F_2_MPa``, ``S_F_1``, ``S_F_2``, ``Y_F_1``, ``Y_S_1``, ``Y_F_2``, ``Y_S_2`` and
    ``method``.
    """
    if factors not in FACTOR_MODES:
        raise GearoptInputError(f"factors={factors!r} must be one of {FACTOR_MODES}")
    unknown = sorted(set(torques_Nm) - set(train.pairs))
    if unknown:
        raise GearoptInputError(f"torques_Nm names unknown mesh(es) {unknown}; the train has {sorted(train.pairs)}")
    materials = dict(materials or {})
    if factors == "given":
        extra = sorted(set(rating_options) - set(_GIVEN_LOAD_FACTORS))
        unused = [n for n, v in (("accuracy_grades", accuracy_grades), ("lubricant", lubricant), ("life_h", life_h))
                  if v is not None]
        if extra or unused:
            raise GearoptInputError(f"factors='given' takes the load factors {_GIVEN_LOAD_FACTORS} only; "
                                    f"{extra + unused} apply to factors='computed'")
        loads = {k: rating_options.get(k, 1.0) for k in _GIVEN_LOAD_FACTORS}

        def rate(name, pair, torque, mat):
            return _given_factors_row(name, pair, torque, mat, application_factor, **loads)
    else:
        if root_speed_rpm is None:
            raise GearoptInputError("factors='computed' needs root_speed_rpm (speed of the train's root gear [rpm])")
        grades = dict(accuracy_grades or {})
        lub = default_lubricant() if lubricant is None else lubricant

        def rate(name, pair, torque, mat):
            return _computed_factors_row(train, name, pair, torque, mat, root_speed_rpm, application_factor, grades,
                                         lub, life_h, rating_options)
    rows = []
    for name, pair in train.pairs.items():
        if name not in torques_Nm:
            continue
        mat = tuple(materials.get(g, train.gears[g].material or DEFAULT_MATERIAL) for g in pair.names)
        rows.append(rate(name, pair, torques_Nm[name], mat))
    return pd.DataFrame(rows)


def _computed_factors_row(train, name, pair, torque, mat, root_speed_rpm, application_factor, grades, lub, life_h,
                          rating_options) -> dict:
    f = nm.to_float
    gears = pair.names
    speed = train.gear_speed_rpm(gears[0], root_speed_rpm)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = rate_iso6336(pair, torque, speed, driving_gear=1, application_factor=application_factor,
                         accuracy_grade=tuple(grades.get(g, 6) for g in gears), materials=mat, lubricant=lub,
                         life_h=life_h, **rating_options)
    row = {"mesh": name, "gear_1": gears[0], "gear_2": gears[1], "torque_Nm": f(torque),
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
    return row


def _given_factors_row(name, pair, torque, mat, K_A, K_v, K_Hbeta, K_Halpha, K_Fbeta, K_Falpha) -> dict:
    c = contact_stress_iso6336(pair, torque, driving_gear=1, K_A=K_A, K_v=K_v, K_Hbeta=K_Hbeta,
                               K_Halpha=K_Halpha, material=mat)
    r = root_stress_iso6336(pair, torque, driving_gear=1, K_A=K_A, K_v=K_v, K_Fbeta=K_Fbeta, K_Falpha=K_Falpha,
                            material=mat)
    f = nm.to_float
    sh = [f(v) for v in c["sigma_H_MPa"]]
    s_h = [f(v) for v in c["safety_factor"]]
    return {
        "mesh": name, "gear_1": pair.names[0], "gear_2": pair.names[1], "torque_Nm": f(torque),
        "F_t_N": f(c["F_t_N"]), "sigma_H0_MPa": f(c["sigma_H0_MPa"]), "sigma_H_MPa": max(sh), "S_H": min(s_h),
        "sigma_H_1_MPa": sh[0], "sigma_H_2_MPa": sh[1], "S_H_1": s_h[0], "S_H_2": s_h[1],
        "sigma_F_1_MPa": f(r["gear1"]["sigma_F_MPa"]), "sigma_F_2_MPa": f(r["gear2"]["sigma_F_MPa"]),
        "S_F_1": f(r["gear1"]["safety_factor"]), "S_F_2": f(r["gear2"]["safety_factor"]),
        "Y_F_1": f(r["gear1"]["Y_F"]), "Y_S_1": f(r["gear1"]["Y_S"]),
        "Y_F_2": f(r["gear2"]["Y_F"]), "Y_S_2": f(r["gear2"]["Y_S"]),
        "method": f"contact: {ISO_CONTACT_METHOD}; root: {ISO_ROOT_METHOD}",
    }


__all__ = ["iso6336_train_table", "DEFAULT_MATERIAL", "FACTOR_MODES"]
