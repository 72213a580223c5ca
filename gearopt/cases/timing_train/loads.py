"""The timing train's quasi-static accessory load case: the shaft load torques its camshaft, air compressor, fuel
pump and lube pump gears (``cam``, ``ac``, ``fp``, ``lpg``) deliver to their accessories, from the ``[engine.*]``
section of the packaged data (all [E] estimates), and the per-mesh torques that carry them from the crank
(:func:`~gearopt.joints.walk_off.quasi_static_mesh_torques_Nm`).

The gear names are this train's: the library (joints, report) knows none of them. The report tables take the load
case as a ``(torques, description)`` pair: ``joint_table(system, "helical", quasi_static_load_case(system,
"helical"))``.
"""

from __future__ import annotations

from typing import Any

from ...data import System, system_of, train_from_data
from ...errors import GearoptInputError
from ...geometry.train import GearTrain
from ...joints.walk_off import quasi_static_mesh_torques_Nm

QUASI_STATIC_CASE = ("quasi-static accessory peaks (valve train mean + amplitude, AC and FP peaks, lube pump mean; "
                     "[E] engine data, summed as if simultaneous, no torsional vibration)")
"""Description of :func:`quasi_static_load_case` (the report tables' ``load_case`` attribute)."""


def accessory_load_torques_Nm(system: System, case: str = "peak") -> dict[str, float]:
    """Shaft load torques [N m] each accessory gear of the timing train delivers to its accessory, from
    ``[engine.*]`` of ``system`` (a :class:`~gearopt.data.System`; all [E] estimates):

    ``"peak"``: camshaft valve train mean + amplitude, air compressor peak, fuel pump peak, lube pump mean;
    ``"mean"``: the mean values (air compressor loaded mean). Combine with
    :func:`~gearopt.joints.walk_off.quasi_static_mesh_torques_Nm` for a quasi-static load case
    (:func:`quasi_static_load_case`); dynamic torques (torsional vibration at overspeed, the cause of the thesis'
    failure) come from the dynamics models instead. A system without ``[engine]`` raises
    :class:`~gearopt.errors.MissingSectionError` naming the file.
    """
    system = system_of(system, "accessory_load_torques_Nm")
    e = system.section("engine", "accessory_load_torques_Nm")
    if case == "peak":
        return {"cam": e["camshaft"]["valve_train_torque_mean_Nm"] + e["camshaft"]["valve_train_torque_amplitude_Nm"],
                "ac": e["air_compressor"]["torque_peak_Nm"], "fp": e["fuel_pump"]["torque_peak_Nm"],
                "lpg": e["lube_pump"]["torque_mean_Nm"]}
    if case == "mean":
        return {"cam": e["camshaft"]["valve_train_torque_mean_Nm"],
                "ac": e["air_compressor"]["torque_mean_loaded_Nm"], "fp": e["fuel_pump"]["torque_mean_Nm"],
                "lpg": e["lube_pump"]["torque_mean_Nm"]}
    raise GearoptInputError(f"case={case!r} must be 'peak' or 'mean'")


def quasi_static_load_case(system: System, train: str | GearTrain = "spur") -> tuple[dict[str, Any], str]:
    """``(torques, description)``: the per-mesh torques [N m] (on each mesh's first gear, + = it drives) of the
    accessory peaks (:func:`accessory_load_torques_Nm` ``"peak"``) carried from the root gear of ``train``
    (``"spur"``/``"helical"`` built from ``system``, or a :class:`~gearopt.geometry.GearTrain`), and
    :data:`QUASI_STATIC_CASE`. The pair is a load case of :func:`gearopt.report.joint_tables.joint_table` and
    :func:`~gearopt.report.joint_tables.web_table`. A system without ``[engine]`` raises
    :class:`~gearopt.errors.MissingSectionError` naming the file and this load case."""
    system = system_of(system, "quasi_static_load_case")
    system.require("engine", "the quasi-static accessory load case (quasi_static_load_case)")
    tr = train if isinstance(train, GearTrain) else train_from_data(system.data, train)
    return quasi_static_mesh_torques_Nm(tr, accessory_load_torques_Nm(system, "peak")), QUASI_STATIC_CASE


__all__ = ["accessory_load_torques_Nm", "quasi_static_load_case", "QUASI_STATIC_CASE"]
