"""The macro side of a built scene: the geometry of each mesh, symbolic in train-level variables
(``root_profile_shift``, ``helix_angle_deg`` of the :class:`~gearopt.geometry.train.GearTrain`: every mesh follows at
its fixed centre distance) or in mesh-level macro variables, and the walk-off demand on each shaft-hub joint.

Walk-off in the NLP: when a load case gives no ``joint_axial_force_N`` for a joint, the axial force on the joint's
gear follows from the load case's mesh torques and the (possibly symbolic) helix angle by
:func:`gearopt.joints.walk_off.walk_off` (``F_z = -h tan(beta_w) F_theta`` summed over the gear's meshes). A margin
limit ``capacity / |demand| >= S`` with a symbolic demand is imposed as ``capacity^2 - S^2 demand^2 >= 0``: equal
where the demand is nonzero and smooth where it vanishes (a spur train).
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping

from .. import numerics as nm
from ..errors import GearoptInputError
from ..geometry.pair import GearPair
from ..geometry.train import GearTrain
from .scene_contact import corner_values
from .scene_spec import LoadCase
from .scene_terms import variable_kind

TRAIN_TARGET = "train"
TRAIN_FIELDS = {"root_profile_shift": "root_profile_shift", "helix_angle_deg": "helix_angle_deg"}


class TrainModels:
    """Mixin of :class:`~gearopt.design.scene.BuiltScene`: geometry and walk-off."""

    def _free(self, target: str, group: str) -> dict[str, Any]:
        return {name: x for (t, name), x in self._variables.items()
                if t == target and variable_kind(name).group == group}

    def _helix_free(self) -> bool:
        return (TRAIN_TARGET, "helix_angle_deg") in self._variables

    def _train_values(self, values: Mapping[str, float] | None = None) -> dict[str, Any]:
        free = self._free(TRAIN_TARGET, "train")
        if values is not None:
            free = {n: values[f"{TRAIN_TARGET}.{n}"] for n in free}
        return {TRAIN_FIELDS[n]: x for n, x in free.items()}

    def _symbolic_train(self) -> GearTrain:
        free = self._train_values()
        return self._model("train:symbolic", lambda: replace(self.scene.train, **free),
                           f"symbolic in {sorted(free)}")

    def train_at(self, values: Mapping[str, float]) -> GearTrain:
        """The scene's train with the train-level variables at ``values`` (``"train.variable"`` keys)."""
        free = self._train_values(values)
        return replace(self.scene.train, **free) if free else self.scene.train

    def _macro_free(self, mesh: str) -> bool:
        """Whether the mesh's macro geometry depends on design variables."""
        train_mesh = self.scene.train is not None and mesh in self.scene.train.pairs and \
            bool(self._free(TRAIN_TARGET, "train"))
        return train_mesh or bool(self._free(mesh, "macro"))

    def _pair(self, mesh: str) -> GearPair:
        macro = self._free(mesh, "macro")
        train_mesh = self.scene.train is not None and mesh in self.scene.train.pairs and \
            bool(self._free(TRAIN_TARGET, "train")) and mesh not in (self.scene.pairs or {})

        def build():
            pair = self._symbolic_train().pairs[mesh] if train_mesh else self._meshes[mesh]
            return _with_mesh_macro(pair, macro)

        if macro or train_mesh:
            detail = f"symbolic in {sorted(macro) or sorted(self._free(TRAIN_TARGET, 'train'))}"
        else:
            detail = "numeric"
        return self._model(f"geometry:{mesh}", build, detail)

    def _numeric_pair(self, mesh: str, values: Mapping[str, float]) -> GearPair:
        """The mesh's pair at the design ``values`` (numbers)."""
        pair = self._meshes[mesh]
        if self._free(TRAIN_TARGET, "train") and mesh in self.scene.train.pairs \
                and mesh not in (self.scene.pairs or {}):
            pair = self.train_at(values).pairs[mesh]
        macro = {n: values[f"{mesh}.{n}"] for n in self._free(mesh, "macro")}
        return _with_mesh_macro(pair, macro)

    def _geometry(self, mesh: str) -> dict:
        return self._pair(mesh).geometry()

    def _contact_ratio_bounds(self, mesh: str) -> tuple[float, float]:
        """Largest transverse and overlap ratios of ``mesh`` over the corners of the macro bounds (+0.2 each): they
        fix the tooth pairs of the macro-symbolic LTCA."""
        bounds = {f"{t}.{n}": (entry.lower[0], entry.upper[0]) for (t, n), entry in
                  ((k, self.problem._variables[f"{k[0]}.{k[1]}"]) for k in self._variables)
                  if t in (TRAIN_TARGET, mesh) and variable_kind(n).group in ("train", "macro")}
        eps_a, eps_b = [], []
        for corner in corner_values(bounds):
            values = {**self._initial_values(), **corner}
            try:
                g = self._numeric_pair(mesh, values).geometry()
            except GearoptInputError:
                continue
            eps_a.append(float(g["transverse_contact_ratio"]))
            eps_b.append(float(g["overlap_contact_ratio"]))
        if not eps_a:
            raise GearoptInputError(f"mesh {mesh!r}: no corner of the macro bounds {bounds} gives a valid geometry")
        return max(eps_a) + 0.2, max(eps_b) + (0.2 if max(eps_b) > 0 else 0.0)

    def _initial_values(self) -> dict[str, float]:
        return {f"{t}.{n}": float(self.problem._variables[f"{t}.{n}"].init[0]) for (t, n) in self._variables}

    # -- walk-off ------------------------------------------------------------------------------------------------

    def joint_axial_force_N(self, joint: str, lc: LoadCase):
        """Axial force on ``joint``'s gear at ``lc`` [N]: the load case's own demand if it gives one, else from the
        load case's mesh torques and the train's (possibly symbolic) helix angle."""
        if joint in lc.joint_axial_force_N:
            return float(lc.joint_axial_force_N[joint])
        return self._walk_off(lc).axial_force_N[self._joint_gear(joint)]

    def joint_torque_Nm(self, joint: str, lc: LoadCase):
        """Torque through ``joint`` at ``lc`` [N m]: the load case's own demand, else the net mesh torque on its
        gear."""
        if joint in lc.joint_torque_Nm:
            return float(lc.joint_torque_Nm[joint])
        return nm.to_float(self._walk_off(lc).joint_torque_Nm[self._joint_gear(joint)])

    def _joint_gear(self, joint: str) -> str:
        gear = self._data_values()["joints"][joint].get("gear")
        if self.scene.train is None or gear not in self.scene.train.gears:
            raise GearoptInputError(f"joint {joint!r}: its demand is not in the load case and its gear {gear!r} is "
                                    f"not a gear of the scene's train (give joint_torque_Nm/joint_axial_force_N)")
        return gear

    def _walk_off(self, lc: LoadCase):
        from ..joints.walk_off import walk_off

        train = self._symbolic_train() if self._free(TRAIN_TARGET, "train") else self.scene.train
        if train is None:
            raise GearoptInputError("walk-off demands need the scene's train")

        def build():
            torques = {}
            for mesh, spec in train.meshes.items():
                t = lc.torque_Nm.get(mesh) if isinstance(lc.torque_Nm, Mapping) else lc.torque_Nm
                if t is None:
                    continue
                pair = train.pairs[mesh]
                torques[mesh] = t if self._driving_gear(mesh) == 1 else -t * pair.teeth[0] / pair.teeth[1]
            return walk_off(train, torques, root_rotation=self._opts["root_rotation"])

        return self._model(f"walk_off@{lc.name}", build, "axial forces and joint torques from the mesh torques")


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


__all__ = ["TrainModels", "TRAIN_TARGET"]
