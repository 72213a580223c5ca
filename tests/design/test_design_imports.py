"""The design package's modules import each other without a cycle, and none hides one behind an import inside a
function: the graph of intra-package imports (module level and nested, relative and absolute, parsed as
tests/test_architecture.py does) is acyclic, and every gearopt import of the package is at module level."""

from __future__ import annotations

import ast
import pathlib

import gearopt.design

DESIGN = pathlib.Path(gearopt.design.__file__).parent
ROOT = DESIGN.parent.parent          # the directory holding the gearopt package


def _module_name(path: pathlib.Path, root: pathlib.Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(package: pathlib.Path, root: pathlib.Path):
    """(importing module, imported target, line, nested) for every import in ``package``; ``nested``: inside a
    function or class body (not at module level)."""
    rows = []
    for path in sorted(package.rglob("*.py")):
        module = _module_name(path, root)
        is_package = path.name == "__init__.py"
        tree = ast.parse(path.read_text(encoding="utf-8"))
        top = {id(n) for n in tree.body}
        top |= {id(n) for stmt in tree.body if isinstance(stmt, (ast.If, ast.Try))
                for n in ast.walk(stmt) if isinstance(n, (ast.Import, ast.ImportFrom))}
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                if node.level:
                    base = module.split(".") if is_package else module.split(".")[:-1]
                    base = base[: len(base) - (node.level - 1)]
                    stem = ".".join(base + ([node.module] if node.module else []))
                else:
                    stem = node.module or ""
                targets = [f"{stem}.{a.name}" for a in node.names] + [stem]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                continue
            for t in targets:
                rows.append((module, t, node.lineno, id(node) not in top))
    return rows


def _graph(package: pathlib.Path, root: pathlib.Path) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (``from .x import name`` counts ``x``, and ``name`` when it is a
    module of its own)."""
    modules = {_module_name(p, root) for p in package.rglob("*.py")}
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for module, target, _, _ in _imports(package, root):
        if target in modules and target != module:
            graph[module].add(target)
    return graph


def _cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``graph`` (its modules in order, the first repeated at the end), or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt):] + [nxt]
            if nxt not in state:
                found = visit(nxt)
                if found:
                    return found
        stack.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            found = visit(node)
            if found:
                return found
    return None


def test_the_design_package_has_no_import_cycle():
    graph = _graph(DESIGN, ROOT)
    assert "gearopt.design.scene" in graph and "gearopt.design.scene_contact" in graph["gearopt.design.scene"]
    assert _cycle(graph) is None, " -> ".join(_cycle(graph))


def test_no_gearopt_import_inside_a_function_of_the_design_package_without_a_stated_reason():
    # a deferred import is how a cycle hides: none of the design package's own modules is imported late, and a late
    # import of another gearopt module states why on its line ("# imported here: <reason>", e.g. to keep
    # `import gearopt` light); the cycle check above counts nested imports anyway
    lines = {_module_name(p, ROOT): p.read_text(encoding="utf-8").splitlines() for p in DESIGN.rglob("*.py")}
    nested = [(m, t, line) for m, t, line, inner in _imports(DESIGN, ROOT)
              if inner and (t == "gearopt" or t.startswith("gearopt."))]
    own = [f"{m}:{line}: {t}" for m, t, line in nested if t == "gearopt.design" or t.startswith("gearopt.design.")]
    assert own == []
    unexplained = sorted({f"{m}:{line}" for m, t, line in nested if "# imported here:" not in lines[m][line - 1]})
    assert unexplained == []


def test_the_checks_see_nested_relative_cycles(tmp_path):
    pkg = tmp_path / "gearopt" / "design"
    (pkg / "sub").mkdir(parents=True)
    (tmp_path / "gearopt" / "__init__.py").write_text("")
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from .b import f\n")
    (pkg / "b.py").write_text("def f():\n    from .sub import g\n")
    (pkg / "sub" / "__init__.py").write_text("from .c import g\n")
    (pkg / "sub" / "c.py").write_text("def g():\n    from gearopt.design.a import f\n")
    graph = _graph(pkg, tmp_path)
    assert _cycle(graph) == ["gearopt.design.a", "gearopt.design.b", "gearopt.design.sub", "gearopt.design.sub.c",
                             "gearopt.design.a"]
    nested = {(m, t) for m, t, _, inner in _imports(pkg, tmp_path) if inner and t.startswith("gearopt.")}
    assert {("gearopt.design.b", "gearopt.design.sub"), ("gearopt.design.sub.c", "gearopt.design.a")} <= nested
