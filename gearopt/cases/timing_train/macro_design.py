"""The macro-design tables of the thesis (Tables 3.1-3.4) and a per-mesh check table, from gearopt trains.

Each table carries gearopt's own numbers next to the thesis' (normalised where the thesis normalised them), so the
comparison is a shape check as docs/source-study.md sec. 1 explains. Columns carry units or say ``normalised``.
"""

from __future__ import annotations

import math

import pandas as pd

from ...data import values
from ...errors import GeometryError
from ...geometry.conversion import helical_to_spur_table
from ...geometry.train import GearTrain


def conversion_table(helical: GearTrain, thesis: dict) -> pd.DataFrame:
    """Thesis Table 3.1: helical -> standard spur errors, with the thesis' columns alongside."""
    df = helical_to_spur_table(helical)
    t = values(thesis["table_3_1"])
    ref = pd.DataFrame({"thesis_speed_ratio_error_percent": t["speed_ratio_error_percent"],
                        "thesis_centre_distance_change_percent": t["centre_distance_change_percent"]},
                       index=pd.Index(t["meshes"], name="mesh"))
    return df.join(ref)


def sum_shift_table(spur: GearTrain, thesis: dict, normalise_centre_distance_by: str = "cam-fp",
                    normalise_shift_by: str = "cam-ac") -> pd.DataFrame:
    """Thesis Table 3.2: centre distance and sum of profile shifts per mesh, absolute and normalised as the thesis
    did (centre distance by cam-FP, sum of shifts by cam-AC)."""
    m = spur.mesh_table()
    t = values(thesis["table_3_2"])
    df = pd.DataFrame({
        "centre_distance_mm": m["centre_distance_mm"],
        "centre_distance_modification": m["centre_distance_modification"],
        "working_pressure_angle_deg": m["working_pressure_angle_deg"],
        "sum_profile_shift": m["sum_profile_shift"],
        "centre_distance_normalised": m["centre_distance_mm"] / m.loc[normalise_centre_distance_by,
                                                                      "centre_distance_mm"],
        "sum_profile_shift_normalised": m["sum_profile_shift"] / m.loc[normalise_shift_by, "sum_profile_shift"],
    })
    ref = pd.DataFrame({"thesis_centre_distance_normalised": t["centre_distance_normalised"],
                        "thesis_sum_profile_shift_normalised": t["sum_profile_shift_normalised"]},
                       index=pd.Index(t["meshes"], name="mesh"))
    return df.join(ref)


def shift_table(spur: GearTrain, thesis: dict, iso_split: GearTrain | None = None,
                normalise_by: str = "cam-ac") -> pd.DataFrame:
    """Thesis Table 3.3: profile shift per gear (absolute and normalised by the cam-AC sum), with the split that
    ISO/TR 4467 lambda = 0.5 on the root mesh would give (``iso_split``) and the thesis' normalised values."""
    norm = spur.mesh_table().loc[normalise_by, "sum_profile_shift"]
    t = values(thesis["table_3_3"])
    df = pd.DataFrame({"teeth": {g: s.teeth for g, s in spur.gears.items()},
                       "profile_shift": {g: float(x) for g, x in spur.profile_shifts.items()}})
    df.index.name = "gear"
    df["profile_shift_normalised"] = df["profile_shift"] / norm
    if iso_split is not None:
        df["profile_shift_iso_tr_4467"] = pd.Series({g: float(x) for g, x in iso_split.profile_shifts.items()})
    ref = pd.Series(t["profile_shift_normalised"], index=t["gears"], name="thesis_profile_shift_normalised")
    return df.join(ref)


def change_table(spur: GearTrain, thesis: dict) -> pd.DataFrame:
    """Thesis Table 3.4: percentage change of addendum, tip and root diameter and reference tooth thickness of each
    gear against the same gear unshifted (d_a0 = m(z + 2 h_aP*), d_f0 = m(z - 2 h_fP*), s0 = pi m/2)."""
    gt = spur.gear_table()
    m = float(spur.rack.module_mm)
    ha, hf = spur.rack.addendum_coefficient, spur.rack.dedendum_coefficient
    z = gt["teeth"].astype(float)
    beta = math.radians(float(spur.helix_angle_deg))
    d = z * m / math.cos(beta)
    df = pd.DataFrame({
        "addendum_change_percent": (gt["addendum_mm"] / (ha * m) - 1.0) * 100.0,
        "tip_diameter_change_percent": (gt["tip_diameter_mm"] / (d + 2 * ha * m) - 1.0) * 100.0,
        "root_diameter_change_percent": (gt["root_diameter_mm"] / (d - 2 * hf * m) - 1.0) * 100.0,
        "tooth_thickness_change_percent": (gt["tooth_thickness_mm"] / (math.pi * m / 2) - 1.0) * 100.0,
    })
    t = values(thesis["table_3_4"])
    for key in ("addendum_change_percent", "tip_diameter_change_percent", "root_diameter_change_percent",
                "tooth_thickness_change_percent"):
        df[f"thesis_{key}"] = pd.Series(t[key], index=t["gears"])
    return df


def mesh_check_table(train: GearTrain, **limits) -> pd.DataFrame:
    """Per mesh: contact ratios (nominal and worst case), backlash range (from :meth:`GearTrain.mesh_table`), tip
    thicknesses, bottom clearances, SAP roll angles, and the verdict of :meth:`GearPair.check` with ``limits``
    (``"ok"`` or the violated limits by name)."""
    shared = ["transverse_contact_ratio", "worst_case_transverse_contact_ratio", "overlap_contact_ratio",
              "total_contact_ratio", "normal_backlash_min_mm", "normal_backlash_max_mm"]
    rows = {}
    for name, pair in train.pairs.items():
        g = pair.geometry()
        try:
            pair.check(**limits)
            verdict = "ok"
        except GeometryError as err:
            verdict = str(err).split(": ", 1)[1]
        rows[name] = {
            "tip_thickness_1_mm": g["tip_thickness_mm"][0], "tip_thickness_2_mm": g["tip_thickness_mm"][1],
            "bottom_clearance_1_mm": g["bottom_clearance_mm"][0],
            "bottom_clearance_2_mm": g["bottom_clearance_mm"][1],
            "sap_roll_1_deg": g["sap_roll_deg"][0], "sap_roll_2_deg": g["sap_roll_deg"][1],
            "check": verdict,
        }
    return train.mesh_table()[shared].join(pd.DataFrame.from_dict(rows, orient="index"))
