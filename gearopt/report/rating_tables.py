"""Strength rating table of a gear train: ISO 6336-2 contact stress and ISO 6336-3 (method B) root stress with their
safety factors, one row per mesh (the main job shows it for the default spur and helical trains); the table is
:func:`gearopt.rating.iso6336_train_table` with given load factors."""

from __future__ import annotations

import pandas as pd

from ..errors import GearoptInputError
from ..rating.train_rating import DEFAULT_MATERIAL, iso6336_train_table


def rating_table(train, torques_Nm: dict, *, K_A=1.0, K_v=1.0, K_Hbeta=1.0, K_Halpha=1.0, K_Fbeta=1.0,
                 K_Falpha=1.0, materials: dict | None = None) -> pd.DataFrame:
    """Contact and root stresses and safety factors per mesh of a numeric :class:`~gearopt.geometry.GearTrain`:
    :func:`gearopt.rating.iso6336_train_table` with ``factors="given"`` (the one train rating table).

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
    if not torques_Nm:
        raise GearoptInputError("torques_Nm is empty: give {mesh name: torque on its driving gear [N m]}")
    return iso6336_train_table(train, torques_Nm, factors="given", application_factor=K_A, K_v=K_v, K_Hbeta=K_Hbeta,
                               K_Halpha=K_Halpha, K_Fbeta=K_Fbeta, K_Falpha=K_Falpha, materials=materials)


__all__ = ["rating_table", "DEFAULT_MATERIAL"]
