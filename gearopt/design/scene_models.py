"""The model graph of a built scene (:class:`SceneModels`): each model a quantity needs, built once per target into
the build's :class:`~gearopt.design.scene_cache.ModelCache` -- the geometry of each mesh, the symbolic train, the
walk-off demands, the ISO 6336 stress and rating models, the joint capacities and the gear blanks. The contact
models (smooth and macro LTCA, microgeometry, exact check) are :class:`~gearopt.design.scene_contact.ContactModels`,
built on this graph.

Macro geometry: symbolic in train-level variables (``root_profile_shift``, ``helix_angle_deg`` of the
:class:`~gearopt.geometry.train.GearTrain`: every mesh follows at its fixed centre distance) or in mesh-level macro
variables. The design variables are the transcription's symbols
(:class:`~gearopt.design.scene_transcription.SceneTranscription` declares them into ``variables``, the mapping
shared with this graph); the graph evaluates its models at them. The data set is read through
:class:`~gearopt.design.scene_inputs.SceneInputs` only.

Walk-off in the NLP: when a load case gives no ``joint_axial_force_N`` for a joint, the axial force on the joint's
gear follows from the load case's mesh torques and the (possibly symbolic) helix angle by
:func:`gearopt.joints.walk_off.walk_off` (``F_z = -h tan(beta_w) F_theta`` summed over the gear's meshes). A margin
limit ``capacity / |demand| >= S`` with a symbolic demand is imposed as ``capacity^2 - S^2 demand^2 >= 0``: equal
where the demand is nonzero and smooth where it vanishes (a spur train).
"""

from __future__ import annotations

import inspect
import threading
import warnings
from dataclasses import replace
from typing import Any, Callable, Mapping

from .. import numerics as nm
from ..errors import GearoptInputError
from ..geometry.pair import GearPair
from ..geometry.train import GearTrain
from ..joints.walk_off import walk_off
from ..nlp.problem import Problem
from ..rating import (RatingValidityWarning, StiffnessValidityWarning, contact_stress_iso6336, rate_iso6336,
                      root_stress_iso6336)
from .positions import corner_values
from .scene_cache import ModelCache
from .scene_inputs import SceneInputs
from .scene_options import LTCAOptions
from .scene_spec import LoadCase
from .scene_terms import variable_kind

TRAIN_TARGET = "train"
TRAIN_FIELDS = {"root_profile_shift": "root_profile_shift", "helix_angle_deg": "helix_angle_deg"}
CONTACT_KEYS = {"K_A", "K_v", "K_Hbeta", "K_Halpha", "material", "life_factor", "Z_L", "Z_v", "Z_R", "Z_W", "Z_X",
                "S_Hmin"}
ROOT_KEYS = {"K_A", "K_v", "K_Fbeta", "K_Falpha", "material", "life_factor", "Y_ST", "Y_deltarelT", "Y_RrelT", "Y_X",
             "S_Fmin", "rim_backup_ratio", "accuracy_grade"}
"""``iso6336_options`` keys of :func:`~gearopt.rating.contact_stress_iso6336` and
:func:`~gearopt.rating.root_stress_iso6336`."""


TRAIN_CACHE_SIZE = 8
"""Trains :meth:`SceneModels.train_at` keeps (the most recently used)."""
_TRAINS_LOCK = threading.Lock()


class SceneModels:
    """The model graph of one build (module docstring).

    Args:
        scene: the :class:`~gearopt.design.scene.Scene` declared.
        options: the build's :class:`~gearopt.design.scene_options.LTCAOptions` (the defaults with the data's,
            the scene's and the build's overrides).
        inputs: the build's :class:`~gearopt.design.scene_inputs.SceneInputs` (data set, parameters).
        cache: the build's :class:`~gearopt.design.scene_cache.ModelCache`.
        variables: ``(target, name)`` -> the design variable's symbol, filled by the transcription.
        problem: the build's :class:`Problem` (bounds and starts of the variables).

    Public interface: the declaration's ``meshes`` and ``needs``, the resolved ``load_cases``
    (:meth:`resolve_load_cases`), :meth:`model` (get or build a model), :meth:`driving_gear`,
    :meth:`driver_speed_rpm`, :meth:`free`, :meth:`helix_free`, :meth:`macro_free`, :meth:`pair`,
    :meth:`numeric_pair`, :meth:`geometry`, :meth:`train_at`, :meth:`contact_ratio_bounds`, :meth:`initial_values`,
    :meth:`joint_torque_Nm`, :meth:`joint_axial_force_N`, :meth:`walk_off`, :meth:`iso`, :meth:`rating`,
    :meth:`joint`, :meth:`blank`.
    """

    def __init__(self, scene, options: LTCAOptions, inputs: SceneInputs, cache: ModelCache,
                 variables: dict[tuple[str, str], Any], problem: Problem):
        self.scene = scene
        self.options = options
        self.inputs = inputs
        self.cache = cache
        self.variables = variables
        self.problem = problem
        self.meshes: dict[str, GearPair] = scene.meshes()
        self.needs: dict[str, set[str]] = scene.needs()
        self.load_cases: list[LoadCase] = list(scene.load_cases)
        self._trains: dict[tuple, GearTrain] = {}      # train_at's recent trains by their variables' values

    @property
    def parametric(self) -> bool:
        return self.inputs.parametric

    def model(self, key: str, build: Callable[[], Any], detail: Callable[[Any], str] | str = "") -> Any:
        """The model under ``key``, built once (:meth:`ModelCache.get`)."""
        return self.cache.get(key, build, detail)

    def resolve_load_cases(self) -> list[LoadCase]:
        """Resolve the scene's load cases (a dynamic one by one simulation, with the demands of the joints the
        scene's quantities name) into :attr:`load_cases`."""
        joints = {t for t, needs in self.needs.items() if "joint" in needs}
        self.load_cases = [self.inputs.resolve_load_case(lc, joints) for lc in self.scene.load_cases]
        return self.load_cases

    # -- meshes --------------------------------------------------------------------------------------------------

    def driving_gear(self, mesh: str) -> int:
        d = self.scene.driving_gear
        g = d.get(mesh, 1) if isinstance(d, Mapping) else d
        if g not in (1, 2):
            raise GearoptInputError(f"driving_gear[{mesh}]={g!r} must be 1 or 2")
        return int(g)

    def driver_speed_rpm(self, mesh: str, crank_speed_rpm: float) -> float:
        """Speed of the mesh's driving gear at a crank (root gear) speed."""
        name = self.meshes[mesh].names[self.driving_gear(mesh) - 1]
        train = self.scene.train
        return train.gear_speed_rpm(name, crank_speed_rpm) if train is not None else crank_speed_rpm

    # -- design variables -----------------------------------------------------------------------------------------

    def free(self, target: str, group: str) -> dict[str, Any]:
        """The free variables of ``target`` in ``group`` (name -> symbol)."""
        return {name: x for (t, name), x in self.variables.items()
                if t == target and variable_kind(name).group == group}

    def helix_free(self) -> bool:
        return (TRAIN_TARGET, "helix_angle_deg") in self.variables

    def initial_values(self) -> dict[str, float]:
        """The declared start of every design variable (``"target.variable"`` keys)."""
        return {f"{t}.{n}": float(self.problem._variables[f"{t}.{n}"].init[0]) for (t, n) in self.variables}

    # -- geometry ------------------------------------------------------------------------------------------------

    def _train_values(self, values: Mapping[str, float] | None = None) -> dict[str, Any]:
        free = self.free(TRAIN_TARGET, "train")
        if values is not None:
            free = {n: values[f"{TRAIN_TARGET}.{n}"] for n in free}
        return {TRAIN_FIELDS[n]: x for n, x in free.items()}

    def symbolic_train(self) -> GearTrain:
        free = self._train_values()
        return self.model("train:symbolic", lambda: replace(self.scene.train, **free),
                          f"symbolic in {sorted(free)}")

    def train_at(self, values: Mapping[str, float]) -> GearTrain:
        """The scene's train with the train-level variables at ``values`` (``"train.variable"`` keys). The last
        :data:`TRAIN_CACHE_SIZE` trains are kept by their values: an exact evaluation asks for the train of one
        design several times (its geometry limits, its exact LTCA), and building one propagates the shifts through
        every mesh (milliseconds)."""
        free = self._train_values(values)
        if not free:
            return self.scene.train
        if any(nm.is_symbolic(v) for v in free.values()):
            return replace(self.scene.train, **free)
        key = tuple(sorted((k, float(v)) for k, v in free.items()))
        with _TRAINS_LOCK:
            train = self._trains.pop(key, None)
        if train is None:
            train = replace(self.scene.train, **free)
        with _TRAINS_LOCK:                                  # a thread of a Dask worker may evaluate beside another
            self._trains.pop(key, None)
            while len(self._trains) >= TRAIN_CACHE_SIZE:
                self._trains.pop(next(iter(self._trains)))
            self._trains[key] = train                       # most recent last
        return train

    def macro_free(self, mesh: str) -> bool:
        """Whether the mesh's macro geometry depends on design variables."""
        train_mesh = self.scene.train is not None and mesh in self.scene.train.pairs and \
            bool(self.free(TRAIN_TARGET, "train"))
        return train_mesh or bool(self.free(mesh, "macro"))

    def pair(self, mesh: str) -> GearPair:
        """The mesh's pair, symbolic in the free macro variables (the model ``geometry:<mesh>``)."""
        macro = self.free(mesh, "macro")
        train_mesh = self.scene.train is not None and mesh in self.scene.train.pairs and \
            bool(self.free(TRAIN_TARGET, "train")) and mesh not in (self.scene.pairs or {})

        def build():
            pair = self.symbolic_train().pairs[mesh] if train_mesh else self.meshes[mesh]
            return _with_mesh_macro(pair, macro)

        if macro or train_mesh:
            detail = f"symbolic in {sorted(macro) or sorted(self.free(TRAIN_TARGET, 'train'))}"
        else:
            detail = "numeric"
        return self.model(f"geometry:{mesh}", build, detail)

    def numeric_pair(self, mesh: str, values: Mapping[str, float]) -> GearPair:
        """The mesh's pair at the design ``values`` (numbers)."""
        pair = self.meshes[mesh]
        if self.free(TRAIN_TARGET, "train") and mesh in self.scene.train.pairs \
                and mesh not in (self.scene.pairs or {}):
            pair = self.train_at(values).pairs[mesh]
        macro = {n: values[f"{mesh}.{n}"] for n in self.free(mesh, "macro")}
        return _with_mesh_macro(pair, macro)

    def geometry(self, mesh: str) -> dict:
        return self.pair(mesh).geometry()

    def contact_ratio_bounds(self, mesh: str) -> tuple[float, float]:
        """Largest transverse and overlap ratios of ``mesh`` over the corners of the macro bounds (+0.2 each): they
        fix the tooth pairs of the macro-symbolic LTCA."""
        bounds = {f"{t}.{n}": (entry.lower[0], entry.upper[0]) for (t, n), entry in
                  ((k, self.problem._variables[f"{k[0]}.{k[1]}"]) for k in self.variables)
                  if t in (TRAIN_TARGET, mesh) and variable_kind(n).group in ("train", "macro")}
        eps_a, eps_b = [], []
        for corner in corner_values(bounds):
            values = {**self.initial_values(), **corner}
            try:
                g = self.numeric_pair(mesh, values).geometry()
            except GearoptInputError:
                continue
            eps_a.append(float(g["transverse_contact_ratio"]))
            eps_b.append(float(g["overlap_contact_ratio"]))
        if not eps_a:
            raise GearoptInputError(f"mesh {mesh!r}: no corner of the macro bounds {bounds} gives a valid geometry")
        return max(eps_a) + 0.2, max(eps_b) + (0.2 if max(eps_b) > 0 else 0.0)

    # -- ISO 6336 ------------------------------------------------------------------------------------------------

    def iso(self, mesh: str, lc: LoadCase) -> dict:
        """ISO 6336-2/-3 method B contact and root stress at ``lc`` (keywords from the scene's ``iso6336_options``,
        then the load case's)."""
        opts = {**self.scene.iso6336_options, **lc.iso6336_options}

        def build():
            pair, g = self.pair(mesh), self.driving_gear(mesh)
            torque = self.inputs.datum(f"torque_Nm[{mesh}]@{lc.name}", lc.mesh_torque_Nm(mesh), "N*m")
            if self.parametric:
                opts["material"] = self.inputs.rating_materials(self.meshes[mesh].names,
                                                                opts.get("material", "20MnCr5"))
            return {"contact": contact_stress_iso6336(pair, torque, driving_gear=g,
                                                      **{k: v for k, v in opts.items() if k in CONTACT_KEYS}),
                    "root": root_stress_iso6336(pair, torque, driving_gear=g,
                                                **{k: v for k, v in opts.items() if k in ROOT_KEYS})}

        return self.model(f"iso6336:{mesh}@{lc.name}", build, f"ISO 6336-2/-3 method B at {lc.name}")

    def rating(self, mesh: str, lc: LoadCase):
        """ISO 6336 rating with computed factors (``rate_iso6336``; its keywords from the scene's ``iso6336_options``,
        then the load case's: ``LoadCase.iso6336_options``). Without
        an ``accuracy_grade`` or ``materials`` there, the mesh's gears' own: the data's ISO 1328 grades (a scene with
        ``data``; 6 where a gear states none) and the train's gear materials -- what the verdict's rating table
        (:func:`gearopt.design.requirements.rating_table`) uses."""
        if lc.speed_rpm is None:
            raise GearoptInputError(f"load case {lc.name!r} needs speed_rpm for the ISO 6336 rating of {mesh!r}")
        allowed = set(inspect.signature(rate_iso6336).parameters) - {"pair", "torque_Nm", "speed_rpm", "driving_gear"}
        given = {**self.scene.iso6336_options, **lc.iso6336_options}
        unknown = sorted(set(lc.iso6336_options) - allowed)
        if unknown:
            raise GearoptInputError(f"load case {lc.name!r}: iso6336_options {unknown} are not keywords of "
                                    f"rate_iso6336 ({sorted(allowed)})")
        opts = {k: v for k, v in given.items() if k in allowed}
        opts.update({k: v for k, v in self._gear_rating_options(mesh).items() if k not in opts})
        # the scuffing ratings only where a quantity of the scene asks for them (most of a symbolic rating's build)
        opts.setdefault("scuffing", any(q.quantity.startswith("scuffing_safety_factor") and q.target == mesh
                                        and (not q.load_cases or lc.name in q.load_cases)
                                        for q in (*self.scene.objectives, *self.scene.limits)))

        def build():
            torque = self.inputs.datum(f"torque_Nm[{mesh}]@{lc.name}", lc.mesh_torque_Nm(mesh), "N*m")
            speed = self.inputs.datum(f"speed_rpm[{mesh}]@{lc.name}", self.driver_speed_rpm(mesh, lc.speed_rpm),
                                      "rpm")
            if self.parametric:
                opts["materials"] = self.inputs.rating_materials(self.meshes[mesh].names,
                                                                 opts.get("materials", "20MnCr5"))
            with warnings.catch_warnings(record=True) as caught:     # the standard's validity notes go to the
                warnings.simplefilter("always")                      # build table, as the rating table's do
                # a symbolic rating: one call of an SX kernel traced once per process (numerics.traced_call)
                rating = nm.traced_call(rate_iso6336, self.pair(mesh), torque, speed,
                                        driving_gear=self.driving_gear(mesh), **opts)
            for w in caught:
                if issubclass(w.category, (RatingValidityWarning, StiffnessValidityWarning)):
                    validity.append(str(w.message))
                else:
                    warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
            return rating

        validity: list[str] = []
        return self.model(f"iso6336_rating:{mesh}@{lc.name}", build, lambda _: (
            f"ISO 6336 rating (computed factors) at {lc.name}"
            + (f"; validity: {'; '.join(sorted(set(validity)))}" if validity else "")))

    def _gear_rating_options(self, mesh: str) -> dict:
        """The mesh's gears' accuracy grades (from the scene's data) and materials (from its train), where known."""
        names, out = self.meshes[mesh].names, {}
        if self.scene.data is not None:
            gears = self.inputs.system().gears
            out["accuracy_grade"] = tuple(int(gears[g].accuracy_grade_iso1328) if g in gears and
                                          gears[g].accuracy_grade_iso1328 is not None else 6 for g in names)
        train = self.scene.train
        if train is not None and all(g in train.gears and train.gears[g].material for g in names):
            out["materials"] = tuple(train.gears[g].material for g in names)
        return out

    # -- joints and blanks ---------------------------------------------------------------------------------------

    def joint(self, joint: str, lc: LoadCase | None) -> dict:
        """Capacity of ``joint`` at the load case's speed, with its free variables (and, parametric, its data)."""
        overrides = {variable_kind(name).key or name: x for name, x in self.free(joint, "joint").items()}
        overrides = self.inputs.joint_overrides(joint, overrides)
        speed = lc.speed_rpm if (lc is not None and lc.speed_rpm is not None) else 0.0
        return self.model(f"joint:{joint}@{speed:g}rpm",
                          lambda: self.inputs.joint_capacity(joint, speed, overrides),
                          f"capacity at {speed:g} rpm, free {sorted(overrides)}")

    def blank(self, gear: str, symbolic: bool = True):
        """The gear's blank from the data set; ``symbolic``: with its free variables (the model ``blank:<gear>``)."""
        blank = self.inputs.blank(gear)
        if not symbolic:
            return blank
        free = self.free(gear, "blank")
        return self.model(f"blank:{gear}", lambda: replace(blank, **free), f"free {sorted(free)}")

    # -- walk-off ------------------------------------------------------------------------------------------------

    def joint_axial_force_N(self, joint: str, lc: LoadCase):
        """Axial force on ``joint``'s gear at ``lc`` [N]: the load case's own demand if it gives one, else from the
        load case's mesh torques and the train's (possibly symbolic) helix angle."""
        if joint in lc.joint_axial_force_N:
            return float(lc.joint_axial_force_N[joint])
        return self.walk_off(lc).axial_force_N[self._joint_gear(joint)]

    def joint_torque_Nm(self, joint: str, lc: LoadCase):
        """Torque through ``joint`` at ``lc`` [N m]: the load case's own demand, else the net mesh torque on its
        gear."""
        if joint in lc.joint_torque_Nm:
            return float(lc.joint_torque_Nm[joint])
        return nm.to_float(self.walk_off(lc).joint_torque_Nm[self._joint_gear(joint)])

    def _joint_gear(self, joint: str) -> str:
        gear = self.inputs.joint_entry(joint).get("gear")
        if self.scene.train is None or gear not in self.scene.train.gears:
            raise GearoptInputError(f"joint {joint!r}: its demand is not in the load case and its gear {gear!r} is "
                                    f"not a gear of the scene's train (give joint_torque_Nm/joint_axial_force_N)")
        return gear

    def walk_off(self, lc: LoadCase):
        """Axial forces and joint torques of the train at ``lc`` from its mesh torques (the model
        ``walk_off@<load case>``)."""
        train = self.symbolic_train() if self.free(TRAIN_TARGET, "train") else self.scene.train
        if train is None:
            raise GearoptInputError("walk-off demands need the scene's train")

        def build():
            torques = {}
            for mesh, spec in train.meshes.items():
                t = lc.torque_Nm.get(mesh) if isinstance(lc.torque_Nm, Mapping) else lc.torque_Nm
                if t is None:
                    continue
                pair = train.pairs[mesh]
                torques[mesh] = t if self.driving_gear(mesh) == 1 else -t * pair.teeth[0] / pair.teeth[1]
            return walk_off(train, torques, root_rotation=self.options.root_rotation)

        return self.model(f"walk_off@{lc.name}", build, "axial forces and joint torques from the mesh torques")


def _with_mesh_macro(pair: GearPair, macro: Mapping[str, Any]) -> GearPair:
    if "profile_shift_1" in macro:
        x1 = macro["profile_shift_1"]
        pair = replace(pair, profile_shifts=(x1, pair.profile_shifts[0] + pair.profile_shifts[1] - x1),
                       tip_diameters_mm=None)
    if "face_width_mm" in macro:
        pair = replace(pair, face_width_mm=(macro["face_width_mm"], macro["face_width_mm"]))
    if "tip_diameter_1_mm" in macro or "tip_diameter_2_mm" in macro:
        d = pair.geometry()["tip_diameter_mm"]
        pair = replace(pair, tip_diameters_mm=(macro.get("tip_diameter_1_mm", d[0]),
                                               macro.get("tip_diameter_2_mm", d[1])))
    return pair


__all__ = ["SceneModels", "TRAIN_TARGET", "TRAIN_FIELDS"]
