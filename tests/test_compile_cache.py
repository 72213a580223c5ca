"""The on-disk compile cache (gearopt.compile_cache): compile once, load after; damaged entries rebuilt; no compiler
or GEAROPT_JIT=0 -> interpreted with the same values."""

import logging
import os
import sys
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from gearopt import compile_cache

sys.path.insert(0, str(Path(__file__).parent / "dynamics"))


def _kernel(extra: dict) -> ca.Function:
    x = ca.SX.sym("x", 3)
    return ca.Function("kernel", [x], [ca.sin(x) * ca.exp(-x[0] * x[1]) + x[2] ** 3], extra)


def _definition() -> str:
    return _kernel({}).serialize()


@pytest.fixture
def cache(tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    tmp_path = tmp_path / "cache"
    monkeypatch.setenv("GEAROPT_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("GEAROPT_JIT", raising=False)
    return tmp_path


needs_compiler = pytest.mark.skipif(not compile_cache.compiler_available(), reason="no C compiler on this machine")


@needs_compiler
def test_compiled_once_then_loaded_with_equal_values(cache):
    x = np.array([0.3, -1.2, 0.7])
    ref = np.array(_kernel({})(x))
    first, how1 = compile_cache.compiled("kernel", _definition(), _kernel)
    entries = list(cache.glob("kernel-*.casadi"))
    second, how2 = compile_cache.compiled("kernel", _definition(), _kernel)
    assert (how1, how2) == ("compiled", "cached") and len(entries) == 1
    library = entries[0].with_suffix(".lib")
    assert sorted(p.name for p in cache.iterdir()) == sorted([entries[0].name, library.name])
    assert [p.suffix for p in library.rglob("*") if p.is_file()] == [".so"]  # no build leftovers
    assert list(Path.cwd().iterdir()) == []  # nor in the working directory
    np.testing.assert_allclose(np.array(first(x)), ref, rtol=1e-14)
    np.testing.assert_allclose(np.array(second(x)), ref, rtol=1e-14)
    # another definition or other flags: another entry
    _, how3 = compile_cache.compiled("kernel", _definition() + "other", _kernel)
    assert how3 == "compiled" and len(list(cache.glob("kernel-*.casadi"))) == 2
    assert compile_cache.cache_key("k", "d", ("-O1",)) != compile_cache.cache_key("k", "d", ("-O2",))


@needs_compiler
def test_damaged_entry_is_rebuilt(cache):
    compile_cache.compiled("kernel", _definition(), _kernel)
    entry = next(cache.glob("kernel-*.casadi"))
    entry.write_bytes(entry.read_bytes()[:1000])  # truncated
    fun, how = compile_cache.compiled("kernel", _definition(), _kernel)
    assert how == "compiled"
    np.testing.assert_allclose(np.array(fun([1.0, 2.0, 3.0])), np.array(_kernel({})([1.0, 2.0, 3.0])), rtol=1e-14)
    assert compile_cache.compiled("kernel", _definition(), _kernel)[1] == "cached"
    for lib in entry.with_suffix(".lib").rglob("*.so"):  # library deleted
        lib.unlink()
    assert compile_cache.compiled("kernel", _definition(), _kernel)[1] == "compiled"


def test_no_compiler_gives_interpreted_with_one_notice(cache, monkeypatch, caplog):
    monkeypatch.setattr(compile_cache, "compiler_available", lambda: False)
    monkeypatch.setattr(compile_cache, "_NOTICE_GIVEN", False)
    with caplog.at_level(logging.WARNING, logger="gearopt.compile"):
        a, how_a = compile_cache.compiled("kernel", _definition(), _kernel)
        b, how_b = compile_cache.compiled("kernel", _definition() + "2", _kernel)
    assert (how_a, how_b) == ("interpreted", "interpreted")
    notices = [r for r in caplog.records if "no C compiler" in r.getMessage()]
    assert len(notices) == 1 and "\n" not in notices[0].getMessage()
    np.testing.assert_allclose(np.array(a([0.1, 0.2, 0.3])), np.array(_kernel({})([0.1, 0.2, 0.3])), rtol=1e-15)
    assert list(cache.glob("*.casadi")) == []


def test_jit_off_by_environment(cache, monkeypatch):
    monkeypatch.setenv("GEAROPT_JIT", "0")
    assert compile_cache.compiled("kernel", _definition(), _kernel)[1] == "interpreted"
    assert list(cache.glob("*.casadi")) == []


@needs_compiler
def test_simulator_loads_its_kernels_from_the_cache(cache, monkeypatch):
    from dynamics_networks import forced_pair

    from gearopt.dynamics.simulate import Simulator

    net = forced_pair(ripple_Nm=50.0)
    first = Simulator(net, lash=True, jit=True, output_step_deg=5.0)
    path = os.environ["PATH"]
    monkeypatch.setenv("PATH", "")        # no compiler can start now: the second build must only load
    second = Simulator(net, lash=True, jit=True, output_step_deg=5.0)
    monkeypatch.setenv("PATH", path)
    interp = Simulator(net, lash=True, jit=False, output_step_deg=5.0)
    assert set(first.compiled.values()) == {"compiled"} and set(second.compiled.values()) == {"cached"}
    assert set(interp.compiled.values()) == {"interpreted"}
    runs = [s.run(1500.0, cycles=1) for s in (first, second, interp)]
    f = [r.mesh_force_N["g1-g2"].to_numpy() for r in runs]
    np.testing.assert_allclose(f[1], f[0], rtol=0, atol=1e-9 * np.max(np.abs(f[0])))
    np.testing.assert_allclose(f[2], f[0], rtol=0, atol=1e-6 * np.max(np.abs(f[0])))


@needs_compiler
def test_prune_removes_the_least_recently_used_entries(cache):
    compile_cache.compiled("kernel", _definition(), _kernel)
    compile_cache.compiled("kernel", _definition() + "b", _kernel)
    first, second = (next(cache.glob(f"kernel-{compile_cache.cache_key('kernel', d)[:24]}.casadi"))
                     for d in (_definition(), _definition() + "b"))
    os.utime(first, (1e9, 1e9))
    os.utime(second, (1e9 + 10, 1e9 + 10))
    compile_cache.compiled("kernel", _definition(), _kernel)   # a hit: the first entry is now the recent one

    def size(p):
        return p.stat().st_size + sum(f.stat().st_size for f in p.with_suffix(".lib").rglob("*") if f.is_file())

    assert compile_cache.prune(cache, max_mb=1.5 * max(size(first), size(second)) / 1e6) == [second.stem]
    assert first.exists() and not second.exists() and not second.with_suffix(".lib").exists()


@needs_compiler
def test_a_failing_compiler_falls_back_to_interpreted(cache, monkeypatch, caplog):
    def broken(options):
        if options:
            raise RuntimeError("compiler exploded\nshell: gcc: error")
        return _kernel(options)

    with caplog.at_level(logging.WARNING, logger="gearopt.compile"):
        fun, how = compile_cache.compiled("kernel", _definition(), broken)
    assert how == "interpreted" and any("compiling kernel failed" in r.getMessage() for r in caplog.records)
    np.testing.assert_allclose(np.array(fun([0.1, 0.2, 0.3])), np.array(_kernel({})([0.1, 0.2, 0.3])), rtol=1e-15)
    assert list(cache.glob("*.casadi")) == []
