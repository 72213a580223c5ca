"""The public surface: ``gearopt.__all__`` is a short list of the names most studies need, and every public object
has one documented import path -- ``gearopt.X`` for the names of ``gearopt.__all__``, ``gearopt.<unit>.X`` for the
rest, where ``<unit>`` is a subpackage or a public top-level module listing X in its ``__all__``. No object is
listed by two ``__all__`` lists (a facade name is not listed again by its subpackage, and a subpackage does not list
another's names); the modules inside a subpackage are its implementation (``docs/architecture.md``)."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import gearopt

PRIVATE_TOP_LEVEL = {"cli"}          # the `gearopt` command, not an import surface


def _public_units() -> list[str]:
    """The facade, every subpackage and every public top-level module of gearopt."""
    units = ["gearopt"]
    for info in pkgutil.iter_modules(gearopt.__path__):
        if not info.name.startswith("_") and info.name not in PRIVATE_TOP_LEVEL:
            units.append(f"gearopt.{info.name}")
    return units


def _subpackages() -> list[str]:
    return [f"gearopt.{i.name}" for i in pkgutil.iter_modules(gearopt.__path__) if i.ispkg]


def test_facade_lists_a_short_surface_and_every_name_resolves():
    names = gearopt.__all__
    assert 20 <= len(names) <= 35, f"gearopt.__all__ has {len(names)} names: keep the facade to the core names"
    assert len(set(names)) == len(names), "a name listed twice in gearopt.__all__"
    missing = [n for n in names if not hasattr(gearopt, n)]
    assert missing == []


def test_facade_imports_nothing_it_does_not_list():
    # submodules (gearopt.cli, gearopt.numerics, ...) become attributes when anything imports them: not names
    public = {n for n, obj in vars(gearopt).items() if not n.startswith("_") and not inspect.ismodule(obj)}
    extra = sorted(public - set(gearopt.__all__))
    assert extra == [], f"gearopt imports names it does not list in __all__: {extra}"


def test_every_subpackage_lists_its_public_names_and_they_resolve():
    for unit in _subpackages():
        module = importlib.import_module(unit)
        assert hasattr(module, "__all__"), f"{unit} has no __all__"
        missing = [n for n in module.__all__ if not hasattr(module, n)]
        assert missing == [], f"{unit}.__all__ lists names it does not have: {missing}"


def test_every_class_and_function_a_subpackage_imports_is_listed_once():
    # a subpackage's own class or function in its namespace is listed by its __all__ or, for a core name, by the
    # facade's: none is reachable there without a documented path
    for unit in _subpackages():
        module = importlib.import_module(unit)
        unlisted = [n for n, obj in vars(module).items()
                    if not n.startswith("_") and (inspect.isclass(obj) or inspect.isfunction(obj))
                    and (obj.__module__ == unit or obj.__module__.startswith(unit + "."))
                    and n not in module.__all__ and getattr(gearopt, n, None) is not obj]
        assert unlisted == [], f"{unit} imports {unlisted} without listing them (its __all__ or gearopt.__all__)"


def test_no_object_is_listed_under_two_paths():
    listed: dict[int, list[str]] = {}
    for unit in _public_units():
        module = importlib.import_module(unit)
        for name in getattr(module, "__all__", ()):
            obj = getattr(module, name)
            if isinstance(obj, (bool, int, float, str, bytes, type(None))):
                continue                    # interned values: equal constants are not the same object
            listed.setdefault(id(obj), []).append(f"{unit}.{name}")
    twice = sorted(paths for paths in listed.values() if len(paths) > 1)
    assert twice == [], "objects listed by more than one __all__ (keep the one documented path):\n" + "\n".join(
        ", ".join(p) for p in twice)


def test_star_import_gives_exactly_all():
    namespace: dict = {}
    exec("from gearopt import *", namespace)
    assert sorted(set(namespace) - {"__builtins__"}) == sorted(gearopt.__all__)
