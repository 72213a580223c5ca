"""Validation of parsed data against the schema (:func:`validate_data`): unknown keys with the nearest valid key,
missing keys, types, ranges in the unit of the key's suffix, then the cross-references between sections
(:mod:`gearopt.data.schema_crossrefs`). Every problem is one line naming the key path; all of a file's problems are
raised together in one :class:`~gearopt.errors.DataFileError`."""

from __future__ import annotations

import difflib
import hashlib
import math
import pickle
import re

from ..errors import DataFileError
from .schema_crossrefs import cross_checks
from .schema_keys import MAX_MAGNITUDE, TRAIN_KINDS, default_range, rule_for, unit_of
from .schema_tree import Node, schema

_VALID: set[bytes] = set()
"""Digests of the data contents found valid in this process (:func:`validate_data` checks each content once)."""
_MAX_VALID = 1024


def _content_digest(data: dict) -> bytes | None:
    """SHA-256 of the pickled contents (keys, values and their types), or None when they do not pickle."""
    try:
        return hashlib.sha256(pickle.dumps(data, protocol=pickle.HIGHEST_PROTOCOL)).digest()
    except Exception:  # noqa: BLE001 -- an unpicklable value: validated every time, as before
        return None


def validate_data(data: dict, source: str = "<data>") -> dict:
    """Check parsed data against the schema; return ``data`` unchanged or raise
    :class:`~gearopt.errors.DataFileError` listing every problem as ``<source>: <key path>: <problem>``.

    Contents found valid once in this process (same keys, values and value types, by digest) are not checked
    again: the checks are a pure function of the contents, and a long run validates the same data at every
    train it builds (~30 ms each). Data that fails is checked (and fails) every time."""
    problems: list[str] = []
    if not isinstance(data, dict):
        raise DataFileError(f"{source}: the data must be a table of sections (got {type(data).__name__})")
    digest = _content_digest(data)
    if digest is not None and digest in _VALID:
        return data
    _check_table(data, schema(), "", problems)
    if not problems:
        cross_checks(data, problems)
    if problems:
        head = f"{source}: {len(problems)} problem{'s' if len(problems) > 1 else ''} in the data"
        raise DataFileError(head + "\n" + "\n".join(f"  - {source}: {p}" for p in problems[:40])
                            + (f"\n  ... and {len(problems) - 40} more" if len(problems) > 40 else ""))
    if digest is not None:
        if len(_VALID) >= _MAX_VALID:
            _VALID.clear()
        _VALID.add(digest)
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
        if key not in known and path == "design_loads" and key.endswith("_torque_Nm"):
            problems.append(f"{where}: design torques are stated per mesh: move it to [meshes.<driving>-<driven>] "
                            f"as design_torque_Nm (the torque on the mesh's driving gear [N m])")
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

