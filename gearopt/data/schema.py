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

Modules: :mod:`~gearopt.data.schema_keys` (the table of keys and rules), :mod:`~gearopt.data.schema_tree` (the tree
read from the reference file), :mod:`~gearopt.data.schema_validate` and :mod:`~gearopt.data.schema_crossrefs` (the
checks and their messages), :mod:`~gearopt.data.schema_docs` (the Markdown); this module reads files and re-exports
the public names of the others.
"""

from __future__ import annotations

import tomllib

from ..errors import DataFileError
# the schema's names, importable from here (some only re-exported)
from .schema_docs import SECTION_MEANINGS, schema_markdown
from .schema_keys import (MAX_MAGNITUDE, NAMED_TABLES, NON_NEGATIVE_UNITS, REQUIRED_ITEM_KEYS, REQUIRED_SECTIONS,
                          RULES, SCHEMA_VERSION, SIGNED_WORDS, TRAIN_KINDS, UNIT_SUFFIXES, Rule, default_range,
                          generic_path, rule_for, unit_of)
from .schema_tree import Node, schema
from .schema_validate import validate_data


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


__all__ = ["SCHEMA_VERSION", "REQUIRED_SECTIONS", "RULES", "Rule", "UNIT_SUFFIXES", "schema", "validate_data",
           "parse_data_file", "schema_markdown", "unit_of", "default_range"]
