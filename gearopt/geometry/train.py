"""Gear trains: named gears and meshes with fixed centre distances, arranged as a tree.

Profile shift propagates through the tree (thesis section 3.4.2, Tables 3.2-3.3): the root mesh's sum of shifts is
split by a given shift of its root gear (or ISO/TR 4467 lambda); every further mesh shares one gear whose shift is
already known, and its other gear takes the rest of that mesh's sum x1 + x2 fixed by its centre distance.
Speeds follow from the tooth counts (external meshes reverse the sense of rotation), helix hands alternate.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field
from typing import Any

import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError
from .pair import GearPair
from .tolerances import PairTolerances


@dataclass(frozen=True)
class GearSpec:
    """One gear of a train: name, teeth, face width [mm], allowances and material key."""

    name: str
    teeth: int
    face_width_mm: float
    tooth_thickness_upper_allowance_um: float = 0.0
    tooth_thickness_lower_allowance_um: float = 0.0
    tip_diameter_allowance_mm: tuple[float, float] = (0.0, 0.0)
    material: str | None = None
    role: str = ""


@dataclass(frozen=True)
class MeshSpec:
    """One mesh of a train: ``gears`` = (driving gear, driven gear) names; working centre distance [mm] fixed by the
    housing, and its allowances (lower, upper) [mm]."""

    gears: tuple[str, str]
    centre_distance_mm: Any
    centre_distance_allowance_mm: tuple[float, float] = (0.0, 0.0)

    @property
    def name(self) -> str:
        return f"{self.gears[0]}-{self.gears[1]}"


@dataclass(frozen=True)
class RackSpec:
    """Common basic rack and tool data of a train (normal module [mm], normal pressure angle [deg], coefficients)."""

    module_mm: Any = 3.0
    pressure_angle_deg: Any = 20.0
    addendum_coefficient: float = 1.0
    dedendum_coefficient: float = 1.25
    root_radius_coefficient: float = 0.38


@dataclass
class GearTrain:
    """A tree of external gear meshes with fixed centre distances.

    ``root_mesh``/``root_gear`` start the profile-shift propagation: the root gear's shift is ``root_profile_shift``
    if given, else it follows from splitting the root mesh's sum by ISO/TR 4467 with ``root_shift_split``.
    ``root_profile_shift`` may be a CasADi symbol, making every pair symbolic. Speed ratios are relative to the root
    gear (negative = opposite sense of rotation). ``helix_angle_deg`` is common to all gears (a gear meshing with
    several others has one helix); ``root_hand`` is the root gear's helix hand, neighbours alternate.
    """

    gears: dict[str, GearSpec]
    meshes: dict[str, MeshSpec]
    rack: RackSpec = field(default_factory=RackSpec)
    helix_angle_deg: Any = 0.0
    root_mesh: str | None = None
    root_gear: str | None = None
    root_profile_shift: Any = None
    root_shift_split: Any = 0.5
    root_hand: str = "right"
    name: str = ""
    pairs: dict[str, GearPair] = field(init=False)
    profile_shifts: dict[str, Any] = field(init=False)
    speed_ratios: dict[str, float] = field(init=False)
    helix_hands: dict[str, str | None] = field(init=False)
    tip_diameters_mm: dict[str, Any] = field(init=False)

    def __post_init__(self):
        self._check_tree()
        if self.root_mesh is None:
            self.root_mesh = next(iter(self.meshes))
        if self.root_mesh not in self.meshes:
            raise GearoptInputError(f"root_mesh={self.root_mesh!r} is not a mesh of the train {list(self.meshes)}")
        if self.root_gear is None:
            self.root_gear = self.meshes[self.root_mesh].gears[0]
        if self.root_gear not in self.meshes[self.root_mesh].gears:
            raise GearoptInputError(f"root_gear={self.root_gear!r} is not a gear of root_mesh {self.root_mesh!r}")
        if self.root_hand not in ("right", "left"):
            raise GearoptInputError(f"root_hand={self.root_hand!r} must be 'right' or 'left'")
        self._propagate()

    # ------------------------------------------------------------------------------------------------------------

    def _check_tree(self) -> None:
        if not self.gears or not self.meshes:
            raise GearoptInputError("a gear train needs at least two gears and one mesh")
        for name, mesh in self.meshes.items():
            for g in mesh.gears:
                if g not in self.gears:
                    raise GearoptInputError(f"mesh {name!r} names gear {g!r}, which is not in gears {list(self.gears)}")
            if mesh.gears[0] == mesh.gears[1]:
                raise GearoptInputError(f"mesh {name!r} meshes gear {mesh.gears[0]!r} with itself")
        if len(self.meshes) != len(self.gears) - 1:
            raise GearoptInputError(f"the train must be a tree: {len(self.gears)} gears need exactly "
                                    f"{len(self.gears) - 1} meshes, got {len(self.meshes)}")
        reached = self._bfs_order(next(iter(self.gears)))
        missing = set(self.gears) - {g for g, _ in reached}
        if missing:
            raise GearoptInputError(f"gears {sorted(missing)} are not connected to the rest of the train")

    def _neighbours(self, gear: str):
        for name, mesh in self.meshes.items():
            if gear in mesh.gears:
                yield name, mesh.gears[1] if mesh.gears[0] == gear else mesh.gears[0]

    def _bfs_order(self, start: str) -> list[tuple[str, str | None]]:
        """Gears in breadth-first order from ``start`` with the mesh through which each was reached."""
        order, seen, queue = [(start, None)], {start}, deque([start])
        while queue:
            g = queue.popleft()
            for mesh_name, other in self._neighbours(g):
                if other not in seen:
                    seen.add(other)
                    order.append((other, mesh_name))
                    queue.append(other)
        return order

    def _pair(self, mesh: MeshSpec, profile_shift1) -> GearPair:
        g1, g2 = (self.gears[n] for n in mesh.gears)
        tol = PairTolerances(
            centre_distance_allowance_mm=tuple(mesh.centre_distance_allowance_mm),
            tooth_thickness_upper_allowance_um=(g1.tooth_thickness_upper_allowance_um,
                                                g2.tooth_thickness_upper_allowance_um),
            tooth_thickness_lower_allowance_um=(g1.tooth_thickness_lower_allowance_um,
                                                g2.tooth_thickness_lower_allowance_um),
            tip_diameter_allowance_mm=(tuple(g1.tip_diameter_allowance_mm), tuple(g2.tip_diameter_allowance_mm)))
        hands = None
        if nm.is_symbolic(self.helix_angle_deg) or nm.to_float(self.helix_angle_deg) != 0.0:
            hands = (self.helix_hands[g1.name], self.helix_hands[g2.name])
        kwargs = dict(teeth=(g1.teeth, g2.teeth), centre_distance_mm=mesh.centre_distance_mm,
                      module_mm=self.rack.module_mm, pressure_angle_deg=self.rack.pressure_angle_deg,
                      helix_angle_deg=self.helix_angle_deg, face_width_mm=(g1.face_width_mm, g2.face_width_mm),
                      addendum_coefficient=self.rack.addendum_coefficient,
                      dedendum_coefficient=self.rack.dedendum_coefficient,
                      root_radius_coefficient=self.rack.root_radius_coefficient,
                      tolerances=tol, names=(g1.name, g2.name), helix_hands=hands)
        shift = dict(shift_split=self.root_shift_split) if profile_shift1 is None else dict(profile_shift1=profile_shift1)
        try:
            return GearPair.from_centre_distance(**shift, **kwargs)
        except GearoptInputError as err:  # name the mesh: the pair's own message knows only its numbers
            raise GearoptInputError(f"mesh {mesh.name!r} ({g1.name} z{g1.teeth}, {g2.name} z{g2.teeth}): {err}") \
                from None

    def _propagate(self) -> None:
        order = self._bfs_order(self.root_gear)
        self.speed_ratios, self.helix_hands = {self.root_gear: 1.0}, {self.root_gear: self.root_hand}
        flip = {"right": "left", "left": "right"}
        for gear, mesh_name in order[1:]:
            other = next(g for g in self.meshes[mesh_name].gears if g != gear)
            self.speed_ratios[gear] = -self.speed_ratios[other] * self.gears[other].teeth / self.gears[gear].teeth
            self.helix_hands[gear] = flip[self.helix_hands[other]]
        self.pairs, self.profile_shifts = {}, {}
        root = self.meshes[self.root_mesh]
        if self.root_profile_shift is None:
            pair = self._pair(root, None)
            self.profile_shifts.update(zip(root.gears, pair.profile_shifts))
        else:
            self.profile_shifts[self.root_gear] = self.root_profile_shift
        for gear, mesh_name in order[1:]:
            mesh = self.meshes[mesh_name]
            known = next(g for g in mesh.gears if g != gear)
            if mesh.gears[0] == known:
                pair = self._pair(mesh, self.profile_shifts[known])
            else:  # the known gear is gear 2: gear 1 takes the rest of the sum
                sum_x = self._pair(mesh, None).geometry()["sum_profile_shift"]
                pair = self._pair(mesh, sum_x - self.profile_shifts[known])
            self.profile_shifts[gear] = pair.profile_shifts[mesh.gears.index(gear)]
            self.pairs[mesh_name] = pair
        self.pairs = {name: self.pairs[name] for name in self.meshes}  # keep the declared mesh order
        self._unify_tip_diameters()

    def _unify_tip_diameters(self) -> None:
        """A gear has one tip diameter: with tip shortening, each of its meshes asks for its own; take the smallest
        (keeps at least the basic-rack bottom clearance in every mesh) and rebuild the pairs with it."""
        tips: dict[str, Any] = {}
        for pair in self.pairs.values():
            for name, d_a in zip(pair.names, pair.geometry()["tip_diameter_mm"]):
                tips[name] = d_a if name not in tips else nm.fmin(tips[name], d_a)
        self.tip_diameters_mm = tips
        self.pairs = {name: pair.with_options(tip_diameters_mm=(tips[pair.names[0]], tips[pair.names[1]]))
                      for name, pair in self.pairs.items()}

    def gear_speed_rpm(self, gear: str, root_speed_rpm: float) -> float:
        """Speed of ``gear`` [rpm] (magnitude) when the root gear turns at ``root_speed_rpm``; a name that is not
        a gear of the train (a pair's default label) turns with the root."""
        return abs(float(self.speed_ratios.get(gear, 1.0))) * root_speed_rpm

    # ------------------------------------------------------------------------------------------------------------
    # tables
    # ------------------------------------------------------------------------------------------------------------

    def mesh_table(self) -> pd.DataFrame:
        """One row per mesh: centre distances, y, sum of shifts, shifts, working pressure angle, contact ratios,
        backlash range (numeric trains only)."""
        rows = []
        for name, pair in self.pairs.items():
            g = pair.geometry()
            rows.append({
                "mesh": name, "teeth_1": pair.teeth[0], "teeth_2": pair.teeth[1],
                "centre_distance_mm": g["centre_distance_mm"],
                "reference_centre_distance_mm": g["reference_centre_distance_mm"],
                "centre_distance_modification": g["centre_distance_modification"],
                "sum_profile_shift": g["sum_profile_shift"],
                "profile_shift_1": g["profile_shifts"][0], "profile_shift_2": g["profile_shifts"][1],
                "tip_shortening": g["tip_shortening"],
                "working_pressure_angle_deg": g["working_pressure_angle_deg"],
                "transverse_contact_ratio": g["transverse_contact_ratio"],
                "worst_case_transverse_contact_ratio": g["worst_case_transverse_contact_ratio"],
                "overlap_contact_ratio": g["overlap_contact_ratio"],
                "total_contact_ratio": g["total_contact_ratio"],
                "normal_backlash_min_mm": g["normal_backlash_min_mm"],
                "normal_backlash_max_mm": g["normal_backlash_max_mm"],
            })
        return pd.DataFrame(rows).set_index("mesh")

    def gear_table(self) -> pd.DataFrame:
        """One row per gear: teeth, shift, speed ratio to the root gear, helix hand, diameters, thicknesses."""
        rows = {}
        for pair in self.pairs.values():
            g = pair.geometry()
            for i, gear in enumerate(pair.names):
                row = {
                    "teeth": pair.teeth[i], "profile_shift": g["profile_shifts"][i],
                    "speed_ratio": self.speed_ratios[gear], "helix_hand": self.helix_hands[gear]
                    if pair.helix_hands else "",
                    "pitch_diameter_mm": g["pitch_diameter_mm"][i], "base_diameter_mm": g["base_diameter_mm"][i],
                    "tip_diameter_mm": g["tip_diameter_mm"][i], "root_diameter_mm": g["root_diameter_mm"][i],
                    "addendum_mm": g["addendum_mm"][i], "whole_depth_mm": g["whole_depth_mm"][i],
                    "tooth_thickness_mm": g["tooth_thickness_mm"][i], "tip_thickness_mm": g["tip_thickness_mm"][i],
                }
                rows.setdefault(gear, row)
        return pd.DataFrame.from_dict({g: rows[g] for g in self.gears}, orient="index").rename_axis("gear")
