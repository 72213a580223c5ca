"""Contact study of the thesis (chapter 4): helical baseline vs unmodified spur vs optimised spur, per mesh.

For each named mesh: the exact LTCA of the helical pair (sliced face) and of the unmodified spur pair at the design
torque, the PPTE-minimising spur microgeometry over the design-torque range (robust: largest PPTE over the load
cases, :func:`gearopt.design.microgeometry_nlp.optimise_microgeometry`), its exact LTCA, and the Harris maps of the
three designs. Outputs per design: PPTE, maximum contact stress, maximum root stress of each gear, maximum contact
(flash) temperature, loaded contact ratio. Plain data (DataFrames, dicts, LTCA results); figures are drawn by the
caller (:mod:`gearopt.report.ltca_figures`).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
import pandas as pd

from ..contact.harris import harris_map
from ..contact.ltca import LTCAResult, ltca
from ..design.microgeometry_nlp import MicrogeometryDesign, optimise_microgeometry
from ..geometry.train import GearTrain

DESIGNS = ("helical", "spur_unmodified", "spur_optimised")


@dataclass
class MeshContactStudy:
    """Results of one mesh: ``ltca`` by design, the optimisation, the Harris maps and a summary table."""

    mesh: str
    torque_Nm: float
    speed_rpm: float
    driving_gear: int
    ltca: dict[str, LTCAResult]
    optimisation: MicrogeometryDesign
    harris: dict[str, pd.DataFrame]
    summary: pd.DataFrame
    times_s: dict = field(default_factory=dict)

    def headline(self) -> dict[str, Any]:
        """Headline numbers with units, per design (for ``result.json``)."""
        s = self.summary.set_index("design")
        out: dict[str, Any] = {}
        for col in ("ppte_um", "max_contact_stress_MPa", "max_root_stress_MPa", "max_flash_temperature_C",
                    "loaded_contact_ratio"):
            if col == "max_root_stress_MPa":
                out[col] = {d: [float(s.loc[d, "max_root_stress_1_MPa"]), float(s.loc[d, "max_root_stress_2_MPa"])]
                            for d in s.index}
            else:
                out[col] = {d: float(s.loc[d, col]) for d in s.index}
        return out


def _summary_row(design: str, r: LTCAResult) -> dict[str, Any]:
    return {"design": design, "ppte_um": r.ppte_um, "max_contact_stress_MPa": r.max_contact_stress_MPa,
            "max_root_stress_1_MPa": r.max_root_stress_MPa[0], "max_root_stress_2_MPa": r.max_root_stress_MPa[1],
            "max_flash_temperature_C": r.max_flash_temperature_C, "loaded_contact_ratio": r.loaded_contact_ratio,
            "max_load_intensity_N_per_mm": r.max_load_intensity_N_per_mm}


def mesh_contact_study(trains: dict[str, GearTrain], mesh: str, torque_Nm: float, *, crank_speed_rpm: float,
                       torque_fractions: Sequence[float] = (0.5, 1.0, 1.5), driving_gear: int = 1,
                       positions: int | None = None, nlp_positions: int = 40, helical_slices: int | None = None,
                       harris_points: int = 9,
                       bulk_temperature_C: float = 100.0, friction_coefficient: float = 0.06,
                       **nlp_options: Any) -> MeshContactStudy:
    """The three-design comparison of ``mesh`` (a key of both trains' ``pairs``) at ``torque_Nm`` on its driving
    gear; ``crank_speed_rpm`` sets every gear's speed through the train's speed ratios. ``positions`` and
    ``helical_slices``: resolution of every exact LTCA (None: the converged defaults of :func:`ltca`);
    ``nlp_positions``: the positions the microgeometry NLP samples."""
    times: dict[str, float] = {}
    spur, helical = trains["spur"].pairs[mesh], trains["helical"].pairs[mesh]
    speed = trains["spur"].gear_speed_rpm(trains["spur"].pairs[mesh].names[driving_gear - 1], crank_speed_rpm)
    common = dict(driving_gear=driving_gear, positions=positions, speed_rpm=speed,
                  bulk_temperature_C=bulk_temperature_C, friction_coefficient=friction_coefficient)
    t0 = time.perf_counter()
    results = {"helical": ltca(helical, torque_Nm, slices=helical_slices, **common),
               "spur_unmodified": ltca(spur, torque_Nm, **common)}
    times["ltca_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    torques = [torque_Nm * f for f in torque_fractions]
    torques = [torque_Nm] + [t for t in torques if t != torque_Nm]   # the design torque first
    opt = optimise_microgeometry(spur, torques, driving_gear=driving_gear, positions=nlp_positions,
                                 check_positions=positions or 1280, speed_rpm=speed,
                                 bulk_temperature_C=bulk_temperature_C, friction_coefficient=friction_coefficient,
                                 **nlp_options)
    times["microgeometry_nlp_s"] = time.perf_counter() - t0
    results["spur_optimised"] = ltca(spur, torque_Nm, microgeometry=opt.microgeometry, **common)
    t0 = time.perf_counter()
    span = np.linspace(min(torques) * 0.5, max(torques) * 1.2, harris_points)
    harris = {"helical": harris_map(helical, None, span, slices=helical_slices, driving_gear=driving_gear,
                                    positions=positions),
              "spur_unmodified": harris_map(spur, None, span, driving_gear=driving_gear, positions=positions),
              "spur_optimised": harris_map(spur, opt.microgeometry, span, driving_gear=driving_gear,
                                           positions=positions)}
    times["harris_s"] = time.perf_counter() - t0
    summary = pd.DataFrame([_summary_row(d, results[d]) for d in DESIGNS])
    return MeshContactStudy(mesh=mesh, torque_Nm=torque_Nm, speed_rpm=speed, driving_gear=driving_gear,
                            ltca=results, optimisation=opt, harris=harris, summary=summary, times_s=times)


__all__ = ["mesh_contact_study", "MeshContactStudy", "DESIGNS"]
