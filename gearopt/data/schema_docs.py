"""The data-file schema as a Markdown document (:func:`schema_markdown`; ``docs/data-schema.md`` is its text): one
row per key with kind, unit, range, whether it is required, and its meaning."""

from __future__ import annotations

from .schema_keys import REQUIRED_SECTIONS, SECTION_USES, RULES, UNIT_SUFFIXES, default_range, unit_of
from .schema_tree import Node, schema

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
    "design_loads": "application factor, torque-range fractions and speed of the design loads",
    "excitation": "a generic driving torque (mean plus harmonics) on one gear, for trains without an engine",
    "design_limits": "design limits",
    "requirements": "the requirements every verdict judges and the design NLPs carry (each key optional; defaults "
                    "in gearopt.data.requirements)",
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
        "gearopt reads a gear system from a TOML file: the packaged timing train",
        "(`gearopt/data/default_train.toml`), the packaged minimal pair (`gearopt/data/minimal_train.toml`, a",
        "complete two-gear example of every section a study of a pair needs) or a file of yours.",
        "`gearopt.load_system(path)` parses and validates it once and returns a typed, frozen `System`: gears, meshes",
        "(each with its own name, design torque and load range), train variants, materials, lubrication, joints,",
        "design loads and limits, and the excitation (an `[engine]` or a generic `[excitation]` driving torque).",
        "Every file is validated on load: unknown keys (with the nearest valid key), missing keys, types, ranges in",
        "the unit of the key's suffix, and cross-references. All problems of a file are reported together in one",
        "`DataFileError` (a `GearoptInputError`), each line naming the file and the key path; an empty, damaged or",
        "non-UTF-8 file gives one error naming the file.",
        "",
        "Conventions: the unit of a number is the suffix of its key (`_mm` millimetres, `_um` micrometres, `_deg`",
        "degrees, `_Nm` newton metres, `_kgm2` kg m^2, `_MPa`, `_rpm` ...); keys without a unit suffix are",
        "dimensionless. Any key `foo` may have a sibling `foo_source` (a string: its provenance). `nan`, `inf` and",
        "numbers given as strings are rejected everywhere. Named tables (`gears`, `meshes`, `materials`, `joints`)",
        "hold entries with names of your choice, shown as `*` below; `trains` holds `spur` and/or `helical`.",
        "",
        "Meshes are named `<driving>-<driven>` by their gears' names, and each states its own design load:",
        "`[meshes.<name>] design_torque_Nm` (the torque on the driving gear) and optionally `torque_range_Nm` (the",
        "load cases of its design range; default: the design torque times `[design_loads] torque_range_fractions`).",
        "",
        f"Required sections: {', '.join('`' + s + '`' for s in REQUIRED_SECTIONS)}. The other sections are",
        "optional; when present, their required keys must be there (the models that read them need them). A study",
        "that needs a section the file lacks stops with a `MissingSectionError` naming the file and the section:",
        "",
        *[f"- `[{name}]`: {use}" for name, use in SECTION_USES.items()],
        "",
        "Cross-checks: mesh gears, `trains.*.root_mesh`/`root_gear`, gear materials, joint gears and the",
        "excitation's gear must exist; a mesh is named `<driving>-<driven>`; lower allowances do not exceed upper",
        "ones; `engine.firing_order` is a permutation of 1..`engine.cylinders`; the camshaft and crankshaft station",
        "lists match their counts; the excitation's harmonic lists have one entry per harmonic.",
        "",
        "| key | kind | unit | range | required | meaning |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for path, kind, unit, rng, required, meaning in _rows(schema()):
        lines.append(f"| `{path}` | {kind} | {unit} | {rng} | {'yes' if required else 'no'} | {meaning} |")
    return "\n".join(lines) + "\n"
