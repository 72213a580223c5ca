"""The timing-train case: the packaged diesel engine's timing gear train (``gearopt/data/default_train.toml``).

Everything that knows this train by name lives here: its torsional model with the engine, camshaft and accessory
drives (:mod:`.model`), the co-design study of its spur and low-helix options (:mod:`.codesign`), the failure
reproduction of the helical cam gear's walk-off (:mod:`.failure`), the comparison with the source study's macro
design tables (:mod:`.macro_design`), its quasi-static accessory load case (:mod:`.loads`) and the verdict-first summary of the main job's result (:mod:`.summary`).
``problems/cam_gear_walkoff.py`` runs them.
"""

from ...data import System, system_of
from .codesign import (CONTACT_STRESS_ALLOWANCE, GEOMETRY_LIMITS, MESHES, WALK_OFF_JOINTS, CodesignOption,
                       CodesignStudy, codesign_study)
from .failure import FIELD_RATE, HELICAL_ALTERNATIVES, failure_reproduction
from .loads import QUASI_STATIC_CASE, accessory_load_torques_Nm, quasi_static_load_case
from .model import TimingModel, default_timing_model


def timing_model(system: System, kind: str = "spur", **options) -> TimingModel:
    """The timing-system model of a :class:`~gearopt.data.System` of the packaged timing train's layout (an
    ``[engine]`` section and the timing train's gears): :func:`default_timing_model` of the system."""
    return default_timing_model(kind, system=system_of(system, "timing_model"), **options)


__all__ = ["TimingModel", "default_timing_model", "timing_model", "codesign_study", "CodesignStudy",
           "CodesignOption", "MESHES", "WALK_OFF_JOINTS", "GEOMETRY_LIMITS",
           "CONTACT_STRESS_ALLOWANCE", "failure_reproduction", "FIELD_RATE", "HELICAL_ALTERNATIVES",
           "accessory_load_torques_Nm", "quasi_static_load_case", "QUASI_STATIC_CASE"]
