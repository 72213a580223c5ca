"""The inputs of a built scene: every read of the scene's data set goes through :class:`SceneInputs`.

The data set (``Scene.data``, a :class:`~gearopt.data.System`; required by the quantities below) gives the
shaft-hub joints (``[joints.*]``: their entries and capacities), the gear blanks, the gear materials of the ISO 6336
rating; a dynamic load case (:meth:`~gearopt.design.scene_spec.LoadCase.from_dynamics`) becomes a given one by one
simulation of the scene's ``dynamics_model``. In a parametric build (``Scene.build(parametric=True)``) the data a
quantity uses enters the NLP as a :class:`~gearopt.nlp.problem.Problem` parameter (:meth:`SceneInputs.datum`,
listed in ``data_parameters``). Only this class reads the data set.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Iterable, Sequence

import numpy as np

from .. import numerics as nm
from ..blank import blank_from_data
from ..data import System, system_of
from ..dynamics import walk_off_history
from ..errors import GearoptInputError
from ..geometry.forces import mesh_torque_Nm
from ..joints import joint_capacity
from ..nlp.problem import Problem
from ..rating.materials import material_pair
from .scene_cache import ModelCache
from .scene_spec import LoadCase

JOINT_DATA = {"press_fit": (("friction_coefficient", ""), ("diametral_interference_um", "um"), ("fit_length_mm", "mm"),
                           ("shaft_diameter_mm", "mm"), ("hub_outer_diameter_mm", "mm")),
              "taper_nut": (("friction_coefficient", ""), ("nut_torque_Nm", "N*m"), ("nut_factor", ""),
                            ("taper_length_mm", "mm"))}
"""Entries of a ``[joints.*]`` record that a parametric build declares as NLP parameters (name, unit): the data a
joint's capacity depends on most (friction, interference or preload, fit geometry)."""


class SceneInputs:
    """The data set of a scene (``scene.data``: a :class:`~gearopt.data.System`; required by joint, blank and
    rating-material quantities), the dynamic load cases resolved against it, and the data that enter a parametric
    NLP.

    Public interface: :meth:`system`, :meth:`joint_names`, :meth:`joint_entry`,
    :meth:`joint_overrides`, :meth:`joint_capacity`, :meth:`blank`, :meth:`rating_materials`,
    :meth:`resolve_load_case`, :meth:`datum` and :attr:`data_parameters` (name -> value, unit, symbol).
    """

    def __init__(self, scene, cache: ModelCache, problem: Problem, parametric: bool = False):
        self.scene = scene
        self.cache = cache
        self.problem = problem
        self.parametric = bool(parametric)
        self.data_parameters: dict[str, dict[str, Any]] = {}

    # -- the data set ----------------------------------------------------------------------------------------------

    def system(self) -> System:
        """The scene's data set (``scene.data``, a :class:`~gearopt.data.System`); a scene without one raises
        naming what needs it (the packaged data are never read behind the caller's back), a raw dict raises naming
        the conversion."""
        if self.scene.data is None:
            raise GearoptInputError(f"scene {self.scene.name!r} needs a data set for its joints, blanks or rating "
                                    "materials: give Scene(data=gearopt.load_system(path)) (or the packaged timing "
                                    "train's gearopt.load_system())")
        return self.cache.get("data:validated", lambda: system_of(self.scene.data, f"scene {self.scene.name!r}"),
                              "the scene's data set")

    def joint_names(self) -> list[str]:
        """The ``[joints.*]`` entries of the data set."""
        return sorted(self.system().joints)

    def has_joint(self, joint: str) -> bool:
        return joint in self.system().joints

    def joint_entry(self, joint: str) -> dict:
        """The entries of the ``[joints.<joint>]`` record (values, units in the key names)."""
        return dict(self.system().joints[joint].entries)

    def joint_overrides(self, joint: str, overrides: dict[str, Any]) -> dict[str, Any]:
        """``overrides`` (the joint's free variables, by data key) plus, in a parametric build, the joint data of
        :data:`JOINT_DATA` not already free, as parameters."""
        if self.parametric:
            entry = self.joint_entry(joint)
            for key, unit in JOINT_DATA.get(entry["joint_type"], ()):
                if key not in overrides and key in entry:
                    overrides[key] = self.datum(f"{key}[{joint}]", entry[key], unit)
        return overrides

    def joint_capacity(self, joint: str, speed_rpm: float, overrides: dict[str, Any]) -> dict:
        """Capacity of ``joint`` at ``speed_rpm`` with the data entries of ``overrides`` replaced
        (:func:`gearopt.joints.joint_capacity`)."""
        return joint_capacity(self.system(), joint, speed_rpm=speed_rpm, overrides=overrides)

    def blank(self, gear: str):
        """The :class:`~gearopt.blank.GearBlank` of ``gear`` of the scene's train from the data set."""
        blank, _ = blank_from_data(self.system(), self.scene.train, gear)
        return blank

    def rating_materials(self, names: Sequence[str], materials) -> tuple:
        """Both gears' materials (``names``: the gears, for the parameter names) with their endurance limits
        sigma_Hlim, sigma_Flim as data (parametric build)."""
        out = []
        for name, m in zip(names, material_pair(materials)):
            limits = {key: self.datum(f"{key}[{name}]", getattr(m, key), "MPa")
                      for key in ("sigma_Hlim_MPa", "sigma_Flim_MPa") if getattr(m, key) is not None}
            out.append(replace(m, **limits))
        return tuple(out)

    # -- dynamic load cases --------------------------------------------------------------------------------------

    def resolve_load_case(self, lc: LoadCase, joints: Iterable[str] = ()) -> LoadCase:
        """A dynamic load case becomes a given one: mesh torques and the demands of ``joints`` from one
        simulation of the scene's ``dynamics_model`` (the model and each simulation built once)."""
        if lc.dynamics is None:
            return lc
        dyn = lc.dynamics
        if self.scene.dynamics_model is None:
            raise GearoptInputError(f"load case {lc.name!r} takes its loads from the dynamics: give the scene a "
                                    "dynamics_model (kind -> torsional model of the scene's train, e.g. "
                                    "lambda kind: gearopt.dynamics.train_model(system, kind))")
        model = self.cache.get(f"dynamics:{dyn['kind']}", lambda: self.scene.dynamics_model(dyn["kind"]),
                               f"torsional model ({dyn['kind']})")
        key = f"simulation:{dyn['kind']}@{lc.speed_rpm:g}rpm{',backlash' if dyn['backlash'] else ''}"
        sim = self.cache.get(key, lambda: model.simulate(speed_rpm=lc.speed_rpm, cycles=dyn["cycles"],
                                                         backlash=dyn["backlash"]),
                             f"{dyn['cycles']} cycle(s), statistic {dyn['statistic']}")
        torques = {}
        for mesh in sim.mesh_force_N.columns:
            force = np.abs(sim.mesh_force_N[mesh].to_numpy())
            stat = force.max() if dyn["statistic"] == "peak" else np.sqrt(np.mean(force ** 2))
            torques[mesh] = float(mesh_torque_Nm(stat, sim.mesh_base_radii_mm[mesh][0]))
        jt, ja = {}, {}
        for joint in sorted(joints):
            w = walk_off_history(model, sim, joint)
            jt[joint] = float(np.max(np.abs(w["joint_torque_Nm"])))
            ja[joint] = float(np.max(np.abs(w["axial_force_N"])))
        return LoadCase(name=lc.name, torque_Nm=torques, speed_rpm=lc.speed_rpm, joint_torque_Nm=jt,
                        joint_axial_force_N=ja, iso6336_options=lc.iso6336_options)

    # -- data as NLP parameters ----------------------------------------------------------------------------------

    def datum(self, name: str, value: float, unit: str):
        """A datum a quantity uses: the number itself, or (``parametric`` build) a :class:`Problem` parameter of
        that value, declared once per name and listed in ``data_parameters`` (name -> value, unit)."""
        if not self.parametric or not nm.is_numeric(value):
            return value
        if name not in self.data_parameters:
            symbol = self.problem.parameter(name, float(value), unit=unit)
            self.data_parameters[name] = {"value": float(value), "unit": unit, "symbol": symbol}
        return self.data_parameters[name]["symbol"]


__all__ = ["SceneInputs", "JOINT_DATA"]
