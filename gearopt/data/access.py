"""Data access for library functions: a :class:`~gearopt.data.system.System` or its validated dict, never the
packaged file behind the caller's back.

Library functions that read whole section trees (the engine models, the joint/blank/web tables) take ``data``: a
:class:`System` (``gearopt.load_system(path)``) or the validated dict of a data file
(``gearopt.load_default_data(path)``). :func:`data_of` returns the dict of either and raises when the caller gave
none; :func:`require_section` returns one top-level section and raises
:class:`~gearopt.errors.MissingSectionError` naming the file (when known), the section and what needs it.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ..errors import DataFileError, GearoptInputError, MissingSectionError
from .schema_keys import SECTION_USES
from .system import Joint, System, system_from_data


def data_of(source: System | Mapping[str, Any] | None, needed_by: str = "this function") -> dict[str, Any]:
    """The validated data dict of ``source``: ``system.data`` of a :class:`System` (a deep copy), or the mapping
    itself. ``None`` (no data given) raises :class:`~gearopt.errors.GearoptInputError` naming the argument and
    ``needed_by``: the library never falls back to the packaged data."""
    if isinstance(source, System):
        return source.data
    if source is None:
        raise GearoptInputError(
            f"{needed_by}: data is required (got None): pass the System of your data file "
            f"(gearopt.load_system(path)) or its validated dict (gearopt.load_default_data(path)); the library does "
            f"not read the packaged default data on its own")
    if not isinstance(source, Mapping):
        raise GearoptInputError(f"{needed_by}: data={type(source).__name__} must be a System "
                                f"(gearopt.load_system(path)) or the dict of a data file")
    return source if isinstance(source, dict) else dict(source)


def system_of(source: System | Mapping[str, Any] | None, needed_by: str = "this function") -> System:
    """The :class:`System` of ``source``: the system itself, or the :class:`System` of a validated data dict
    (:func:`~gearopt.data.system.system_from_data`; validation is cached by content, so a dict already validated
    costs a few ms). The one conversion point of the library functions that take a System (during the transition
    they still accept the validated dict). ``None`` or a non-mapping raises as :func:`data_of`."""
    if isinstance(source, System):
        return source
    return system_from_data(data_of(source, needed_by))


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


def source_name(source: System | Mapping[str, Any] | None) -> str:
    """The file name of a :class:`System`, ``"<data>"`` for a plain dict (messages)."""
    return source.source if isinstance(source, System) else "<data>"


def require_section(source: System | Mapping[str, Any] | None, section: str,
                    needed_by: str = "this function") -> Any:
    """The top-level ``section`` of ``source`` (a :class:`System` or a data dict; provenance strings included).

    No data raises as :func:`data_of`; data without the section raise
    :class:`~gearopt.errors.MissingSectionError` naming the file (``"<data>"`` for a plain dict), ``[section]``
    and ``needed_by`` (the same message as :meth:`System.require`)."""
    if isinstance(source, System):
        source.require(section, needed_by)
        return source.data[section]
    data = data_of(source, needed_by)
    if section not in data:
        use = SECTION_USES.get(section)
        raise MissingSectionError(
            f"{source_name(source)}: [{section}] is missing: {needed_by} needs it"
            + (f" ({section} holds {use})" if use else "") + "; add the section (docs/data-schema.md)")
    return data[section]


__all__ = ["data_of", "system_of", "joint_record", "material_record", "require_section", "source_name"]
