"""Strength rating table of a gear train: ISO 6336-2 contact stress and ISO 6336-3 (method B) root stress with their
safety factors, one row per mesh (the main job shows it for the default spur and helical trains)."""

from __future__ import annotations

import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from ..rating.contact_stress import ISO_CONTACT_METHOD, contact_stress_iso6336
from ..rating.root_stress import ISO_ROOT_METHOD, root_stress_iso6336

#: Material used when a gear of the train names none.
DEFAULT_MATERIAL = "20MnCr5"


def rating_table(train, torques_Nm: dict, *, K_A=1.0, K_v=1.0, K_Hbeta=1.0, K_Halpha=1.0, K_Fbeta=1.0,
                 K_Falpha=1.0, materials: dict | None = None) -> pd.DataFrame:
    """Contact and root stresses and safety factors per mesh of a numeric :class:`~gearopt.geometry.GearTrain`.

    Args:
        train: the gear train (numeric).
        torques_Nm: {mesh name: torque [N m] on that mesh's driving (first) gear}; only these meshes are rated.
        K_A, K_v, K_Hbeta, K_Halpha, K_Fbeta, K_Falpha: load factors applied to every mesh (default 1).
        materials: {gear name: material name or Material} overriding the gears' own ``material`` (default
            ``"20MnCr5"`` where a gear names none).

    Returns a DataFrame, one row per rated mesh in the train's order: ``mesh``, ``gear_1``, ``gear_2``,
    ``torque_Nm``, ``F_t_N``, ``sigma_H0_MPa``, ``sigma_H_MPa`` (larger of the two gears), ``S_H`` (smaller),
    ``sigma_H_1_MPa``, ``sigma_H_2_MPa``, ``S_H_1``, ``S_H_2`` (ISO 6336-2 method B, with Z_B/Z_D),
    ``sigma_F_1_MPa``, ``sigma_F_2_MPa``, ``S_F_1``, ``S_F_2``, ``Y_F_1``, ``Y_S_1``, ``Y_F_2``, ``Y_S_2``
    (ISO 6336-3 method B), and ``method``. S = strength / stress with the life and other factors 1.
    """
    unknown = sorted(set(torques_Nm) - set(train.pairs))
    if unknown:
        raise GearoptInputError(f"torques_Nm names unknown mesh(es) {unknown}; the train has {sorted(train.pairs)}")
    if not torques_Nm:
        raise GearoptInputError("torques_Nm is empty: give {mesh name: torque on its driving gear [N m]}")
    materials = dict(materials or {})
    rows = []
    for name, pair in train.pairs.items():
        if name not in torques_Nm:
            continue
        mat = tuple(materials.get(gear, train.gears[gear].material or DEFAULT_MATERIAL) for gear in pair.names)
        torque = torques_Nm[name]
        c = contact_stress_iso6336(pair, torque, driving_gear=1, K_A=K_A, K_v=K_v, K_Hbeta=K_Hbeta,
                                   K_Halpha=K_Halpha, material=mat)
        r = root_stress_iso6336(pair, torque, driving_gear=1, K_A=K_A, K_v=K_v, K_Fbeta=K_Fbeta, K_Falpha=K_Falpha,
                                material=mat)
        f = nm.to_float
        sh = [f(v) for v in c["sigma_H_MPa"]]
        s_h = [f(v) for v in c["safety_factor"]]
        rows.append({
            "mesh": name, "gear_1": pair.names[0], "gear_2": pair.names[1], "torque_Nm": f(torque),
            "F_t_N": f(c["F_t_N"]), "sigma_H0_MPa": f(c["sigma_H0_MPa"]), "sigma_H_MPa": max(sh), "S_H": min(s_h),
            "sigma_H_1_MPa": sh[0], "sigma_H_2_MPa": sh[1], "S_H_1": s_h[0], "S_H_2": s_h[1],
            "sigma_F_1_MPa": f(r["gear1"]["sigma_F_MPa"]), "sigma_F_2_MPa": f(r["gear2"]["sigma_F_MPa"]),
            "S_F_1": f(r["gear1"]["safety_factor"]), "S_F_2": f(r["gear2"]["safety_factor"]),
            "Y_F_1": f(r["gear1"]["Y_F"]), "Y_S_1": f(r["gear1"]["Y_S"]),
            "Y_F_2": f(r["gear2"]["Y_F"]), "Y_S_2": f(r["gear2"]["Y_S"]),
            "method": f"contact: {ISO_CONTACT_METHOD}; root: {ISO_ROOT_METHOD}",
        })
    return pd.DataFrame(rows)


__all__ = ["rating_table", "DEFAULT_MATERIAL"]
