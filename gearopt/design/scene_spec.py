"""The declarative parts of a scene: load cases, design variables, objectives and limits (plain frozen dataclasses).

A scene names its *targets*: a mesh of the train (``"pinion-wheel"``), a shaft-hub joint of the data (``"cam"``) or a
gear whose blank is designed (``"cam"``). Quantities and variables are looked up in
:mod:`gearopt.design.scene_terms`, which says what each needs (geometry, ISO 6336, the smooth LTCA, a joint model,
a blank model, the dynamics) so that :class:`~gearopt.design.scene.Scene` builds only that.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

from ..errors import GearoptInputError
from ..validation import check_range

AGGREGATES = ("max", "mean")
TARGET_KINDS = ("mesh", "joint", "blank")


@dataclass(frozen=True)
class LoadCase:
    """One operating point of a scene.

    Args:
        name: label used in constraint names (``"max_contact_stress_MPa[pinion-wheel]@design"``).
        torque_Nm: torque on the driving gear of each mesh [N m]: one number for every mesh, or a mapping mesh ->
            torque. Mesh quantities need it (> 0).
        speed_rpm: crank (root gear) speed [rpm]; the driving gear of a mesh turns at its speed ratio times this.
            Needed by contact-temperature quantities and by joint capacities (centrifugal loss).
        joint_torque_Nm, joint_axial_force_N: demand on each shaft-hub joint [N m], [N] (mapping joint -> value);
            joint margins need them.
        dynamics: ``None`` for a given load case, or a dict ``{"kind": "spur"|"helical", "backlash": bool,
            "statistic": "peak"|"rms", "cycles": int}`` -- then the mesh torques and joint demands come from a
            simulation of the scene's ``dynamics_model`` at ``speed_rpm`` (built only for such a scene). Make it with
            :meth:`from_dynamics`.
        iso6336_options: keywords of the ISO 6336 rating at this load case that override the scene's
            ``iso6336_options`` (e.g. ``{"application_factor": 1.0, "K_v": 1.0}`` at a dynamic peak torque, whose
            simulation already holds the external and internal dynamic loads: ISO 6336-1 method A).
    """

    name: str
    torque_Nm: float | Mapping[str, float] | None = None
    speed_rpm: float | None = None
    joint_torque_Nm: Mapping[str, float] = field(default_factory=dict)
    joint_axial_force_N: Mapping[str, float] = field(default_factory=dict)
    dynamics: Mapping[str, Any] | None = None
    iso6336_options: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name:
            raise GearoptInputError(f"LoadCase name={self.name!r} must be a non-empty string")
        if self.speed_rpm is not None:
            check_range(f"LoadCase {self.name!r} speed_rpm", self.speed_rpm, 0.0, None, unit="rpm")
        if self.dynamics is not None and self.speed_rpm is None:
            raise GearoptInputError(f"LoadCase {self.name!r}: a dynamic load case needs speed_rpm")

    @classmethod
    def from_dynamics(cls, name: str, speed_rpm: float, *, kind: str = "spur", backlash: bool = False,
                      statistic: str = "peak", cycles: int = 1,
                      iso6336_options: Mapping[str, Any] | None = None) -> "LoadCase":
        """A load case whose mesh torques (|mesh force| x base radius of gear 1, ``statistic`` over the simulated
        cycles) and joint demands (peak joint torque and axial force, :func:`gearopt.dynamics.walk_off_history`)
        come from the scene's torsional model (``Scene.dynamics_model``) of ``kind`` at ``speed_rpm``."""
        if kind not in ("spur", "helical"):
            raise GearoptInputError(f"kind={kind!r} must be 'spur' or 'helical'")
        if statistic not in ("peak", "rms"):
            raise GearoptInputError(f"statistic={statistic!r} must be 'peak' or 'rms'")
        return cls(name=name, speed_rpm=speed_rpm, dynamics={"kind": kind, "backlash": bool(backlash),
                                                             "statistic": statistic, "cycles": int(cycles)},
                   iso6336_options=dict(iso6336_options or {}))

    def mesh_torque_Nm(self, mesh: str) -> float:
        t = self.torque_Nm
        if isinstance(t, Mapping):
            if mesh not in t:
                raise GearoptInputError(f"LoadCase {self.name!r} gives no torque_Nm for mesh {mesh!r} "
                                        f"(it has {sorted(t)})")
            t = t[mesh]
        if t is None:
            raise GearoptInputError(f"LoadCase {self.name!r} has no torque_Nm (mesh {mesh!r} needs one)")
        check_range(f"LoadCase {self.name!r} torque_Nm[{mesh}]", t, 0.0, None, low_inclusive=False, unit="N*m")
        return float(t)


@dataclass(frozen=True)
class DesignVariable:
    """A free design quantity of one target, with bounds in its own units (``name`` carries them).

    ``init``: starting value (default: the target's present value, or the middle of the bounds); ``scale``: expected
    magnitude (Ipopt sees value/scale; default from the variable's vocabulary entry). ``lower``/``upper`` default to
    the vocabulary's bounds where it states them (microgeometry), else they are required.
    """

    name: str
    target: str
    lower: float | None = None
    upper: float | None = None
    init: float | None = None
    scale: float | None = None


@dataclass(frozen=True)
class Objective:
    """One term of the objective: ``weight * quantity / scale``, minimised (``sense="min"``) or maximised.

    ``aggregate`` over the load cases of a per-load-case quantity: ``"max"`` (an epigraph variable: robust design
    over the range) or ``"mean"``; ``load_cases``: only these load cases (names; default all).
    """

    quantity: str
    target: str
    sense: str = "min"
    aggregate: str = "max"
    weight: float = 1.0
    scale: float | None = None
    load_cases: tuple[str, ...] | None = None

    def __post_init__(self):
        if self.sense not in ("min", "max"):
            raise GearoptInputError(f"Objective {self.quantity!r}: sense={self.sense!r} must be 'min' or 'max'")
        if self.aggregate not in AGGREGATES:
            raise GearoptInputError(f"Objective {self.quantity!r}: aggregate={self.aggregate!r} must be one of "
                                    f"{AGGREGATES}")
        check_range(f"Objective {self.quantity!r} weight", self.weight, 0.0, None, low_inclusive=False)


@dataclass(frozen=True)
class Limit:
    """A constraint ``lower <= quantity <= upper`` on one target, imposed at every load case of the scene (or only
    at ``load_cases`` when given). ``options``: keyword arguments of the quantity (e.g. the limits of
    ``geometry_limits``, which imposes every named margin of :meth:`GearPair.constraints`)."""

    quantity: str
    target: str
    lower: float | None = None
    upper: float | None = None
    load_cases: tuple[str, ...] | None = None
    options: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        if self.lower is None and self.upper is None and self.quantity != "geometry_limits":
            raise GearoptInputError(f"Limit {self.quantity!r} on {self.target!r} needs a lower or an upper bound")


__all__ = ["LoadCase", "DesignVariable", "Objective", "Limit"]
