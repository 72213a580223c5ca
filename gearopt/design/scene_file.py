"""Scenes declared in a data file: ``[scenes.<name>]`` tables in the TOML format of the train data, so a study can
be rerun without writing Python.

A scene table holds ``train`` (``"spur"`` or ``"helical"``: a train of the data's ``[trains.*]``), optional
``driving_gear``, ``ltca_options`` (flat keys of :class:`~gearopt.design.scene_options.LTCAOptions`) and
``iso6336_options`` tables, and arrays of tables ``load_cases``,
``variables``, ``objectives`` and ``limits`` whose keys are the arguments of :class:`LoadCase`,
:class:`DesignVariable`, :class:`Objective` and :class:`Limit` (units in the key names). A load case may give
``design_torque_fraction`` instead of ``torque_Nm``: that fraction of each mesh's ``design_torque_Nm`` (so one scene
file serves any train). A load case may give
``dynamics = {kind = "spur", backlash = true, statistic = "peak", cycles = 1}`` (:meth:`LoadCase.from_dynamics`).
Unknown keys are rejected with the nearest valid one. ``docs/scenes.md`` documents the format with an example.
"""

from __future__ import annotations

import difflib
from dataclasses import fields
from typing import Any, Mapping

from ..data import System, system_from_data, system_of, train_from_data
from ..errors import GearoptInputError
from ..validation import check_range
from .scene import Scene
from .scene_options import LTCAOptions
from .scene_spec import DesignVariable, Limit, LoadCase, Objective

_SCENE_KEYS = {"train", "driving_gear", "ltca_options", "iso6336_options", "load_cases", "variables", "objectives",
               "limits", "description"}


def _check_keys(where: str, table: Mapping[str, Any], valid: set[str]) -> None:
    for key in table:
        if key not in valid:
            near = difflib.get_close_matches(key, sorted(valid), n=1)
            hint = f"; did you mean {near[0]!r}?" if near else f"; valid keys: {sorted(valid)}"
            raise GearoptInputError(f"{where}: unknown key {key!r}{hint}")


def _make(cls, where: str, table: Mapping[str, Any]):
    if not isinstance(table, Mapping):
        raise GearoptInputError(f"{where} must be a table, got {type(table).__name__}")
    names = {f.name for f in fields(cls)}
    _check_keys(where, table, names)
    kw = dict(table)
    if cls is Limit and "load_cases" in kw:
        kw["load_cases"] = tuple(kw["load_cases"])
    try:
        return cls(**kw)
    except TypeError as exc:   # a required argument missing
        raise GearoptInputError(f"{where}: {exc}") from None


def scene_names(data: Mapping[str, Any]) -> list[str]:
    """Names of the scenes a data file declares (``[scenes.<name>]``)."""
    return list((data.get("scenes") or {}).keys())


def scene_from_data(data: Mapping[str, Any], name: str, *, train_data: System | None = None) -> Scene:
    """The :class:`Scene` declared as ``[scenes.<name>]`` in ``data`` (the parsed scene file); its train (and the
    joints and blanks the scene's targets name) come from ``train_data``, the :class:`~gearopt.data.System` of the
    train's data file (default: ``data`` itself, which must then hold the train: its tables besides ``[scenes]``
    are validated into a System, :func:`~gearopt.data.system_from_data`). The scene's ``data`` is that System."""
    scenes = data.get("scenes") or {}
    if name not in scenes:
        near = difflib.get_close_matches(name, list(scenes), n=1)
        raise GearoptInputError(f"scene {name!r} is not declared in the data ([scenes.*] holds {list(scenes)})"
                                + (f"; did you mean {near[0]!r}?" if near else ""))
    spec = scenes[name]
    where = f"[scenes.{name}]"
    _check_keys(where, spec, _SCENE_KEYS)
    kind = spec.get("train", "spur")
    if train_data is not None:
        system = system_of(train_data, "scene_from_data(train_data=...)")
    elif not data.get("trains"):
        raise GearoptInputError(f"{where} train={kind!r} is not a train of the data (it has no [trains.*]; give "
                                f"train_data=gearopt.load_system(path))")
    else:
        system = system_from_data({k: v for k, v in data.items() if k != "scenes"})
    if kind not in system.trains:
        raise GearoptInputError(f"{where} train={kind!r} is not a train of the data ([trains.*] holds "
                                f"{list(system.trains)})")
    load_cases = []
    for i, lc in enumerate(spec.get("load_cases", [])):
        if "dynamics" in lc:
            extra = set(lc) - {"name", "speed_rpm", "dynamics", "iso6336_options"}
            if extra:
                raise GearoptInputError(f"{where} load_cases[{i}]: a dynamic load case takes name, speed_rpm, "
                                        f"dynamics and iso6336_options only, not {sorted(extra)}")
            dyn = dict(lc["dynamics"])
            _check_keys(f"{where} load_cases[{i}].dynamics", dyn, {"kind", "backlash", "statistic", "cycles"})
            load_cases.append(LoadCase.from_dynamics(lc["name"], lc["speed_rpm"], **dyn,
                                                     iso6336_options=lc.get("iso6336_options")))
        elif "design_torque_fraction" in lc:
            if "torque_Nm" in lc:
                raise GearoptInputError(f"{where} load_cases[{i}]: give torque_Nm or design_torque_fraction, not both")
            f = lc["design_torque_fraction"]
            check_range(f"{where} load_cases[{i}].design_torque_fraction", f, 0.0, None, low_inclusive=False)
            design = system.design_torques_Nm()
            if not design:
                raise GearoptInputError(f"{where} load_cases[{i}]: design_torque_fraction needs the meshes' "
                                        "design_torque_Nm in the data ([meshes.<name>])")
            rest = {k: v for k, v in lc.items() if k != "design_torque_fraction"}
            load_cases.append(_make(LoadCase, f"{where} load_cases[{i}]",
                                    {**rest, "torque_Nm": {m: float(f) * t for m, t in design.items()}}))
        else:
            load_cases.append(_make(LoadCase, f"{where} load_cases[{i}]", lc))
    ltca_options = dict(spec.get("ltca_options", {}))
    try:                        # checked here to name the scene; the build takes the flat table
        LTCAOptions.from_mapping(ltca_options)
    except GearoptInputError as exc:
        raise GearoptInputError(f"{where} {exc}") from None
    return Scene(name=name, train=train_from_data(system.data, kind), load_cases=load_cases,
                 variables=[_make(DesignVariable, f"{where} variables[{i}]", v)
                            for i, v in enumerate(spec.get("variables", []))],
                 objectives=[_make(Objective, f"{where} objectives[{i}]", o)
                             for i, o in enumerate(spec.get("objectives", []))],
                 limits=[_make(Limit, f"{where} limits[{i}]", lim) for i, lim in enumerate(spec.get("limits", []))],
                 driving_gear=spec.get("driving_gear", 1), data=system,
                 ltca_options=ltca_options,
                 iso6336_options=dict(spec.get("iso6336_options", {})))


__all__ = ["scene_from_data", "scene_names"]
