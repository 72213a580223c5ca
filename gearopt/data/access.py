"""Data access for library functions: a :class:`~gearopt.data.system.System`, never the raw dict of a data file
and never the packaged file behind the caller's back.

Library functions take ``system``: the :class:`System` of a data file (``gearopt.load_system(path)``; a validated
dict converts with ``gearopt.data.system_from_data(d)``). :func:`system_of` checks the argument (no data, a raw dict
or another type raise :class:`~gearopt.errors.GearoptInputError` naming the function and the fix);
:func:`require_section` returns one top-level section and raises :class:`~gearopt.errors.MissingSectionError`
naming the file, the section and what needs it.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

from ..errors import DataFileError, GearoptInputError
from .system import Joint, System


def system_of(source: System, needed_by: str = "this function") -> System:
    """``source`` itself when it is a :class:`System`: the check of every library function that takes one.

    ``None`` (no data given), a dict (the raw data of a file) or any other type raise
    :class:`~gearopt.errors.GearoptInputError` naming ``needed_by``, the type received and the fix
    (``gearopt.load_system(path)``, or ``gearopt.data.system_from_data(d)`` for a validated dict): the library
    never falls back to the packaged data."""
    if isinstance(source, System):
        return source
    if source is None:
        raise GearoptInputError(
            f"{needed_by}: data is required (got None): pass the System of your data file "
            f"(gearopt.load_system(path)); the library does not read the packaged default data on its own")
    if isinstance(source, Mapping):
        raise GearoptInputError(
            f"{needed_by}: got a {type(source).__name__} (the raw data of a file); library functions take a System: "
            f"pass gearopt.load_system(path), or convert a validated dict with gearopt.data.system_from_data(d)")
    raise GearoptInputError(f"{needed_by}: got a {type(source).__name__}; it must be a System "
                            f"(gearopt.load_system(path), or gearopt.data.system_from_data(d) for a data dict)")


def joint_record(system: System, joint: str, needed_by: str = "this function") -> Joint:
    """The joint ``[joints.<joint>]`` of ``system``; a missing one raises
    :class:`~gearopt.errors.DataFileError` naming the file, the key path ``joints.<joint>`` and the joints the file
    has."""
    if joint not in system.joints:
        raise DataFileError(f"{system.source}: joints.{joint} is missing: {needed_by} needs the joint {joint!r} "
                            f"(joints: {', '.join(sorted(system.joints)) or 'none'}); add [joints.{joint}]")
    return system.joints[joint]


def material_record(system: System, name: str, needed_by: str = "this function",
                    where: str | None = None) -> Mapping[str, Any]:
    """The material ``[materials.<name>]`` of ``system`` (values, provenance stripped, read-only); a missing one
    raises :class:`~gearopt.errors.DataFileError` naming the file, the key path ``materials.<name>``, the key
    that refers to it (``where``, e.g. ``"joints.cam.hub_material"``) and the materials the file has."""
    if name not in system.materials:
        ref = f" ({where} = {name!r})" if where else ""
        raise DataFileError(f"{system.source}: materials.{name} is missing{ref}: {needed_by} needs it (materials: "
                            f"{', '.join(sorted(system.materials)) or 'none'}); add [materials.{name}]")
    return system.materials[name]


def require_section(source: System, section: str, needed_by: str = "this function") -> Any:
    """The top-level ``section`` of the :class:`System` ``source`` (a copy, provenance strings included).

    Anything but a System raises as :func:`system_of`; a file without the section raises
    :class:`~gearopt.errors.MissingSectionError` naming the file, ``[section]`` and ``needed_by``
    (:meth:`System.require`)."""
    system = system_of(source, needed_by)
    system.require(section, needed_by)
    return copy.deepcopy(system._data[section])          # the section only (System.data copies the whole file)


__all__ = ["system_of", "joint_record", "material_record", "require_section"]
