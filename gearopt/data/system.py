"""The typed system model: a data file parsed and validated once into frozen records.

:func:`load_system` reads a TOML data file (``docs/data-schema.md``), validates it (file, key path and unit in every
message) and returns a :class:`System`: the basic rack, the gears, the meshes (each with its own name, its design
torque and its load range), the gear-train variants (``[trains.spur]``, ``[trains.helical]``), materials,
lubrication, the shaft-hub joint of each gear, the design loads and limits, and the excitation (an engine, or a
generic driving torque: mean plus harmonics). Library functions take these records, never the raw file; a study
that needs a section the file does not have raises :class:`~gearopt.errors.MissingSectionError` naming the file,
the section and what needs it (:meth:`System.require`).

Any topology is expressible: meshes are named ``<driving>-<driven>`` by the user's own gear names, and each states
its design load by that name (``[meshes.<name>] design_torque_Nm``).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any, Mapping

from ..errors import DataFileError, GearoptInputError, MissingSectionError
from ..geometry.train import GearSpec, GearTrain, MeshSpec, RackSpec
from .requirements import Requirements, requirements_from_data
from .schema_keys import SECTION_USES




class ReadOnlyMap(dict):
    """A dict that refuses changes (the records' tables): read like a dict, pickled like one (a :class:`System`
    crosses process boundaries with the scenes and models that hold it)."""

    def _refuse(self, *args, **kwargs):
        raise TypeError("a System's tables are read-only: load the changed file again (gearopt.load_system)")

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = __ior__ = _refuse

    def __reduce__(self):
        return ReadOnlyMap, (dict(self),)


def _frozen(mapping: Mapping[str, Any]) -> Mapping[str, Any]:
    """A read-only deep copy of a nested mapping (lists become tuples)."""
    def conv(v):
        if isinstance(v, Mapping):
            return _frozen(v)
        if isinstance(v, list):
            return tuple(conv(e) for e in v)
        return v
    return ReadOnlyMap({k: conv(v) for k, v in mapping.items()})


def _plain(values: Mapping[str, Any]) -> dict[str, Any]:
    """The entries of a table without their ``*_source`` provenance strings (one level)."""
    return {k: v for k, v in values.items() if not k.endswith("_source")}


@dataclass(frozen=True)
class Gear:
    """One gear of the system (``[gears.<name>]``).

    ``teeth`` z; ``face_width_mm`` b; ``material`` a key of ``[materials]`` or of the packaged catalogue;
    ``tooth_thickness_allowance_um`` (upper, lower) E_sns/E_sni; ``tip_diameter_allowance_mm`` (lower, upper);
    ``accuracy_grade_iso1328``; ``blank`` ``"solid"``/``"webbed"``/``"recessed"`` (or None); ``inertia_kgm2`` the
    gear's own polar inertia when stated; ``speed_ratio_to_crank`` its speed over the reference shaft's (timing
    trains); ``entries`` every key of the table (provenance stripped), for models that read further keys (blank
    dimensions)."""

    name: str
    teeth: int
    face_width_mm: float
    material: str | None = None
    role: str = ""
    tooth_thickness_allowance_um: tuple[float, float] = (0.0, 0.0)
    tip_diameter_allowance_mm: tuple[float, float] = (0.0, 0.0)
    accuracy_grade_iso1328: int | None = None
    blank: str | None = None
    inertia_kgm2: float | None = None
    speed_ratio_to_crank: float | None = None
    entries: Mapping[str, Any] = field(default_factory=dict, repr=False, compare=False)

    def spec(self) -> GearSpec:
        """The geometry layer's :class:`~gearopt.geometry.GearSpec` of this gear."""
        return GearSpec(name=self.name, teeth=self.teeth, face_width_mm=self.face_width_mm,
                        tooth_thickness_upper_allowance_um=self.tooth_thickness_allowance_um[0],
                        tooth_thickness_lower_allowance_um=self.tooth_thickness_allowance_um[1],
                        tip_diameter_allowance_mm=self.tip_diameter_allowance_mm, material=self.material,
                        role=self.role)


@dataclass(frozen=True)
class Mesh:
    """One mesh (``[meshes.<name>]``), named ``<driving>-<driven>`` by its gears.

    ``centre_distance_mm`` a; ``centre_distance_allowance_mm`` (lower, upper); ``backlash_mm`` (min, max) when
    stated; ``design_torque_Nm`` the design torque on the driving gear (None: the file states none);
    ``torque_range_Nm`` the load cases of the mesh's design range [N m], design torque first: the file's
    ``torque_range_Nm`` or, by default, the design torque times ``[design_loads] torque_range_fractions``."""

    name: str
    driving_gear: str
    driven_gear: str
    centre_distance_mm: float
    centre_distance_allowance_mm: tuple[float, float] = (0.0, 0.0)
    backlash_mm: tuple[float, float] | None = None
    design_torque_Nm: float | None = None
    torque_range_Nm: tuple[float, ...] = ()

    @property
    def gears(self) -> tuple[str, str]:
        return self.driving_gear, self.driven_gear

    def spec(self) -> MeshSpec:
        return MeshSpec(gears=self.gears, centre_distance_mm=self.centre_distance_mm,
                        centre_distance_allowance_mm=self.centre_distance_allowance_mm)


@dataclass(frozen=True)
class TrainVariant:
    """A train of the system's gears and meshes (``[trains.<kind>]``, kind ``"spur"`` or ``"helical"``): its
    helix angle and the root mesh whose profile shifts are set first (``root_profile_shift`` of ``root_gear``, or
    the ISO/TR 4467 ``root_shift_split``)."""

    kind: str
    helix_angle_deg: float
    root_mesh: str
    root_gear: str
    root_profile_shift: float | None = None
    root_shift_split: float = 0.5
    root_hand: str = "right"
    entries: Mapping[str, Any] = field(default_factory=dict, repr=False, compare=False)


@dataclass(frozen=True)
class DesignLoads:
    """``[design_loads]``: the ISO 6336-1 application factor K_A, the default torque-range fractions of the
    design torques, the speed [rpm] of the train's root gear at which the design loads act (rated speed) and the
    highest speed the joints must hold (``overspeed_rpm``)."""

    application_factor_K_A: float = 1.0
    torque_range_fractions: tuple[float, ...] = (1.0,)
    speed_rpm: float | None = None
    overspeed_rpm: float | None = None


@dataclass(frozen=True)
class DesignLimits:
    """``[design_limits]``: the limits the design NLPs carry (None: not stated)."""

    max_root_stress_MPa: float | None = None
    max_contact_temperature_C: float | None = None
    min_loaded_contact_ratio: float | None = None


@dataclass(frozen=True)
class Lubrication:
    """``[lubrication]``: the mean tooth friction coefficient (Blok) and the oil (bulk) temperature [degC]."""

    mean_friction_coefficient: float
    oil_temperature_C: float


@dataclass(frozen=True)
class Joint:
    """The shaft-hub joint of one gear (``[joints.<name>]``): ``joint_type`` ``"press_fit"`` or ``"taper_nut"``;
    ``entries`` its dimensions, fit and friction (units in the key names; provenance stripped)."""

    name: str
    gear: str
    joint_type: str
    entries: Mapping[str, Any] = field(default_factory=dict, repr=False, compare=False)

    def __getitem__(self, key: str) -> Any:
        return self.entries[key]

    @property
    def free(self) -> bool:
        """Whether the joint's interference (press fit) or nut torque (taper) is a design variable (``free = true``):
        a recommendation sizes it for the requirements."""
        return bool(self.entries.get("free", False))


@dataclass(frozen=True)
class DrivingTorque:
    """A generic excitation (``[excitation]``): the torque on ``gear`` is ``mean_torque_Nm`` plus harmonics
    ``sum_k A_k cos(n_k theta + phi_k)`` of the gear's rotation angle theta (orders ``harmonic_orders`` per
    revolution, amplitudes ``harmonic_amplitudes_Nm``, phases ``harmonic_phases_deg``); the train runs at
    ``speed_rpm`` of that gear by default."""

    gear: str
    mean_torque_Nm: float
    harmonic_orders: tuple[float, ...] = ()
    harmonic_amplitudes_Nm: tuple[float, ...] = ()
    harmonic_phases_deg: tuple[float, ...] = ()
    speed_rpm: float | None = None


@dataclass(frozen=True)
class System:
    """A gear system parsed and validated once (see the module docstring).

    ``source`` names the file in messages; ``sections`` the sections the file has; ``gears``/``meshes``/
    ``trains``/``joints``/``materials`` by name; ``excitation`` a :class:`DrivingTorque`, ``"engine"`` (the file's
    ``[engine]`` section drives the train) or None; ``requirements`` the :class:`~gearopt.data.requirements.Requirements`
    every verdict judges (``[requirements]`` completed by ``[design_limits]`` and the defaults). :meth:`train` builds a :class:`~gearopt.geometry.GearTrain`,
    :meth:`require` names a missing section, :meth:`section` returns any section's validated entries and
    :attr:`data` the validated file (provenance included) for the models that read a whole section tree.
    """

    source: str
    title: str
    rack: RackSpec
    gears: Mapping[str, Gear]
    meshes: Mapping[str, Mesh]
    trains: Mapping[str, TrainVariant]
    design_loads: DesignLoads | None
    design_limits: DesignLimits | None
    lubrication: Lubrication | None
    joints: Mapping[str, Joint]
    materials: Mapping[str, Mapping[str, Any]]
    excitation: DrivingTorque | str | None
    sections: frozenset[str]
    requirements: Requirements = field(default_factory=Requirements)
    _data: Mapping[str, Any] = field(repr=False, compare=False, default_factory=dict)

    # -- sections ------------------------------------------------------------------------------------------------

    def has(self, section: str) -> bool:
        """Whether the file has the top-level section ``section``."""
        return section in self.sections

    def require(self, section: str, needed_by: str) -> None:
        """Raise :class:`~gearopt.errors.MissingSectionError` naming the file and ``[section]`` when the file lacks
        it (``needed_by``: the command or study that needs it)."""
        if section not in self.sections:
            use = SECTION_USES.get(section)
            raise MissingSectionError(
                f"{self.source}: [{section}] is missing: {needed_by} needs it"
                + (f" ({section} holds {use})" if use else "") + "; add the section (docs/data-schema.md)")

    def section(self, name: str, needed_by: str = "this study") -> Mapping[str, Any]:
        """The validated entries of a top-level section, provenance stripped (read-only)."""
        self.require(name, needed_by)
        return _frozen(_strip(self._data[name]))

    @property
    def data(self) -> dict[str, Any]:
        """A deep copy of the validated file (provenance strings included), for the models that read a whole
        section tree (the engine); prefer the typed records."""
        return copy.deepcopy(self._data)

    # -- look-ups ------------------------------------------------------------------------------------------------

    def mesh(self, name: str) -> Mesh:
        """The mesh ``name``; an unknown name raises naming the file and the meshes it has."""
        if name not in self.meshes:
            raise DataFileError(f"{self.source}: mesh {name!r} is not a mesh of the data (meshes: "
                                f"{', '.join(self.meshes)})")
        return self.meshes[name]

    def gear(self, name: str) -> Gear:
        if name not in self.gears:
            raise DataFileError(f"{self.source}: gear {name!r} is not a gear of the data (gears: "
                                f"{', '.join(self.gears)})")
        return self.gears[name]

    def joint_of(self, gear: str) -> Joint | None:
        """The joint holding ``gear`` (None: the gear has no ``[joints.*]`` entry)."""
        for j in self.joints.values():
            if j.gear == gear:
                return j
        return None

    def default_mesh(self, kind: str = "spur") -> str:
        """The mesh a study of one mesh takes when none is named: the ``kind`` train's only mesh, else its root
        mesh (``[trains.<kind>] root_mesh``)."""
        if kind not in self.trains:
            self.train(kind)                      # raises naming the missing [trains.<kind>]
        return next(iter(self.meshes)) if len(self.meshes) == 1 else self.trains[kind].root_mesh

    def with_joint_entries(self, changes: Mapping[str, Mapping[str, Any]], note: str = "sized joints") -> "System":
        """A copy of the system with entries of ``[joints.<name>]`` replaced (``{joint: {key: value}}``), validated
        again (a design's sized joints: the capacity models read the joints from the system)."""
        data = self.data
        for joint, entries in changes.items():
            if joint not in data.get("joints", {}):
                raise GearoptInputError(f"{self.source}: with_joint_entries names joint {joint!r}, not in [joints] "
                                        f"({sorted(data.get('joints', {}))})")
            data["joints"][joint].update(dict(entries))
        new = system_from_data(data, source=f"{self.source} ({note})" if changes else self.source)
        return replace(new, requirements=self.requirements)       # a caller's requirements stay the system's

    def design_torque_Nm(self, mesh: str) -> float:
        """The design torque of ``mesh`` on its driving gear [N m]; a mesh without one raises naming the key to
        add."""
        m = self.mesh(mesh)
        if m.design_torque_Nm is None:
            raise MissingSectionError(f"{self.source}: meshes.{mesh}.design_torque_Nm is missing: the design torque "
                                      f"of mesh {mesh!r} on its driving gear {m.driving_gear!r} [N m]; add it to "
                                      f"[meshes.{mesh}]")
        return m.design_torque_Nm

    def design_torques_Nm(self) -> dict[str, float]:
        """{mesh: design torque on its driving gear [N m]} of every mesh that states one."""
        return {n: m.design_torque_Nm for n, m in self.meshes.items() if m.design_torque_Nm is not None}

    def torque_range_Nm(self, mesh: str) -> tuple[float, ...]:
        """The load cases of ``mesh``'s design range [N m], design torque first (:attr:`Mesh.torque_range_Nm`)."""
        self.design_torque_Nm(mesh)
        return self.meshes[mesh].torque_range_Nm

    def speeds_rpm(self, needed_by: str) -> tuple[float, float]:
        """(rated, overspeed) speed of the train's root gear [rpm]: the engine's rated and overspeed-test speeds,
        else ``[design_loads] speed_rpm`` and ``overspeed_rpm``; a missing one raises naming the key to add."""
        if "engine" in self.sections:
            e = self.section("engine", needed_by)
            return float(e["rated_speed_rpm"]), float(e["overspeed_test_speed_rpm"])
        dl = self.design_loads
        for key in ("speed_rpm", "overspeed_rpm"):
            if dl is None or getattr(dl, key) is None:
                raise MissingSectionError(f"{self.source}: design_loads.{key} is missing: {needed_by} needs the "
                                          f"rated and overspeed speeds of the root gear [rpm]; add it to "
                                          f"[design_loads]")
        return dl.speed_rpm, dl.overspeed_rpm

    def train(self, kind: str = "spur") -> GearTrain:
        """The :class:`~gearopt.geometry.GearTrain` of ``[trains.<kind>]``."""
        if kind not in self.trains:
            raise MissingSectionError(f"{self.source}: [trains.{kind}] is missing (the data has trains "
                                      f"{', '.join(self.trains) or 'none'}); add it to build the {kind} train")
        t = self.trains[kind]
        try:
            return self._train(t, kind)
        except DataFileError:
            raise
        except GearoptInputError as err:
            raise DataFileError(f"{self.source}: trains.{kind}: {err}") from None

    def _train(self, t: TrainVariant, kind: str) -> GearTrain:
        return GearTrain(gears={n: g.spec() for n, g in self.gears.items()},
                         meshes={n: m.spec() for n, m in self.meshes.items()}, rack=self.rack,
                         helix_angle_deg=t.helix_angle_deg, root_mesh=t.root_mesh, root_gear=t.root_gear,
                         root_profile_shift=t.root_profile_shift, root_shift_split=t.root_shift_split,
                         root_hand=t.root_hand, name=f"{self.title or Path(self.source).stem}: {kind} train")


def _strip(table):
    if isinstance(table, Mapping):
        return {k: _strip(v) for k, v in table.items() if not k.endswith("_source")}
    return table


def _pair(table: Mapping[str, Any], first: str, second: str) -> tuple[float, float]:
    return float(table.get(first, 0.0)), float(table.get(second, 0.0))


def system_from_data(data: Mapping[str, Any], *, source: str = "<data>") -> System:
    """The :class:`System` of parsed data (validated first; ``source`` names it in messages)."""
    from .schema import validate_data

    validate_data(data, source=source)
    d = _strip(data)
    rack = RackSpec(**{k: float(d["rack"][k]) for k in ("module_mm", "pressure_angle_deg", "addendum_coefficient",
                                                         "dedendum_coefficient", "root_radius_coefficient")})
    gears = {}
    for name, g in d["gears"].items():
        gears[name] = Gear(
            name=name, teeth=int(g["teeth"]), face_width_mm=float(g["face_width_mm"]), material=g.get("material"),
            role=g.get("role", ""),
            tooth_thickness_allowance_um=_pair(g, "tooth_thickness_upper_allowance_um",
                                               "tooth_thickness_lower_allowance_um"),
            tip_diameter_allowance_mm=_pair(g, "tip_diameter_lower_allowance_mm", "tip_diameter_upper_allowance_mm"),
            accuracy_grade_iso1328=g.get("accuracy_grade_iso1328"), blank=g.get("blank"),
            inertia_kgm2=g.get("inertia_kgm2"), speed_ratio_to_crank=g.get("speed_ratio_to_crank"),
            entries=_frozen(g))
    loads = None
    if "design_loads" in d:
        dl = d["design_loads"]
        loads = DesignLoads(application_factor_K_A=float(dl.get("application_factor_K_A", 1.0)),
                            torque_range_fractions=tuple(float(f) for f in dl.get("torque_range_fractions", (1.0,))),
                            speed_rpm=float(dl["speed_rpm"]) if "speed_rpm" in dl else None,
                            overspeed_rpm=float(dl["overspeed_rpm"]) if "overspeed_rpm" in dl else None)
    fractions = loads.torque_range_fractions if loads is not None else (1.0,)
    meshes = {}
    for name, m in d["meshes"].items():
        t0 = float(m["design_torque_Nm"]) if "design_torque_Nm" in m else None
        if "torque_range_Nm" in m:
            rng = tuple(float(t) for t in m["torque_range_Nm"])
        elif t0 is not None:
            rng = (t0,) + tuple(t0 * float(f) for f in fractions if f != 1.0)
        else:
            rng = ()
        backlash = (float(m["backlash_min_mm"]), float(m["backlash_max_mm"])) \
            if "backlash_min_mm" in m and "backlash_max_mm" in m else None
        meshes[name] = Mesh(name=name, driving_gear=m["gears"][0], driven_gear=m["gears"][1],
                            centre_distance_mm=float(m["centre_distance_mm"]),
                            centre_distance_allowance_mm=_pair(m, "centre_distance_lower_allowance_mm",
                                                               "centre_distance_upper_allowance_mm"),
                            backlash_mm=backlash, design_torque_Nm=t0, torque_range_Nm=rng)
    trains = {kind: TrainVariant(kind=kind, helix_angle_deg=float(t["helix_angle_deg"]), root_mesh=t["root_mesh"],
                                 root_gear=t["root_gear"], root_profile_shift=t.get("root_profile_shift"),
                                 root_shift_split=float(t.get("root_shift_split", 0.5)),
                                 root_hand=t.get("root_hand", "right"), entries=_frozen(t))
              for kind, t in d["trains"].items()}
    limits = None
    if "design_limits" in d:
        lim = d["design_limits"]
        limits = DesignLimits(**{k: (float(lim[k]) if k in lim else None)
                                 for k in ("max_root_stress_MPa", "max_contact_temperature_C",
                                           "min_loaded_contact_ratio")})
    lub = None
    if "lubrication" in d:
        lub = Lubrication(mean_friction_coefficient=float(d["lubrication"]["mean_friction_coefficient"]),
                          oil_temperature_C=float(d["lubrication"]["oil_temperature_C"]))
    joints = {name: Joint(name=name, gear=j["gear"], joint_type=j["joint_type"], entries=_frozen(j))
              for name, j in d.get("joints", {}).items()}
    excitation: DrivingTorque | str | None = None
    if "excitation" in d:
        e = d["excitation"]
        excitation = DrivingTorque(gear=e["gear"], mean_torque_Nm=float(e["mean_torque_Nm"]),
                                   harmonic_orders=tuple(float(v) for v in e.get("harmonic_orders", ())),
                                   harmonic_amplitudes_Nm=tuple(float(v) for v in e.get("harmonic_amplitudes_Nm", ())),
                                   harmonic_phases_deg=tuple(float(v) for v in e.get("harmonic_phases_deg", ())),
                                   speed_rpm=float(e["speed_rpm"]) if "speed_rpm" in e else None)
    elif "engine" in d:
        excitation = "engine"
    return System(source=source, title=str(d.get("title", "")), rack=rack, gears=ReadOnlyMap(gears),
                  meshes=ReadOnlyMap(meshes), trains=ReadOnlyMap(trains), design_loads=loads,
                  design_limits=limits, lubrication=lub, joints=ReadOnlyMap(joints),
                  materials=_frozen(d.get("materials", {})), excitation=excitation,
                  sections=frozenset(k for k in data if not k.endswith("_source")),
                  requirements=requirements_from_data(d.get("requirements"), d.get("design_limits"), source=source),
                  _data=copy.deepcopy(dict(data)))


_SYSTEMS: dict[tuple, System] = {}


def load_system(path: str | Path | None = None) -> System:
    """The :class:`System` of a data file (default: the packaged timing train, ``gearopt/data/default_train.toml``).

    Every problem of the file (missing, damaged, unknown or missing keys, wrong types, values out of range, broken
    cross-references) is one :class:`~gearopt.errors.DataFileError` naming the file and each key path. A file
    already loaded in this process and unchanged since is not parsed again (the record is immutable)."""
    from . import default_data_path, load_default_data

    p = Path(path) if path is not None else default_data_path()
    try:
        st = p.stat()
        key = (str(p.resolve()), st.st_mtime_ns, st.st_size)
    except OSError:
        key = None
    if key is not None and key in _SYSTEMS:
        return _SYSTEMS[key]
    system = system_from_data(load_default_data(p), source=str(path) if path is not None else str(p))
    if key is not None:
        _SYSTEMS[key] = system
    return system
