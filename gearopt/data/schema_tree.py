"""The schema tree of gearopt's data files, read from the packaged reference instance (``default_train.toml``):
which sections and keys exist, their value kinds, which keys every entry of a named table must have, with the
explicit rules of :mod:`gearopt.data.schema_keys` applied."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
from typing import Any

from .schema_keys import NAMED_TABLES, REQUIRED_ITEM_KEYS, REQUIRED_SECTIONS, RULES

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


def _load(name: str) -> dict:
    with resources.files(__package__).joinpath(name).open("rb") as fh:
        return tomllib.load(fh)


@lru_cache(maxsize=1)
def schema() -> Node:
    """The schema tree: the packaged default file (the timing train) united with the packaged minimal example (the
    sections and optional keys only it has), plus :data:`RULES`."""
    reference = _load("default_train.toml")
    # the minimal example adds the sections the timing train has no use for (a generic [excitation]) and the
    # optional keys it alone shows (a mesh's torque_range_Nm, the design loads' overspeed_rpm)
    for section, value in _load("minimal_train.toml").items():
        if section not in reference:
            reference[section] = value
        elif section == "meshes":
            reference[section] = {**value, **reference[section]}
        elif isinstance(value, dict) and section not in NAMED_TABLES:
            reference[section] = {**value, **reference[section]}
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
