"""Packaged default data: the representative diesel engine and its timing gear train (docs/source-study.md sec. 1).

``default_train.toml`` gives every number a sibling ``<key>_source`` string with its provenance ([V] public source,
[T] thesis, [C] computed, [E] estimate). :func:`load_default_data` returns the parsed file; :func:`values` strips the
provenance; :func:`load_default_train` builds the spur redesign or the helical baseline as a
:class:`~gearopt.geometry.GearTrain`.
"""

from __future__ import annotations

import copy
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from ..errors import DataFileError, GearoptInputError
from ..geometry.train import GearSpec, GearTrain, MeshSpec, RackSpec
from .schema import parse_data_file, schema_markdown, validate_data
from .system import (DesignLimits, DesignLoads, DrivingTorque, Gear, Joint, Lubrication, Mesh, System, TrainVariant,
                     load_system, system_from_data)
from .access import joint_record, material_record, require_section, system_of
from .requirements import Requirements

DEFAULT_FILE = "default_train.toml"
TRAIN_KINDS = ("spur", "helical")


def default_data_path() -> Path:
    """Path of the packaged default data file."""
    return Path(str(resources.files(__package__).joinpath(DEFAULT_FILE)))


def load_thesis_tables() -> dict[str, Any]:
    """The thesis' macro-design tables 3.1-3.4 (``thesis_tables.toml``), for shape checks."""
    with resources.files(__package__).joinpath("thesis_tables.toml").open("rb") as fh:
        return tomllib.load(fh)


_LOADED: dict[tuple, dict[str, Any]] = {}
"""Validated data of the files loaded in this process, by (resolved path, modification time [ns], size)."""


def load_default_data(path: str | Path | None = None) -> dict[str, Any]:
    """Parse the default data file (or another file of the same schema) into nested dicts, provenance included.

    The file is validated against the data schema (``docs/data-schema.md``, :func:`validate_data`): a missing,
    empty, damaged or non-UTF-8 file, or one with unknown or missing keys, wrong types or values out of range,
    raises one :class:`~gearopt.errors.DataFileError` naming the file and every offending key path.

    A file already loaded in this process, unchanged since (same modification time and size), is not parsed and
    validated again: the caller gets its own deep copy of the validated data (a long run loads the default file
    from many places; parsing and validating it takes ~50 ms each time)."""
    p = Path(path) if path is not None else default_data_path()
    try:
        stat = p.stat()
        key = (str(p.resolve()), stat.st_mtime_ns, stat.st_size)
    except OSError:
        key = None                                   # parse_data_file names the problem
    if key in _LOADED:
        return copy.deepcopy(_LOADED[key])
    data = validate_data(parse_data_file(p), source=str(p))
    if key is not None:
        _LOADED[key] = copy.deepcopy(data)
    return data


def values(table: dict[str, Any]) -> dict[str, Any]:
    """A table without its ``*_source`` provenance strings (recursively)."""
    return {k: values(v) if isinstance(v, dict) else v for k, v in table.items() if not k.endswith("_source")}


def missing_provenance(table: dict[str, Any], prefix: str = "") -> list[str]:
    """Dotted names of numeric entries that lack a ``<key>_source`` sibling (empty list: fully documented)."""
    missing = []
    for key, val in table.items():
        name = f"{prefix}{key}"
        if isinstance(val, dict):
            if f"{key}_source" not in table:  # an inline table with one source string covers its entries
                missing.extend(missing_provenance(val, name + "."))
        elif _is_numeric(val) and f"{key}_source" not in table and not key.endswith("_source"):
            missing.append(name)
    return missing


def _is_numeric(val) -> bool:
    if isinstance(val, bool):
        return False
    if isinstance(val, (int, float)):
        return True
    if isinstance(val, list) and val:
        return all(_is_numeric(v) or isinstance(v, list) and all(_is_numeric(e) for e in v) for v in val)
    return False


def provenance_tags(table: dict[str, Any]) -> dict[str, str]:
    """Dotted name -> provenance tag (``V``, ``T``, ``C``, ``E``, ``M``) of every ``*_source`` string, or ``"?"``."""
    tags = {}
    for key, val in table.items():
        if isinstance(val, dict):
            tags.update({f"{key}.{k}": v for k, v in provenance_tags(val).items()})
        elif key.endswith("_source"):
            text = str(val).lstrip()
            tags[key] = text[1] if len(text) > 2 and text[0] == "[" and text[2] == "]" else "?"
    return tags


def train_from_data(data: dict[str, Any], kind: str = "spur", *, source: str = "<data>") -> GearTrain:
    """Build a :class:`GearTrain` of ``kind`` ("spur" or "helical") from parsed data of the default schema
    (validated first; ``source`` names the data in error messages)."""
    if kind not in TRAIN_KINDS:
        raise GearoptInputError(f"kind={kind!r} must be one of {TRAIN_KINDS}")
    validate_data(data, source=source)
    if kind not in data["trains"]:
        raise DataFileError(f"{source}: trains.{kind}: missing table (the data has trains "
                            f"{', '.join(data['trains'])})")
    d = values(data)
    rack = d["rack"]
    gears = {}
    for name, g in d["gears"].items():
        gears[name] = GearSpec(
            name=name, teeth=int(g["teeth"]), face_width_mm=float(g["face_width_mm"]),
            tooth_thickness_upper_allowance_um=float(g.get("tooth_thickness_upper_allowance_um", 0.0)),
            tooth_thickness_lower_allowance_um=float(g.get("tooth_thickness_lower_allowance_um", 0.0)),
            tip_diameter_allowance_mm=(float(g.get("tip_diameter_lower_allowance_mm", 0.0)),
                                       float(g.get("tip_diameter_upper_allowance_mm", 0.0))),
            material=g.get("material"), role=g.get("role", ""))
    meshes = {}
    for name, m in d["meshes"].items():
        mesh = MeshSpec(gears=tuple(m["gears"]), centre_distance_mm=float(m["centre_distance_mm"]),
                        centre_distance_allowance_mm=(float(m.get("centre_distance_lower_allowance_mm", 0.0)),
                                                      float(m.get("centre_distance_upper_allowance_mm", 0.0))))
        if mesh.name != name:
            raise GearoptInputError(f"mesh table {name!r} lists gears {m['gears']}: its name must be "
                                    f"'<driving>-<driven>' = {mesh.name!r}")
        meshes[name] = mesh
    t = d["trains"][kind]
    return GearTrain(
        gears=gears, meshes=meshes,
        rack=RackSpec(module_mm=float(rack["module_mm"]), pressure_angle_deg=float(rack["pressure_angle_deg"]),
                      addendum_coefficient=float(rack["addendum_coefficient"]),
                      dedendum_coefficient=float(rack["dedendum_coefficient"]),
                      root_radius_coefficient=float(rack["root_radius_coefficient"])),
        helix_angle_deg=float(t["helix_angle_deg"]), root_mesh=t["root_mesh"], root_gear=t["root_gear"],
        root_profile_shift=t.get("root_profile_shift"), root_shift_split=t.get("root_shift_split", 0.5),
        root_hand=t.get("root_hand", "right"), name=f"default {kind} timing train")


def load_default_train(kind: str = "spur", path: str | Path | None = None) -> GearTrain:
    """The packaged default timing train: ``"spur"`` (the redesign) or ``"helical"`` (the baseline)."""
    return train_from_data(load_default_data(path), kind, source=str(path or default_data_path()))


# load_system, System, load_default_data and load_default_train are imported from gearopt itself (gearopt.__all__)
__all__ = ["Gear", "Mesh", "TrainVariant", "Joint", "DesignLoads", "DesignLimits", "Lubrication", "DrivingTorque",
           "system_from_data", "validate_data", "parse_data_file", "schema_markdown", "default_data_path",
           "load_thesis_tables", "train_from_data", "values",
           "missing_provenance", "provenance_tags", "TRAIN_KINDS"]
__all__ += ["system_of", "joint_record", "material_record", "require_section", "Requirements"]
