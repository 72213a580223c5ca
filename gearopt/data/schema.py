"""Schema of gearopt's data files (``default_train.toml`` and user files of the same layout), validated on load.

The packaged default file is the reference instance of the schema: it fixes which sections and keys exist, their
value kinds (number, integer, text, list, table) and which keys every entry of a named table (``gears.<name>``,
``meshes.<name>``, ``materials.<name>``, ``joints.<name>``) must have. :data:`RULES` adds, per key, the unit,
admissible range, choices and meaning; the unit of every other key follows from its name's suffix
(:data:`UNIT_SUFFIXES`, gearopt's naming convention). ``docs/data-schema.md`` is generated from this module
(:func:`schema_markdown`).

What :func:`validate_data` checks, with the file and the key path in every message:

- unknown keys (with the nearest valid key, by ``difflib``: a misspelt key or a key with another unit suffix);
- missing keys: the sections a gear train needs (``schema_version``, ``rack``, ``trains``, ``gears``, ``meshes``)
  and, in every section present, the keys its consumers read;
- types: numbers are real numbers (TOML floats or integers; ``nan``/``inf`` and strings are rejected), counts are
  integers, texts are strings, lists have the right element kind and length;
- ranges and units: each number within its key's range (in the unit of its suffix);
- cross-references: mesh gears, root mesh/gear, gear materials, joint gears exist; lists that describe the same
  stations have consistent lengths; allowances are ordered (lower <= upper).

All problems of a file are reported together in one :class:`~gearopt.errors.DataFileError`.
"""

from __future__ import annotations

import difflib
import math
import re
import tomllib
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from typing import Any

from ..errors import DataFileError

SCHEMA_VERSION = 1
REQUIRED_SECTIONS = ("schema_version", "rack", "trains", "gears", "meshes")
#: Tables whose keys are names chosen by the user; every entry follows the same item layout.
NAMED_TABLES = ("gears", "meshes", "materials", "joints", "trains")
TRAIN_KINDS = ("spur", "helical")
#: Keys every entry of these named tables must have (the gear-train builder reads them); the other keys of their
#: entries are optional. Entries of the other named tables need the keys every default entry has.
REQUIRED_ITEM_KEYS = {"gears": {"teeth", "face_width_mm"}, "meshes": {"gears", "centre_distance_mm"},
                      "trains": {"helix_angle_deg", "root_mesh", "root_gear"}}
MAX_MAGNITUDE = 1e15

#: Unit of a key, from its name's suffix (longest suffix first).
UNIT_SUFFIXES = {
    "_N_per_mm_sqrt_s_K": "N/(mm s^0.5 K)", "_Nms_per_rad": "N m s/rad", "_Nm_per_rad": "N m/rad",
    "_N_per_m": "N/m", "_kg_m3": "kg/m^3", "_W_mK": "W/(m K)", "_J_kgK": "J/(kg K)", "_per_K": "1/K",
    "_bar_abs": "bar (absolute)", "_Rz_um": "um (Rz)", "_kgm2": "kg m^2", "_mm2": "mm^2", "_percent": "%",
    "_MPa": "MPa", "_HRC": "HRC", "_rpm": "rpm", "_deg": "deg", "_bar": "bar", "_kW": "kW", "_kJ": "kJ",
    "_Hz": "Hz", "_Nm": "N m", "_mm": "mm", "_um": "um", "_kg": "kg", "_HV": "HV", "_C": "degC", "_N": "N",
    "_L": "L", "_K": "K",
}
#: Units whose quantities cannot be negative (lengths and micrometres only outside allowances and deviations).
NON_NEGATIVE_UNITS = {"kg m^2", "kg", "kg/m^3", "Hz", "rpm", "mm^2", "L", "W/(m K)", "J/(kg K)", "N/m", "N m/rad",
                      "N m s/rad", "kW", "HRC", "HV", "bar", "bar (absolute)", "mm", "um", "um (Rz)", "MPa", "N",
                      "kJ", "N/(mm s^0.5 K)", "1/K"}
SIGNED_WORDS = ("allowance", "deviation", "change", "offset", "torque_min", "start_of_combustion")


@dataclass(frozen=True)
class Rule:
    """Explicit rule of one key (``*`` in a path matches any entry of a named table)."""

    meaning: str
    low: float | None = None
    high: float | None = None
    low_inclusive: bool = True
    high_inclusive: bool = True
    kind: str | None = None  # "int", "float", "str", "list[str]" ... (default: the default file's kind)
    choices: tuple | None = None
    length: int | None = None
    required: bool | None = None  # default: required if every default entry has the key


RULES: dict[str, Rule] = {
    "schema_version": Rule("version of the key layout; this gearopt reads version 1", 1, 1, kind="int"),
    "title": Rule("free text naming the data set", required=False),
    "rack.module_mm": Rule("normal module m_n of the basic rack", 0.05, 100.0, low_inclusive=True),
    "rack.pressure_angle_deg": Rule("normal pressure angle alpha_n of the basic rack", 0.0, 45.0,
                                    low_inclusive=False, high_inclusive=False),
    "rack.addendum_coefficient": Rule("addendum h_aP* of the basic rack, per m_n", 0.0, 3.0, low_inclusive=False),
    "rack.dedendum_coefficient": Rule("dedendum h_fP* of the basic rack, per m_n", 0.0, 3.0, low_inclusive=False),
    "rack.root_radius_coefficient": Rule("root radius rho_fP* of the basic rack, per m_n", 0.0, 1.0),
    "trains.*.helix_angle_deg": Rule("reference helix angle beta of the train (0: spur)", 0.0, 45.0,
                                     high_inclusive=False),
    "trains.*.root_mesh": Rule("the mesh whose shifts are set first ('<driving>-<driven>', a key of meshes)"),
    "trains.*.root_gear": Rule("the gear of the root mesh whose profile shift or split is given"),
    "trains.*.root_profile_shift": Rule("profile shift coefficient x of the root gear", -3.0, 3.0, required=False),
    "trains.*.root_shift_split": Rule("ISO/TR 4467 split lambda of the root mesh's sum of shifts", -0.5, 1.5,
                                      required=False),
    "trains.*.root_hand": Rule("helix hand of the root gear ('right'/'left')", choices=("right", "left"),
                               required=False),
    "trains.*.shift_distribution_lambda": Rule("ISO/TR 4467 lambda used for the other meshes", -0.5, 1.5,
                                               required=False),
    "trains.*.thesis_profile_shifts": Rule("profile shifts of the source study by gear name (comparison only)",
                                           -3.0, 3.0, kind="map[float]", required=False),
    "gears.*.teeth": Rule("number of teeth z", 5, 10000, kind="int"),
    "gears.*.face_width_mm": Rule("face width b", 0.0, 10000.0, low_inclusive=False),
    "gears.*.tooth_thickness_upper_allowance_um": Rule("upper normal tooth-thickness allowance E_sns", -5000.0,
                                                       5000.0),
    "gears.*.tooth_thickness_lower_allowance_um": Rule("lower normal tooth-thickness allowance E_sni", -5000.0,
                                                       5000.0),
    "gears.*.tip_diameter_upper_allowance_mm": Rule("upper tip-diameter allowance", -50.0, 50.0),
    "gears.*.tip_diameter_lower_allowance_mm": Rule("lower tip-diameter allowance", -50.0, 50.0),
    "gears.*.accuracy_grade_iso1328": Rule("ISO 1328 accuracy grade", 1, 12, kind="int"),
    "gears.*.material": Rule("material name (a key of materials)"),
    "gears.*.role": Rule("what the gear drives (free text)"),
    "gears.*.speed_ratio_to_crank": Rule("speed of the gear / crank speed", 0.0, 100.0, low_inclusive=False),
    "gears.*.web_pocket_area_fraction": Rule("fraction of the web area removed by pockets", 0.0, 1.0,
                                             high_inclusive=False),
    "meshes.*.gears": Rule("the two gears of the mesh, driving first (keys of gears)", kind="list[str]", length=2),
    "meshes.*.centre_distance_mm": Rule("working centre distance a", 0.0, 1e5, low_inclusive=False),
    "meshes.*.centre_distance_upper_allowance_mm": Rule("upper centre-distance allowance", -50.0, 50.0),
    "meshes.*.centre_distance_lower_allowance_mm": Rule("lower centre-distance allowance", -50.0, 50.0),
    "meshes.*.sum_profile_shift": Rule("sum of profile shifts x1 + x2 (check value)", -6.0, 6.0),
    "meshes.*.standard_centre_distance_change_percent": Rule("a / a_d - 1 (check value)", -50.0, 50.0),
    "meshes.*.speed_ratio_error_percent": Rule("speed-ratio error against the target (check value)", -100.0, 100.0),
    "service.backlash_range_mm": Rule("service backlash range (min, max)", 0.0, 10.0, kind="list[float]", length=2),
    "materials.*.E_MPa": Rule("Young's modulus", 1e3, 1e6),
    "materials.*.poisson_ratio": Rule("Poisson's ratio", 0.0, 0.5, low_inclusive=False, high_inclusive=False),
    "materials.*.thermal_expansion_per_K": Rule("linear thermal expansion coefficient", 0.0, 1e-3),
    "materials.*.description": Rule("free text"),
    "materials.*.used_for": Rule("free text"),
    "joints.*.joint_type": Rule("'press_fit' or 'taper_nut'", choices=("press_fit", "taper_nut")),
    "joints.*.gear": Rule("the gear held by the joint (a key of gears)"),
    "joints.*.friction_coefficient": Rule("friction coefficient of the joint surfaces", 0.0, 1.0,
                                          low_inclusive=False, high_inclusive=False),
    "joints.*.nut_factor": Rule("nut factor k of T = k F d", 0.0, 1.0, low_inclusive=False, required=False),
    "joints.*.taper_half_angle_deg": Rule("half angle of the taper", 0.0, 45.0, low_inclusive=False,
                                          high_inclusive=False, required=False),
    "engine.cylinders": Rule("number of cylinders", 1, 32, kind="int"),
    "engine.strokes_per_cycle": Rule("2 or 4", choices=(2, 4), kind="int"),
    "engine.valves_per_cylinder": Rule("valves per cylinder", 1, 8, kind="int"),
    "engine.bore_mm": Rule("cylinder bore", 1.0, 2000.0),
    "engine.stroke_mm": Rule("piston stroke", 1.0, 5000.0),
    "engine.connecting_rod_length_mm": Rule("connecting-rod centre distance", 1.0, 10000.0),
    "engine.compression_ratio": Rule("geometric compression ratio", 1.0, 50.0, low_inclusive=False),
    "engine.firing_order": Rule("cylinders in firing order (a permutation of 1..cylinders)", 1, 32,
                                kind="list[int]"),
    "engine.crank_rod_ratio": Rule("crank radius / rod length", 0.0, 1.0, low_inclusive=False,
                                   high_inclusive=False),
    "engine.camshaft.stations": Rule("cam stations (lumped inertias) along the camshaft", 1, 100, kind="int"),
    "engine.fuel_pump.plungers": Rule("pump plungers", 1, 16, kind="int"),
    "engine.combustion.model": Rule("combustion model", choices=("double_wiebe",)),
    "engine.combustion.premixed_fraction": Rule("premixed share of the heat release", 0.0, 1.0),
    "engine.combustion.ratio_of_specific_heats": Rule("gamma of the cylinder charge", 1.0, 2.0,
                                                      low_inclusive=False),
    "engine.crankshaft.shaft_loss_factor": Rule("material loss factor of the crankshaft", 0.0, 1.0),
    "engine.crankshaft.mode_1_damping_ratio": Rule("damping ratio of the first crankshaft mode", 0.0, 1.0),
    "dynamics.mesh_damping_ratio": Rule("damping ratio of the gear meshes", 0.0, 1.0, high_inclusive=False),
    "lubrication.mean_friction_coefficient": Rule("mean tooth friction coefficient (Blok)", 0.0, 1.0,
                                                  high_inclusive=False),
    "lubrication.oil_temperature_C": Rule("oil (bulk) temperature", -50.0, 300.0),
    "design_loads.application_factor_K_A": Rule("ISO 6336-1 application factor", 1.0, 10.0),
    "design_limits.min_loaded_contact_ratio": Rule("smallest admissible loaded contact ratio", 0.0, 5.0),
    "microgeometry.initial.tip_relief_shape": Rule("tip relief shape", choices=("linear", "parabolic", "arc")),
}


# ----------------------------------------------------------------------------------------------------------------
# the skeleton from the reference instance
# ----------------------------------------------------------------------------------------------------------------

def _kind(value) -> str:
    if isinstance(value, bool):
        return "bool"
    if isinstance(value, int):
        return "int"
    if isinstance(value, float):
        return "float"
    if isinstance(value, str):
        return "str"
    if isinstance(value, dict):
        return "table"
    if isinstance(value, list):
        inner = {_kind(v) for v in value}
        if inner <= {"int", "float"} and inner:
            return "list[float]" if "float" in inner else "list[int]"
        if inner == {"str"}:
            return "list[str]"
        if inner and all(k.startswith("list[") for k in inner):
            return "list[list]"
        return "list"
    return type(value).__name__


@dataclass
class Node:
    """A key of the schema: a value (``kind`` not ``table``) or a table of keys (``children``); ``named`` tables
    hold user-named entries that all follow ``item``."""

    path: str
    kind: str
    required: bool = True
    children: dict | None = None
    item: "Node | None" = None
    example: Any = None


def _build(path: str, value, required: bool = True) -> Node:
    if not isinstance(value, dict):
        return Node(path, _kind(value), required, example=value)
    last = path.rsplit(".", 1)[-1]
    if last in NAMED_TABLES and "." not in path:
        entries = [v for v in value.values() if isinstance(v, dict)]
        keys: dict[str, list] = {}
        for entry in entries:
            for k, v in entry.items():
                if not k.endswith("_source"):
                    keys.setdefault(k, []).append(v)
        item_children = {}
        for k, vs in keys.items():
            node = _merge([_build(f"{path}.*.{k}", v) for v in vs])
            node.required = k in REQUIRED_ITEM_KEYS[path] if path in REQUIRED_ITEM_KEYS else len(vs) == len(entries)
            item_children[k] = node
        return Node(path, "named", required, item=Node(f"{path}.*", "table", True, item_children))
    children = {k: _build(f"{path}.{k}" if path else k, v) for k, v in value.items() if not k.endswith("_source")}
    return Node(path, "table", required, children)


def _merge(nodes: list[Node]) -> Node:
    first = nodes[0]
    if first.kind == "table":
        children: dict[str, list] = {}
        for n in nodes:
            for k, c in (n.children or {}).items():
                children.setdefault(k, []).append(c)
        merged = {k: _merge(cs) for k, cs in children.items()}
        for k, cs in children.items():
            merged[k].required = len(cs) == len(nodes)
        return Node(first.path, "table", first.required, merged)
    kinds = {n.kind for n in nodes}
    if kinds == {"int", "float"}:
        return Node(first.path, "float", first.required, example=first.example)
    return first


@lru_cache(maxsize=1)
def schema() -> Node:
    """The schema tree (from the packaged default file plus :data:`RULES`)."""
    with resources.files(__package__).joinpath("default_train.toml").open("rb") as fh:
        reference = tomllib.load(fh)
    root = _build("", reference)
    for section in root.children:
        root.children[section].required = section in REQUIRED_SECTIONS
    _apply_rules(root)
    return root


def _apply_rules(root: Node) -> None:
    for path, rule in RULES.items():
        node = _find(root, path)
        if node is None:
            raise AssertionError(f"schema rule {path!r} names no key of the reference file")
        if rule.kind is not None:
            node.kind = rule.kind
            if rule.kind.startswith("map["):
                node.children = None
        if rule.required is not None:
            node.required = rule.required


def _find(root: Node, path: str) -> Node | None:
    node = root
    for part in path.split("."):
        if node.kind == "named":
            node = node.item
            if part != "*":
                return None
            continue
        if not node.children or part not in node.children:
            return None
        node = node.children[part]
    return node


def rule_for(path: str) -> Rule | None:
    """The explicit rule of a concrete key path (entry names replaced by ``*``)."""
    return RULES.get(generic_path(path))


def generic_path(path: str) -> str:
    parts = path.split(".")
    if parts and parts[0] in NAMED_TABLES and len(parts) > 1:
        parts[1] = "*"
    return ".".join(parts)


def unit_of(key: str) -> str:
    """The unit of a key from its name's suffix ('' for dimensionless keys)."""
    for suffix, unit in UNIT_SUFFIXES.items():
        if key.endswith(suffix):
            return unit
    return ""


def default_range(path: str) -> tuple[float | None, float | None]:
    """Range of a number without an explicit rule: non-negative for units that cannot be negative (lengths outside
    allowances and deviations, masses, inertias, stiffnesses, speeds, pressures ...), otherwise any finite value."""
    key = path.rsplit(".", 1)[-1]
    unit = unit_of(key)
    if unit in NON_NEGATIVE_UNITS and not any(w in key for w in SIGNED_WORDS):
        return 0.0, None
    return None, None


# ----------------------------------------------------------------------------------------------------------------
# validation
# ----------------------------------------------------------------------------------------------------------------

def validate_data(data: dict, source: str = "<data>") -> dict:
    """Check parsed data against the schema; return ``data`` unchanged or raise
    :class:`~gearopt.errors.DataFileError` listing every problem as ``<source>: <key path>: <problem>``."""
    problems: list[str] = []
    if not isinstance(data, dict):
        raise DataFileError(f"{source}: the data must be a table of sections (got {type(data).__name__})")
    _check_table(data, schema(), "", problems)
    if not problems:
        _cross_checks(data, problems)
    if problems:
        head = f"{source}: {len(problems)} problem{'s' if len(problems) > 1 else ''} in the data"
        raise DataFileError(head + "\n" + "\n".join(f"  - {source}: {p}" for p in problems[:40])
                            + (f"\n  ... and {len(problems) - 40} more" if len(problems) > 40 else ""))
    return data


def _check_table(table: dict, node: Node, path: str, problems: list[str]) -> None:
    known = node.children or {}
    for key, value in table.items():
        where = f"{path}.{key}" if path else key
        if key.endswith("_source"):
            base = key[: -len("_source")]
            if base not in known and base not in table:
                problems.append(f"{where}: provenance of an unknown key {base!r}")
            elif not isinstance(value, str):
                problems.append(f"{where}: provenance must be a string (got {type(value).__name__})")
            continue
        if key not in known:
            near = difflib.get_close_matches(key, list(known), n=1, cutoff=0.6)
            hint = f"; did you mean {near[0]!r}?" if near else f"; valid keys: {', '.join(sorted(known)[:12])}" + (
                " ..." if len(known) > 12 else "")
            problems.append(f"{where}: unknown key{hint}")
            continue
        _check_value(value, known[key], where, problems)
    for key, child in known.items():
        if child.required and key not in table:
            where = f"{path}.{key}" if path else key
            unit = unit_of(key)
            problems.append(f"{where}: missing key ({_describe(child, where)}{', unit ' + unit if unit else ''})")


def _describe(node: Node, path: str) -> str:
    rule = rule_for(path)
    if node.kind in ("table", "named"):
        return "a table"
    return f"{node.kind}" + (f": {rule.meaning}" if rule else "")


def _check_value(value, node: Node, path: str, problems: list[str]) -> None:
    if node.kind == "named":
        if not isinstance(value, dict):
            problems.append(f"{path}: must be a table of named entries (got {type(value).__name__})")
            return
        if not value:
            problems.append(f"{path}: must have at least one entry")
        for name, entry in value.items():
            if not isinstance(entry, dict):
                problems.append(f"{path}.{name}: must be a table (got {type(entry).__name__} {entry!r:.40})")
                continue
            if path == "trains" and name not in TRAIN_KINDS:
                near = difflib.get_close_matches(name, TRAIN_KINDS, n=1, cutoff=0.5)
                problems.append(f"trains.{name}: unknown train kind" + (f"; did you mean {near[0]!r}?" if near
                                                                         else f"; valid: {TRAIN_KINDS}"))
                continue
            _check_table(entry, node.item, f"{path}.{name}", problems)
        return
    if node.kind == "table":
        if not isinstance(value, dict):
            problems.append(f"{path}: must be a table (got {type(value).__name__} {value!r:.40})")
            return
        _check_table(value, node, path, problems)
        return
    _check_leaf(value, node.kind, path, problems)


def _check_leaf(value, kind: str, path: str, problems: list[str]) -> None:
    rule = rule_for(path)
    if kind == "str":
        if not isinstance(value, str):
            problems.append(f"{path}: must be a string (got {type(value).__name__} {value!r:.40})")
        elif rule and rule.choices and value not in rule.choices:
            problems.append(f"{path}: {value!r} is not one of {rule.choices}")
        return
    if kind == "bool":
        if not isinstance(value, bool):
            problems.append(f"{path}: must be true or false (got {value!r:.40})")
        return
    if kind.startswith("map["):
        if not isinstance(value, dict):
            problems.append(f"{path}: must be a table of numbers by name (got {type(value).__name__})")
            return
        for name, v in value.items():
            _check_number(v, "float", f"{path}.{name}", path, problems)
        return
    if kind.startswith("list"):
        if not isinstance(value, list):
            problems.append(f"{path}: must be a list (got {type(value).__name__} {value!r:.40})")
            return
        if rule and rule.length is not None and len(value) != rule.length:
            problems.append(f"{path}: must have {rule.length} entries (got {len(value)})")
        inner = kind[5:-1] if kind.endswith("]") else ""
        if inner in ("float", "int", "str"):
            for i, v in enumerate(value):
                _check_leaf(v, inner, f"{path}[{i}]", problems)
        elif inner == "list":
            for i, row in enumerate(value):
                if not isinstance(row, list):
                    problems.append(f"{path}[{i}]: must be a list")
                    continue
                for j, v in enumerate(row):
                    _check_leaf(v, "float", f"{path}[{i}][{j}]", problems)
        return
    _check_number(value, kind, path, re.sub(r"\[\d+\]", "", path), problems)


def _check_number(value, kind: str, path: str, base: str, problems: list[str]) -> None:
    """A number at ``path`` whose rule and unit are those of the key ``base``."""
    unit = unit_of(base.rsplit(".", 1)[-1])
    u = f" {unit}" if unit else ""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        problems.append(f"{path}: must be a number{u} (got {type(value).__name__} {value!r:.40})")
        return
    if kind == "int" and not (isinstance(value, int) or float(value).is_integer()):
        problems.append(f"{path}: {value!r} must be an integer count")
        return
    v = float(value)
    if math.isnan(v):
        problems.append(f"{path}: nan is not a number{u}")
        return
    if math.isinf(v) or abs(v) > MAX_MAGNITUDE:
        problems.append(f"{path}: {value!r}{u} is not a finite number of plausible magnitude (|x| <= "
                        f"{MAX_MAGNITUDE:g})")
        return
    rule = rule_for(base)
    if rule and rule.choices is not None:
        if value not in rule.choices:
            problems.append(f"{path}: {value!r} is not one of {rule.choices}")
        return
    low, high = (rule.low, rule.high) if rule and (rule.low is not None or rule.high is not None) \
        else default_range(base)
    lo_inc = rule.low_inclusive if rule else True
    hi_inc = rule.high_inclusive if rule else True
    if low is not None and (v < low or (v == low and not lo_inc)):
        problems.append(f"{path}: {value!r}{u} is below its limit: must be {'>=' if lo_inc else '>'} {low:g}{u}"
                        + (f" ({rule.meaning})" if rule else ""))
    elif high is not None and (v > high or (v == high and not hi_inc)):
        problems.append(f"{path}: {value!r}{u} exceeds its limit: must be {'<=' if hi_inc else '<'} {high:g}{u}"
                        + (f" ({rule.meaning})" if rule else ""))


def _cross_checks(data: dict, problems: list[str]) -> None:
    gears, meshes = data.get("gears", {}), data.get("meshes", {})
    for name, m in meshes.items():
        pair = m.get("gears", [])
        for g in pair:
            if g not in gears:
                problems.append(f"meshes.{name}.gears: {g!r} is not a key of gears ({', '.join(gears)})")
        if len(pair) == 2 and pair[0] == pair[1]:
            problems.append(f"meshes.{name}.gears: a gear cannot mesh with itself ({pair[0]!r})")
        if len(pair) == 2 and name != f"{pair[0]}-{pair[1]}":
            problems.append(f"meshes.{name}: the table name must be '<driving>-<driven>' = '{pair[0]}-{pair[1]}'")
        _ordered(m, "centre_distance_lower_allowance_mm", "centre_distance_upper_allowance_mm", f"meshes.{name}",
                 problems)
    for kind, t in data.get("trains", {}).items():
        if t.get("root_mesh") not in meshes:
            near = difflib.get_close_matches(str(t.get("root_mesh")), list(meshes), n=1)
            problems.append(f"trains.{kind}.root_mesh: {t.get('root_mesh')!r} is not a key of meshes"
                            + (f"; did you mean {near[0]!r}?" if near else ""))
        elif t.get("root_gear") not in meshes[t["root_mesh"]].get("gears", []):
            problems.append(f"trains.{kind}.root_gear: {t.get('root_gear')!r} is not a gear of the root mesh "
                            f"{t['root_mesh']!r}")
    materials = data.get("materials")
    for name, g in gears.items():
        _ordered(g, "tooth_thickness_lower_allowance_um", "tooth_thickness_upper_allowance_um", f"gears.{name}",
                 problems)
        _ordered(g, "tip_diameter_lower_allowance_mm", "tip_diameter_upper_allowance_mm", f"gears.{name}", problems)
        if materials is not None and "material" in g and g["material"] not in materials:
            problems.append(f"gears.{name}.material: {g['material']!r} is not a key of materials "
                            f"({', '.join(materials)})")
    for name, j in data.get("joints", {}).items():
        if "gear" in j and j["gear"] not in gears:
            problems.append(f"joints.{name}.gear: {j['gear']!r} is not a key of gears")
    engine = data.get("engine", {})
    if "firing_order" in engine and "cylinders" in engine:
        if sorted(engine["firing_order"]) != list(range(1, engine["cylinders"] + 1)):
            problems.append(f"engine.firing_order: {engine['firing_order']} is not a permutation of 1.."
                            f"{engine['cylinders']} (engine.cylinders)")
    cam = engine.get("camshaft", {})
    if "stations" in cam:
        n = cam["stations"]
        for key, want in (("station_inertias_kgm2", n), ("station_stiffnesses_Nm_per_rad", n - 1)):
            if key in cam and len(cam[key]) != want:
                problems.append(f"engine.camshaft.{key}: has {len(cam[key])} entries; engine.camshaft.stations = "
                                f"{n} needs {want}")
    crank = engine.get("crankshaft", {})
    if "node_names" in crank:
        n = len(crank["node_names"])
        for key, want in (("inertias_kgm2", n), ("connection_stiffnesses_Nm_per_rad", n - 1)):
            if key in crank and len(crank[key]) != want:
                problems.append(f"engine.crankshaft.{key}: has {len(crank[key])} entries; "
                                f"engine.crankshaft.node_names has {n} nodes, which need {want}")
    trace = (engine.get("pressure_trace_crank_deg"), engine.get("pressure_trace_MPa"))
    if trace[0] is not None and trace[1] is not None and len(trace[0]) != len(trace[1]):
        problems.append(f"engine.pressure_trace_MPa: has {len(trace[1])} entries; engine.pressure_trace_crank_deg "
                        f"has {len(trace[0])}")


def _ordered(table: dict, low_key: str, high_key: str, path: str, problems: list[str]) -> None:
    if low_key in table and high_key in table and table[low_key] > table[high_key]:
        problems.append(f"{path}.{low_key}: {table[low_key]!r} exceeds {high_key} = {table[high_key]!r}")


# ----------------------------------------------------------------------------------------------------------------
# reading files
# ----------------------------------------------------------------------------------------------------------------

def parse_data_file(path) -> dict:
    """Read and parse a TOML data file; every failure (missing, unreadable, empty, not UTF-8, not TOML) is one
    :class:`~gearopt.errors.DataFileError` naming the file."""
    try:
        raw = open(path, "rb").read()
    except FileNotFoundError:
        raise DataFileError(f"{path}: data file not found") from None
    except (IsADirectoryError, PermissionError, OSError) as exc:
        raise DataFileError(f"{path}: cannot read the data file ({type(exc).__name__}: {exc.strerror})") from None
    if not raw.strip():
        raise DataFileError(f"{path}: the data file is empty (expected TOML with the sections "
                            f"{', '.join(REQUIRED_SECTIONS)}; see docs/data-schema.md)")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise DataFileError(f"{path}: the data file is not UTF-8 text (byte {exc.start}, line {line}: "
                            f"{raw[exc.start:exc.start + 1]!r}); save it as UTF-8") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise DataFileError(f"{path}: not valid TOML: {exc}") from None
    if not data:
        raise DataFileError(f"{path}: the data file is empty (only comments; expected the sections "
                            f"{', '.join(REQUIRED_SECTIONS)}; see docs/data-schema.md)")
    return data


# ----------------------------------------------------------------------------------------------------------------
# documentation
# ----------------------------------------------------------------------------------------------------------------

def _rows(node: Node, path: str = ""):
    if node.kind == "named":
        yield path, "table of named entries", "", "", bool(node.required), _section_meaning(path)
        yield from _rows(node.item, f"{path}.*")
        return
    if node.kind == "table":
        if path:
            yield path, "table", "", "", bool(node.required), _section_meaning(path)
        for k, child in node.children.items():
            yield from _rows(child, f"{path}.{k}" if path else k)
        return
    key = path.rsplit(".", 1)[-1]
    rule = RULES.get(path)
    if rule and rule.choices is not None:
        rng = "one of " + ", ".join(str(c) for c in rule.choices)
    elif rule and (rule.low is not None or rule.high is not None):
        lo = "-inf" if rule.low is None else f"{rule.low:g}"
        hi = "+inf" if rule.high is None else f"{rule.high:g}"
        rng = f"{'[' if rule.low_inclusive else '('}{lo}, {hi}{']' if rule.high_inclusive else ')'}"
    elif node.kind in ("float", "int", "list[float]", "list[int]", "list[list]"):
        low, _ = default_range(path)
        rng = ">= 0" if low == 0.0 else "finite"
    else:
        rng = ""
    if rule and rule.length:
        rng = (rng + f"; {rule.length} entries").strip("; ")
    meaning = rule.meaning if rule else _meaning_from_name(key)
    yield path, node.kind, unit_of(key), rng, bool(node.required), meaning


SECTION_MEANINGS = {
    "rack": "basic rack of all gears (normal section)",
    "trains": "train variants by kind (spur, helical): how the profile shifts are set",
    "gears": "one entry per gear (the entry name is the gear's name)",
    "meshes": "one entry per mesh, named '<driving>-<driven>'",
    "service": "service data",
    "materials": "one entry per material (name as used by gears.*.material and joints)",
    "engine": "the engine: geometry, speeds, pressure trace, combustion, torsional models of crankshaft, camshaft "
              "and accessories",
    "dynamics": "torsional-dynamics settings",
    "microgeometry": "initial tooth modifications",
    "lubrication": "lubrication",
    "joints": "one entry per shaft-hub joint (press fit or nut-clamped taper)",
    "design_loads": "design loads of the meshes",
    "design_limits": "design limits",
    "thesis": "tables of the source study (comparison data)",
}


def _section_meaning(path: str) -> str:
    if path.endswith(".*"):
        return f"an entry of {path[:-2]}"
    return SECTION_MEANINGS.get(path, _meaning_from_name(path.rsplit(".", 1)[-1]))


def _meaning_from_name(key: str) -> str:
    stem = key
    for suffix in UNIT_SUFFIXES:
        if key.endswith(suffix):
            stem = key[: -len(suffix)]
            break
    return stem.replace("_", " ").strip() or key


def schema_markdown() -> str:
    """The schema as a Markdown document (``docs/data-schema.md`` is this text)."""
    lines = [
        "# Data-file schema",
        "",
        "gearopt reads its engine and gear-train data from a TOML file: the packaged default",
        "(`gearopt/data/default_train.toml`) or a file of yours (`gearopt.data.load_default_data(path)`).",
        "Every file is validated on load (`gearopt.data.validate_data`): unknown keys (with the nearest valid key),",
        "missing keys, types, ranges in the unit of the key's suffix, and cross-references. All problems of a file",
        "are reported together in one `DataFileError` (a `GearoptInputError`), each line naming the file and the key",
        "path; an empty, damaged or non-UTF-8 file gives one error naming the file.",
        "",
        "Conventions: the unit of a number is the suffix of its key (`_mm` millimetres, `_um` micrometres, `_deg`",
        "degrees, `_Nm` newton metres, `_kgm2` kg m^2, `_MPa`, `_rpm` ...); keys without a unit suffix are",
        "dimensionless. Any key `foo` may have a sibling `foo_source` (a string: its provenance). `nan`, `inf` and",
        "numbers given as strings are rejected everywhere. Named tables (`gears`, `meshes`, `materials`, `joints`)",
        "hold entries with names of your choice, shown as `*` below; `trains` holds `spur` and/or `helical`.",
        "",
        f"Required sections: {', '.join('`' + s + '`' for s in REQUIRED_SECTIONS)}. The other sections are",
        "optional; when present, their required keys must be there (the models that read them need them).",
        "A minimal train file: `gearopt/data/minimal_train.toml`.",
        "",
        "Cross-checks: mesh gears, `trains.*.root_mesh`/`root_gear`, gear materials and joint gears must exist; a",
        "mesh is named `<driving>-<driven>`; lower allowances do not exceed upper ones; `engine.firing_order` is a",
        "permutation of 1..`engine.cylinders`; the camshaft and crankshaft station lists match their counts.",
        "",
        "| key | kind | unit | range | required | meaning |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for path, kind, unit, rng, required, meaning in _rows(schema()):
        lines.append(f"| `{path}` | {kind} | {unit} | {rng} | {'yes' if required else 'no'} | {meaning} |")
    return "\n".join(lines) + "\n"


__all__ = ["SCHEMA_VERSION", "REQUIRED_SECTIONS", "RULES", "Rule", "UNIT_SUFFIXES", "schema", "validate_data",
           "parse_data_file", "schema_markdown", "unit_of", "default_range"]
