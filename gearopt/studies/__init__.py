"""Studies: multi-model comparisons, trade-off fronts, sensitivity reports and tolerance robustness, on one executor.

- :func:`pareto_front`: the front between a scene's objective and a second quantity (ε-constraint continuation);
  :func:`verify_front`: each of its points re-solved by the scene's exact-LTCA refinement;
- :func:`sensitivity_report`: d objective / d limit (multipliers) and d objective / d datum (KKT system), absolute and
  logarithmic; :func:`limit_move_check`: each active limit moved ±0.5 % and re-solved on its branch, the exact
  optimum's change against the reported sensitivity;
- :func:`monte_carlo`, :func:`sobol_indices`: distributions, probabilities of broken limits and Sobol indices over
  the tolerances (:class:`Tolerance`); :func:`robust_design`: the scene's limits held at the tolerance corners;
- :func:`scene_study`: the three above for one scene, with a report section;
- :func:`calibrate_walk_off`: the walk-off failure model's estimated inputs calibrated against a fleet's failure
  counts (:class:`FieldEvidence`; :func:`field_record` reads them from a data file), with what the field rules out
  and the walk-off probabilities on the calibrated inputs;
- every batch runs on :mod:`gearopt.executor` (serial, local processes or a Dask cluster).
"""

from .calibration import (Calibration, FieldEvidence, UncertainInput, WalkOffModel, calibrate_walk_off, field_record,
                          recheck_on_calibrated_inputs)
from .contact_study import DESIGNS, MeshContactStudy, mesh_contact_study
from .front_check import verify_front
from .monte_carlo import MonteCarloResult, monte_carlo, sobol_indices
from .parametric import KKTSensitivity, kkt_sensitivity
from .pareto import ParetoFront, pareto_front
from .robust import robust_design
from .scene_study import SceneStudy, relief_scene_from_data, scene_study
from .sensitivity import SensitivityReport, limit_move_check, sensitivity_report
from .tolerances import Tolerance, default_tolerances

__all__ = ["calibrate_walk_off", "Calibration", "FieldEvidence", "UncertainInput", "WalkOffModel", "field_record",
           "recheck_on_calibrated_inputs", "mesh_contact_study", "MeshContactStudy", "DESIGNS", "pareto_front", "ParetoFront", "verify_front",
           "sensitivity_report", "SensitivityReport", "limit_move_check", "kkt_sensitivity",
           "KKTSensitivity", "robust_design", "monte_carlo", "sobol_indices", "MonteCarloResult", "Tolerance",
           "default_tolerances", "scene_study", "SceneStudy", "relief_scene_from_data"]
