"""Helical -> spur conversion at fixed centre distances (thesis section 3.4.1, Eq. 3.1, Table 3.1).

A helical gear of z teeth, normal module m_n and helix angle beta has reference diameter d = z m_n / cos(beta).
Keeping that diameter with a spur gear of module m gives z_spur = round(d / m) (thesis Eq. 3.1). Rounding changes
speed ratios (e.g. 2.7 % on one branch of the source study's train), and the standard (unshifted) spur centre distance
m (z1 + z2)/2 no longer equals the housing's centre distance: the gap profile shift must close.
"""

from __future__ import annotations

import math

import pandas as pd

from ..errors import GearoptInputError
from ..validation import check_range
from .train import GearTrain


def spur_teeth_from_helical(teeth: int, module_mm: float, helix_angle_deg: float,
                            spur_module_mm: float | None = None) -> int:
    """Spur tooth count keeping the helical gear's reference diameter: round(z m_n / (cos(beta) m)) (thesis Eq. 3.1).
    ``spur_module_mm`` defaults to the helical normal module."""
    check_range("module_mm", module_mm, 0.0, None, low_inclusive=False, unit="mm")
    check_range("helix_angle_deg", helix_angle_deg, 0.0, 45.0, high_inclusive=False, unit="deg")
    m = module_mm if spur_module_mm is None else spur_module_mm
    check_range("spur_module_mm", m, 0.0, None, low_inclusive=False, unit="mm")
    d = teeth * module_mm / math.cos(math.radians(helix_angle_deg))
    z = int(math.floor(d / m + 0.5))
    if z < 5:
        raise GearoptInputError(f"spur teeth={z} from d={d:.3f} mm and module {m} mm is below the limit 5")
    return z


def helical_to_spur_table(train: GearTrain, spur_module_mm: float | None = None) -> pd.DataFrame:
    """Thesis Table 3.1 for a helical train converted to spur gears at the same centre distances.

    One row per mesh: helical and spur teeth, ``speed_ratio_error_percent`` (error of the spur pair's speed ratio
    n2/n1 = z1/z2 against the helical one), ``standard_centre_distance_mm`` m (z1 + z2)/2 of the spur pair,
    the housing's ``centre_distance_mm``, and ``centre_distance_change_percent`` = (standard - housing)/housing.
    """
    helix = float(train.helix_angle_deg)
    m_n = float(train.rack.module_mm)
    m = m_n if spur_module_mm is None else spur_module_mm
    spur = {name: spur_teeth_from_helical(g.teeth, m_n, helix, m) for name, g in train.gears.items()}
    rows = []
    for name, mesh in train.meshes.items():
        g1, g2 = mesh.gears
        zh1, zh2 = train.gears[g1].teeth, train.gears[g2].teeth
        zs1, zs2 = spur[g1], spur[g2]
        a = float(mesh.centre_distance_mm)
        a_std = 0.5 * m * (zs1 + zs2)
        rows.append({
            "mesh": name, "helical_teeth_1": zh1, "helical_teeth_2": zh2, "spur_teeth_1": zs1, "spur_teeth_2": zs2,
            "speed_ratio_error_percent": ((zs1 / zs2) / (zh1 / zh2) - 1.0) * 100.0,
            "standard_centre_distance_mm": a_std, "centre_distance_mm": a,
            "centre_distance_change_percent": (a_std - a) / a * 100.0,
        })
    return pd.DataFrame(rows).set_index("mesh")
