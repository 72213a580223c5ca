"""The layer order of the package holds: every ``gearopt`` import (module level or inside a function) points to the
same subpackage or to a lower layer, and the NLP framework imports nothing of gears.

The order (``docs/architecture.md``)::

    errors, units -> numerics -> validation, nlp, compile_cache -> geometry -> data -> rating -> contact
      -> joints | blank | engine -> dynamics -> design -> studies -> report -> cases
      -> cli, the package facade

Siblings on one layer (joints, blank, engine) may not import each other: what two of them share moves down.
"""

from __future__ import annotations

import ast
import pathlib

import gearopt

PACKAGE = pathlib.Path(gearopt.__file__).parent

LAYERS = [("errors", "units"), ("numerics",), ("validation", "nlp", "compile_cache", "executor"), ("geometry",), ("data",),
          ("rating",), ("contact",), ("joints", "blank", "engine"), ("dynamics",), ("design",), ("studies",), ("report",), ("cases",),
          ("cli", "__init__")]
RANK = {name: rank for rank, names in enumerate(LAYERS) for name in names}


def _unit(module: str) -> str:
    """The layer unit of a dotted module name: the subpackage or top-level module under ``gearopt``."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "__init__"


def _imports(package: pathlib.Path = PACKAGE) -> list[tuple[str, str, str, int]]:
    """(importing unit, imported unit, file, line) for every gearopt import in the package, nested ones included."""
    rows = []
    for path in sorted(package.rglob("*.py")):
        rel = path.relative_to(package.parent).with_suffix("")
        module = ".".join(rel.parts)
        parent = module[: -len(".__init__")] if module.endswith(".__init__") else module.rsplit(".", 1)[0]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = parent.split(".")[: len(parent.split(".")) - (node.level - 1)]
                    target = ".".join(base + ([node.module] if node.module else []))
                else:
                    target = node.module or ""
                targets = [target] if node.module else [f"{target}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                continue
            for t in targets:
                if t == "gearopt" or t.startswith("gearopt."):
                    rows.append((_unit(module), _unit(t) if t != "gearopt" else "__init__",
                                 str(path.relative_to(package.parent)), node.lineno))
    return rows


def test_every_subpackage_has_a_layer():
    units = {p.stem if p.is_file() else p.name for p in PACKAGE.iterdir()
             if (p.is_dir() and (p / "__init__.py").exists()) or p.suffix == ".py"}
    assert units - set(RANK) == set(), "add new subpackages to LAYERS here and to docs/architecture.md"


def test_imports_point_down_only():
    rows = _imports()
    assert len(rows) > 100  # the parse sees the package's imports
    bad = [f"{file}:{line}: {a} imports {b}" for a, b, file, line in rows
           if a != b and RANK[b] >= RANK[a]]
    assert bad == [], "imports against the layer order:\n" + "\n".join(bad)


def test_nlp_framework_imports_nothing_of_gears():
    allowed = {"nlp", "numerics", "errors", "units"}
    bad = [f"{file}:{line}: imports gearopt.{b}" for a, b, file, line in _imports() if a == "nlp" and b not in allowed]
    assert bad == []


def test_the_layer_check_sees_late_and_absolute_imports(tmp_path):
    # a model importing the design layer inside a function is still a violation, in relative or absolute form
    model = tmp_path / "gearopt" / "contact"
    model.mkdir(parents=True)
    (tmp_path / "gearopt" / "__init__.py").write_text("")
    (model / "__init__.py").write_text("")
    (model / "late.py").write_text("def f():\n    from ..design import Scene\n    import gearopt.studies.x\n")
    rows = _imports(tmp_path / "gearopt")
    assert {(a, b) for a, b, _, _ in rows} == {("contact", "design"), ("contact", "studies")}
    assert all(RANK[b] > RANK[a] for a, b, _, _ in rows)
