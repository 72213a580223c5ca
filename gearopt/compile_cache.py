"""Compile once: CasADi functions JIT-compiled with the system C compiler and kept on disk across runs.

A heavy kernel (an integrator, its output functions) is compiled the first time; its shared library stays in the
cache and the function is saved linking to it (CasADi ``jit_serialize="link"``); later runs, tests and worker
processes load it (milliseconds, no compiler process) instead of generating and compiling the C code again.

Key: SHA-256 of the CasADi version, the platform, the compiler flags, the function's name and the caller's
``definition`` -- the serialized symbolic graph (``casadi.Function.serialize``) plus every option that shapes the
generated code. The graph fixes the generated C source, so a changed model, option or flag gets a new entry; an
unchanged one is never compiled twice. A cache file that does not load (truncated, other CasADi build) is rebuilt
transparently. Writes go to a temporary file renamed into place, so concurrent processes never read a half-written
entry (two cold processes may both compile; the last rename wins, both entries are equal).

Where: ``$GEAROPT_CACHE_DIR`` if set, else ``$XDG_CACHE_HOME/gearopt/compiled`` (default ``~/.cache``); at most
``$GEAROPT_CACHE_MAX_MB`` megabytes (default 1000), the least recently used entries pruned after a compilation.
``GEAROPT_JIT=0`` turns compilation off (interpreted functions; cached entries are still not used, so the
interpreted path can be measured). Without a C compiler (``gcc``, what CasADi's ``shell`` compiler calls) and
without a cached entry, the function is built interpreted and one notice is logged per process.

Optimisation level: ``JIT_FLAGS`` (``-O1``), picked by measurement (``benchmarks/bench_compile.py``: compile time
and run time of the default train's lash integrator at -O0..-O3).
"""

from __future__ import annotations

import contextlib
import hashlib
import logging
import os
import platform
import shutil
import tempfile
import time
from pathlib import Path
from typing import Callable

import casadi as ca

LOG = logging.getLogger("gearopt.compile")

JIT_FLAGS: tuple[str, ...] = ("-O1",)
"""Compiler flags of every cached kernel (``benchmarks/bench_compile.py`` measures the alternatives)."""

_FORMAT = "gearopt-compile-cache-2"  # bump when jit_options() changes what a saved entry does on load
_RESERVED = "gearopt_jit_src"  # CasADi reserves "<name><suffix>.c" in the working directory when it loads an entry
DEFAULT_MAX_MB = 1000.0
_STATS = {"hits": 0, "compiled": 0, "interpreted": 0, "load_time_s": 0.0, "compile_time_s": 0.0}
_NOTICE_GIVEN = False


def cache_dir() -> Path:
    """The directory of compiled entries (module docstring), created on demand."""
    env = os.environ.get("GEAROPT_CACHE_DIR")
    if env:
        path = Path(env).expanduser()
    else:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        path = Path(base) / "gearopt" / "compiled"
    path.mkdir(parents=True, exist_ok=True)
    return path


def compiler_available() -> bool:
    """True if CasADi's ``shell`` compiler can run (``gcc`` on the PATH)."""
    return shutil.which("gcc") is not None


def jit_enabled() -> bool:
    """False when ``GEAROPT_JIT`` is ``0``/``false``/``no`` (module docstring)."""
    return os.environ.get("GEAROPT_JIT", "1").strip().lower() not in ("0", "false", "no", "off")


def auto_jit(jit: bool | None) -> bool:
    """``jit=None``: compile (through the cache) unless ``GEAROPT_JIT=0``; without a C compiler the cache falls
    back to the interpreted functions with a notice."""
    if jit is None:
        return jit_enabled()
    return bool(jit)


def cache_stats() -> dict:
    """Counters of this process: ``hits`` (loaded), ``compiled``, ``interpreted`` (fallbacks), load and compile
    times [s]."""
    return dict(_STATS)


def cache_key(name: str, definition: bytes | str, flags=JIT_FLAGS) -> str:
    """Hex SHA-256 of the entry (module docstring)."""
    h = hashlib.sha256()
    for part in (_FORMAT, ca.__version__, platform.machine(), platform.system(), " ".join(flags), name):
        h.update(part.encode())
        h.update(b"\0")
    h.update(definition.encode() if isinstance(definition, str) else definition)
    return h.hexdigest()


def jit_options(directory: Path, flags=JIT_FLAGS) -> dict:
    """CasADi options that JIT-compile a function with ``flags`` in ``directory``, its library kept there and linked
    (not embedded) when the function is saved: loading then opens it in place, without a compiler or a temporary
    copy. CasADi's own clean-up is off (:func:`compiled` removes the C source and object files)."""
    return {"jit": True, "compiler": "shell", "jit_serialize": "link", "jit_cleanup": False, "jit_name": _RESERVED,
            "jit_options": {"flags": list(flags), "verbose": False, "cleanup": False,
                            "directory": str(directory) + os.sep}}


@contextlib.contextmanager
def stray_sources_removed():
    """Context: C sources CasADi writes to the working directory under this module's reserved JIT name while
    building or loading (it ignores the JIT directory for them) are removed on exit."""
    before = set(Path.cwd().glob(_RESERVED + "*.c"))
    try:
        yield
    finally:
        for junk in set(Path.cwd().glob(_RESERVED + "*.c")) - before:
            junk.unlink(missing_ok=True)


def compiled(name: str, definition: bytes | str, build: Callable[[dict], ca.Function], *,
             flags=JIT_FLAGS) -> tuple[ca.Function, str]:
    """The compiled ``casadi.Function`` of ``definition``: loaded from the cache, else built and stored.

    ``build(options)`` returns the Function built with the extra CasADi ``options`` (the JIT options of
    :func:`jit_options`, or ``{}`` for the interpreted fallback). Returns ``(function, how)`` with ``how`` one of
    ``"cached"``, ``"compiled"``, ``"interpreted"``.
    """
    global _NOTICE_GIVEN
    if not jit_enabled():
        _STATS["interpreted"] += 1
        return build({}), "interpreted"
    key = cache_key(name, definition, flags)
    root = cache_dir()
    path = root / f"{name}-{key[:24]}.casadi"
    library = root / f"{name}-{key[:24]}.lib"
    if path.exists() and any(f.suffix in (".so", ".dylib", ".dll") for f in library.rglob("*")):
        t0 = time.perf_counter()
        try:
            with stray_sources_removed():  # the (empty) source name a load reserves
                fun = ca.Function.load(str(path))
        except Exception as exc:  # noqa: BLE001 -- a damaged entry is rebuilt, never fatal
            LOG.info("compile cache: entry %s did not load (%s); rebuilding", path.name, exc)
        else:
            for junk in library.rglob("*.c"):
                if junk.stat().st_size == 0:
                    junk.unlink(missing_ok=True)
            _STATS["hits"] += 1
            _STATS["load_time_s"] += time.perf_counter() - t0
            try:
                os.utime(path)  # last use, for the pruning of the least recently used entries
            except OSError:
                pass
            return fun, "cached"
    if not compiler_available():
        if not _NOTICE_GIVEN:
            LOG.warning("gearopt: no C compiler (gcc) found: CasADi kernels run interpreted (slower, same results)")
            _NOTICE_GIVEN = True
        _STATS["interpreted"] += 1
        return build({}), "interpreted"
    t0 = time.perf_counter()
    library.mkdir(exist_ok=True)
    entry_dir = Path(tempfile.mkdtemp(dir=library))  # own directory per build (concurrent cold processes)
    fd, partial = tempfile.mkstemp(prefix=path.name + ".", suffix=".partial", dir=root)
    os.close(fd)
    try:
        with stray_sources_removed():
            fun = build(jit_options(entry_dir, flags))
            fun.save(partial)
        os.replace(partial, path)
    except RuntimeError as exc:  # the compiler or the file system failed: run interpreted, say so once
        LOG.warning("gearopt: compiling %s failed (%s); it runs interpreted", name, str(exc).splitlines()[-1][:200])
        _STATS["interpreted"] += 1
        return build({}), "interpreted"
    finally:
        if os.path.exists(partial):
            os.remove(partial)
        for junk in list(entry_dir.glob("*.c")) + list(entry_dir.glob("*.o")):
            junk.unlink(missing_ok=True)
    _STATS["compiled"] += 1
    _STATS["compile_time_s"] += time.perf_counter() - t0
    prune(root)
    return fun, "compiled"


def prune(root: Path | None = None, max_mb: float | None = None) -> list[str]:
    """Remove the least recently used entries until the cache holds at most ``max_mb`` megabytes (default
    ``$GEAROPT_CACHE_MAX_MB`` or 1000); run after every compilation. Returns the names of the removed entries."""
    root = cache_dir() if root is None else root
    if max_mb is None:
        max_mb = float(os.environ.get("GEAROPT_CACHE_MAX_MB", DEFAULT_MAX_MB))
    entries = []
    for path in root.glob("*.casadi"):
        library = path.with_suffix(".lib")
        try:
            size = path.stat().st_size + sum(f.stat().st_size for f in library.rglob("*") if f.is_file())
            entries.append((path.stat().st_mtime, size, path, library))
        except OSError:
            continue
    total = sum(e[1] for e in entries)
    removed = []
    for _, size, path, library in sorted(entries):
        if total <= max_mb * 1e6:
            break
        path.unlink(missing_ok=True)
        shutil.rmtree(library, ignore_errors=True)
        total -= size
        removed.append(path.stem)
    return removed


__all__ = ["JIT_FLAGS", "cache_dir", "cache_key", "cache_stats", "compiled", "compiler_available", "jit_enabled",
           "jit_options", "prune"]
