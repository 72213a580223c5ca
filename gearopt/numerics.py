"""Dual-typed numerical primitives: the single CasADi expression boundary of gearopt.

Every function here accepts Python floats, numpy arrays or CasADi ``SX``/``MX``/``DM`` and returns the same kind:
numeric in -> numpy/float out, symbolic in -> CasADi expression out. Models use only these helpers (never
``casadi.*`` directly), so one model function serves numeric evaluation and Ipopt NLPs alike.

Smooth approximations carry a ``width`` in the physical units of their argument, are overflow-free for any argument,
and converge to the exact function as ``width -> 0``:

* ``softplus(x, w) = max(x, 0) + w*log1p(exp(-|x|/w))`` -- error at most ``w*ln 2`` (at ``x = 0``).
* ``smooth_max(a, b, w) = b + softplus(a - b, w)``, ``smooth_min`` likewise; same error bound.
* ``smooth_abs(x, w) = |x| + w*log1p(exp(-2|x|/w))`` (= ``w*log(2*cosh(x/w))``) -- error at most ``w*ln 2``.

Prefer exact epigraph formulations in NLPs (``t >= g_i``) where Ipopt can own the non-smoothness.

Solver threads: CasADi loads its own OpenBLAS (for Ipopt's MUMPS and its LAPACK plugins) with the first solver that
needs it. Its worker threads spin between the many small factorisations of an NLP wherever a core is free for them:
the packaged train's co-design stage alone in one process took 79-97 CPU-s with them and 72-77 with one thread, in
about the same wall time. Importing this module therefore sets ``OPENBLAS_NUM_THREADS=1`` for the libraries loaded
from then on (CasADi's BLAS, and the processes this one starts) unless the variable is already set: set it before
importing gearopt to choose otherwise (:data:`BLAS_THREADS_VARIABLE`).
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
import warnings
from collections import OrderedDict

import casadi as ca
import numpy as np

from .errors import GearoptInputError

#: Environment variable of the BLAS threads of the libraries loaded after gearopt (module docstring).
BLAS_THREADS_VARIABLE = "OPENBLAS_NUM_THREADS"
os.environ.setdefault(BLAS_THREADS_VARIABLE, "1")

_CASADI_TYPES = (ca.SX, ca.MX, ca.DM)
_SYMBOLIC_TYPES = (ca.SX, ca.MX)


# ----------------------------------------------------------------------------------------------------------------
# type handling
# ----------------------------------------------------------------------------------------------------------------

def is_casadi(*xs) -> bool:
    """True if any argument is a CasADi ``SX``, ``MX`` or ``DM``."""
    return any(isinstance(x, _CASADI_TYPES) for x in xs)


def is_symbolic(*xs) -> bool:
    """True if any argument is a CasADi ``SX`` or ``MX`` with free symbols (a ``DM`` or constant is numeric)."""
    for x in xs:
        if isinstance(x, _SYMBOLIC_TYPES) and not x.is_constant():
            return True
    return False


def depends_on(expr, symbols) -> bool:
    """True if the CasADi expression ``expr`` depends on any of ``symbols`` (e.g. an NLP's decision variables;
    a number depends on nothing)."""
    if not is_casadi(expr):
        return False
    return bool(ca.depends_on(ca.vec(expr), ca.vec(symbols)))


def is_numeric(*xs) -> bool:
    """True if every argument can be evaluated to a number now (floats, arrays, ``DM``, constant expressions)."""
    return not is_symbolic(*xs)


def to_float(x) -> float:
    """Convert a numeric scalar (float, 0-d/1-element array, DM, constant SX/MX) to ``float``."""
    if type(x) is float or type(x) is np.float64:      # the common case, called ~40 times per exact LTCA
        return float(x)
    if isinstance(x, _SYMBOLIC_TYPES):
        x = ca.DM(ca.evalf(x))
    if isinstance(x, ca.DM):
        return float(x.full().reshape(-1)[0]) if x.numel() == 1 else _raise_not_scalar(x)
    arr = np.asarray(x, dtype=float)
    if arr.size != 1:
        _raise_not_scalar(x)
    return float(arr.reshape(-1)[0])


def _raise_not_scalar(x):
    raise GearoptInputError(f"expected a scalar, got shape {np.shape(x)}")


def value(x):
    """Numeric value of ``x`` as float or ndarray; raises if ``x`` holds free symbols."""
    if isinstance(x, _SYMBOLIC_TYPES):
        if not x.is_constant() and is_symbolic(x):
            raise GearoptInputError("value() of an expression with free symbols; substitute numbers first")
        x = ca.DM(ca.evalf(x))
    if isinstance(x, ca.DM):
        a = x.full()
        return float(a.reshape(-1)[0]) if a.size == 1 else a.squeeze()
    if isinstance(x, np.ndarray):
        return x.astype(float) if x.ndim else float(x)
    return float(x)


def _dual(np_fun, ca_fun):
    def f(x):
        return ca_fun(x) if isinstance(x, _CASADI_TYPES) else np_fun(x)
    return f


# ----------------------------------------------------------------------------------------------------------------
# elementary functions (dual-typed)
# ----------------------------------------------------------------------------------------------------------------

sin = _dual(np.sin, ca.sin)
cos = _dual(np.cos, ca.cos)
tan = _dual(np.tan, ca.tan)
asin = _dual(np.arcsin, ca.asin)
atan = _dual(np.arctan, ca.atan)
tanh = _dual(np.tanh, ca.tanh)
exp = _dual(np.exp, ca.exp)
log = _dual(np.log, ca.log)
log1p = _dual(np.log1p, ca.log1p)
fabs = _dual(np.abs, ca.fabs)
sign = _dual(np.sign, ca.sign)
floor = _dual(np.floor, ca.floor)


def sqrt(x):
    """Square root (unguarded: use :func:`sqrt_safe` where the argument may reach zero or below)."""
    return ca.sqrt(x) if isinstance(x, _CASADI_TYPES) else np.sqrt(x)


def acos(x):
    """Arc cosine (unguarded: use :func:`acos_safe` where rounding may push the argument past +-1)."""
    return ca.acos(x) if isinstance(x, _CASADI_TYPES) else np.arccos(x)


def atan2(y, x):
    return ca.atan2(y, x) if is_casadi(y, x) else np.arctan2(y, x)


def fmax(a, b):
    """Exact maximum (non-smooth)."""
    return ca.fmax(a, b) if is_casadi(a, b) else np.maximum(a, b)


def fmin(a, b):
    """Exact minimum (non-smooth)."""
    return ca.fmin(a, b) if is_casadi(a, b) else np.minimum(a, b)


def clip(x, low, high):
    """Clamp ``x`` to ``[low, high]`` (non-smooth at the bounds)."""
    return fmin(fmax(x, low), high)


def where(condition, if_true, if_false):
    """Element-wise ``if_true if condition else if_false``.

    Both branches are evaluated: never put a branch that can produce NaN/Inf here (guard its argument instead),
    since a NaN in the unused branch poisons CasADi derivatives.
    """
    if is_casadi(condition, if_true, if_false):
        return ca.if_else(condition, if_true, if_false)
    return np.where(condition, if_true, if_false)


def vertcat(*xs):
    """Stack scalars/columns vertically: CasADi ``vertcat`` if any is CasADi, else a 1-D numpy array."""
    if is_casadi(*xs):
        return ca.vertcat(*xs)
    return np.concatenate([np.atleast_1d(np.asarray(x, dtype=float)).reshape(-1) for x in xs])


def sum1(xs):
    """Sum of a sequence of dual-typed scalars."""
    total = 0
    for x in xs:
        total = total + x
    return total


# ----------------------------------------------------------------------------------------------------------------
# smooth, overflow-free approximations with a physical width
# ----------------------------------------------------------------------------------------------------------------

def _check_width(width) -> None:
    if is_numeric(width):
        w = to_float(width)
        if not w > 0 or not math.isfinite(w):
            raise GearoptInputError(f"smoothing width={w!r} must be a finite number > 0 (same units as the argument)")


def softplus(x, width):
    """Smooth ``max(x, 0)`` with a width in the units of ``x``: ``max(x,0) + w*log1p(exp(-|x|/w))``.

    Overflow-free for any ``x``; ``softplus >= max(x, 0)``; error ``<= w*ln 2``, largest at ``x = 0``; converges
    uniformly to ``max(x, 0)`` as ``w -> 0``. Written as ``(x+|x|)/2`` so its derivative at ``x = 0`` is exactly 1/2
    in CasADi too.
    """
    _check_width(width)
    ax = fabs(x)
    return 0.5 * (x + ax) + width * log1p(exp(-ax / width))


def sigmoid(x, width):
    """Logistic step ``1/(1+exp(-x/w))`` (the derivative of :func:`softplus`), written ``(1 + tanh(x/(2w)))/2``:
    overflow-free and smooth everywhere (its CasADi derivative at ``x = 0`` is exactly ``1/(4w)``)."""
    _check_width(width)
    return 0.5 * (1.0 + tanh(0.5 * x / width))


def smooth_max(a, b, width):
    """Smooth ``max(a, b)``: ``b + softplus(a - b, w)``; upper bound of the exact max, error ``<= w*ln 2``."""
    return b + softplus(a - b, width)


def smooth_min(a, b, width):
    """Smooth ``min(a, b)``: ``a - softplus(a - b, w)``; lower bound of the exact min, error ``<= w*ln 2``."""
    return a - softplus(a - b, width)


def smooth_abs(x, width):
    """Smooth ``|x|`` = ``w*log(2*cosh(x/w))`` written overflow-free; error ``<= w*ln 2`` (at ``x = 0``)."""
    _check_width(width)
    ax = fabs(x)
    return ax + width * log1p(exp(-2.0 * ax / width))


# ----------------------------------------------------------------------------------------------------------------
# guarded functions (domain safety inside NLPs)
# ----------------------------------------------------------------------------------------------------------------

def sqrt_safe(x, floor_value: float = 0.0):
    """``sqrt(max(x, floor))``: never NaN. With a positive floor its derivative stays finite too."""
    return sqrt(fmax(x, floor_value))


def acos_safe(x, margin: float = 0.0):
    """``acos`` of ``x`` clipped to ``[-1+margin, 1-margin]``: never NaN."""
    return acos(clip(x, -1.0 + margin, 1.0 - margin))


# ----------------------------------------------------------------------------------------------------------------
# involute function and its inverse
# ----------------------------------------------------------------------------------------------------------------

# Taylor coefficients of tan(a) - a (odd powers 3..15); used below |a| < 0.1 where tan(a) - a cancels digits.
_INVOLUTE_SERIES = (1.0 / 3.0, 2.0 / 15.0, 17.0 / 315.0, 62.0 / 2835.0, 1382.0 / 155925.0, 21844.0 / 6081075.0,
                    929569.0 / 638512875.0)
_INVOLUTE_SERIES_LIMIT = 0.1


def involute(alpha_rad):
    """Involute function ``inv(alpha) = tan(alpha) - alpha`` [rad -> rad] (ISO 21771).

    Below 0.1 rad the Taylor series (to alpha^15, relative truncation error < 1e-15) replaces ``tan - alpha``,
    which would lose up to 10 digits to cancellation near the base circle.
    """
    a2 = alpha_rad * alpha_rad
    series = 0.0
    for coefficient in reversed(_INVOLUTE_SERIES):
        series = series * a2 + coefficient
    series = series * a2 * alpha_rad
    # |alpha| is clipped in the closed form so that the unused branch never evaluates tan near pi/2 spuriously
    return where(fabs(alpha_rad) < _INVOLUTE_SERIES_LIMIT, series, tan(alpha_rad) - alpha_rad)


#: Largest involute value handled by :func:`inverse_involute` (inv 75 deg ~= 2.42).
INVOLUTE_MAX = float(math.tan(math.radians(75.0)) - math.radians(75.0))

#: Newton steps unrolled in the symbolic inverse involute: the start below is within 5e-5 (relative) of the root
#: over 0..75 deg, so 2 quadratic steps already reach machine precision (benchmarks/bench_geometry.py); 3 for margin.
_SYMBOLIC_NEWTON_STEPS = 3


def _inverse_involute_start(y):
    """Starting point for Newton on ``inv(a) = y``: ``c / (1 + p1 c^2 + p2 c^4)^q`` with ``c = (3y)^(1/3)``.

    ``c`` is the leading term of the inverse series (``inv a = a^3/3 + ...``); ``p1, p2, q`` were fitted here by
    minimax over 0..75 deg, maximum relative error 4.8e-5 (tested).
    """
    c = (3.0 * y) ** (1.0 / 3.0)
    c2 = c * c
    return c / (1.0 + 0.45185793 * c2 + 0.07774932 * c2 * c2) ** 0.29418877


def inverse_involute(inv_value):
    """Pressure angle [rad] whose involute is ``inv_value`` [rad]: solves ``tan(a) - a = inv_value``.

    Numeric input: vectorised Newton iteration until the step is below 1e-12 relative (the error after that step is
    at rounding level, |a - a*| below 1e-14 rad, tested), for
    ``0 <= inv_value <= INVOLUTE_MAX`` (angles up to 75 deg); out-of-range input raises ``GearoptInputError``.
    Symbolic input: a fixed number of unrolled Newton steps from a starting point above the root, i.e. a smooth
    CasADi expression whose value and derivative (``1/tan^2 a``) match the numeric solution to machine precision.
    """
    if is_symbolic(inv_value):
        y = fmax(inv_value, 1e-300)
        a = _inverse_involute_start(y)
        for _ in range(_SYMBOLIC_NEWTON_STEPS):
            t = tan(a)
            a = a - (involute(a) - y) / (t * t)
        return a
    y = np.asarray(value(inv_value), dtype=float)
    if np.any(~np.isfinite(y)) or np.any(y < 0.0) or np.any(y > INVOLUTE_MAX):
        bad = y[(~np.isfinite(y)) | (y < 0.0) | (y > INVOLUTE_MAX)].reshape(-1)[0]
        raise GearoptInputError(
            f"inverse_involute: inv_value={bad!r} outside [0, {INVOLUTE_MAX:.4f}] (pressure angles 0..75 deg)")
    a = np.where(y > 0.0, _inverse_involute_start(np.maximum(y, 1e-300)), 0.0)
    for _ in range(8):  # quadratic convergence from a 5e-5 start: 2-3 steps; stop once a step is at rounding level
        t = np.tan(a)
        step = np.where(y > 0.0, (involute(a) - y) / np.maximum(t * t, 1e-300), 0.0)
        a = a - step
        if np.all(np.abs(step) <= 1e-12 * np.maximum(a, 1e-300)):
            break
    return float(a) if a.ndim == 0 else a


# ----------------------------------------------------------------------------------------------------------------
# kernels: symbols, columns, reshapes and implicit (root-finding) functions for models wrapped as casadi.Function
# ----------------------------------------------------------------------------------------------------------------

def column(values, like=None):
    """``values`` (any shape) flattened to a column: a CasADi ``DM`` column if ``like`` (or ``values``) is CasADi,
    else a 1-D numpy array. Used to combine numeric grids with symbolic parameters elementwise."""
    if isinstance(values, _CASADI_TYPES):
        return ca.vec(values)
    flat = np.asarray(values, dtype=float).reshape(-1)
    return ca.DM(flat) if is_casadi(like) else flat


def evaluate_stacked(evaluate, exprs) -> list[np.ndarray]:
    """The values of several expressions of the same symbols by ONE call of ``evaluate`` (``expr -> value``, e.g.
    :meth:`casadi.Opti.value` at a point or a solve result's ``value``), each flattened column-major to a 1-D array.
    One call builds one function over all of them, so a model the expressions share (an LTCA evaluation behind every
    limit of a mesh) is evaluated once instead of once per expression. Numbers pass through unevaluated."""
    exprs = list(exprs)
    out: list = [None] * len(exprs)
    symbolic = []
    for i, e in enumerate(exprs):
        if is_numeric(e):
            number = ca.DM(ca.evalf(e)) if isinstance(e, _SYMBOLIC_TYPES) else e
            out[i] = np.asarray(number.full() if isinstance(number, ca.DM) else number,
                                dtype=float).reshape(-1, order="F")
        else:
            symbolic.append(i)
    if symbolic:
        flat = [ca.vec(exprs[i]) for i in symbolic]
        values = np.atleast_1d(np.asarray(evaluate(ca.vertcat(*flat)), dtype=float)).reshape(-1, order="F")
        ends = np.cumsum([int(f.numel()) for f in flat])
        if values.size != ends[-1]:
            raise GearoptInputError(f"evaluate_stacked: the evaluation returned {values.size} values for "
                                    f"{ends[-1]} elements of {len(flat)} expressions")
        for i, part in zip(symbolic, np.split(values, ends[:-1])):
            out[i] = part
    return out


def reshape(x, rows: int, cols: int):
    """Column-major reshape (CasADi convention) for CasADi expressions and numpy arrays alike."""
    if isinstance(x, _CASADI_TYPES):
        return ca.reshape(x, rows, cols)
    return np.reshape(np.asarray(x), (rows, cols), order="F")


def symbol(name: str, rows: int = 1, cols: int = 1, kind: str = "SX"):
    """A CasADi symbol (``SX`` by default, ``MX`` with ``kind="MX"``)."""
    return (ca.MX if kind == "MX" else ca.SX).sym(name, rows, cols)


def function(name: str, inputs: list, outputs: list, input_names=None, output_names=None, cse: bool = True):
    """A ``casadi.Function`` of symbolic ``inputs`` -> ``outputs`` (common subexpressions eliminated for SX)."""
    opts = {"cse": True} if cse and all(isinstance(x, ca.SX) for x in inputs) else {}
    if input_names is not None:
        return ca.Function(name, inputs, outputs, list(input_names), list(output_names), opts)
    return ca.Function(name, inputs, outputs, opts)


def implicit_scalar_root(name: str, residual, n_params: int, *, abstol: float = 1e-10, max_iter: int = 200):
    """``casadi.Function`` ``(x0, p) -> x`` solving the scalar equation ``residual(x, p) = 0`` by Newton's method
    from ``x0`` (CasADi ``rootfinder``), with exact derivatives of ``x`` with respect to ``p`` by the implicit
    function theorem. ``residual`` is a Python callable built from these dual-typed helpers; it is traced once on
    ``SX`` symbols. A failed solve raises a ``RuntimeError`` at evaluation (``error_on_fail``).

    Newton converges monotonically when the residual is convex and increasing in ``x`` and ``x0`` lies right of
    the root (the caller's job to guarantee where it matters).
    """
    x = ca.SX.sym("x")
    p = ca.SX.sym("p", n_params)
    g = ca.Function(f"{name}_residual", [x, p], [residual(x, p)])
    return ca.rootfinder(name, "newton", g, {"abstol": abstol, "max_iter": max_iter, "error_on_fail": True})


# ----------------------------------------------------------------------------------------------------------------
# models traced once into SX kernels
# ----------------------------------------------------------------------------------------------------------------

#: Most kernels :func:`traced_call` keeps per process (least recently used dropped first).
TRACED_KERNELS_MAX = 256
_TRACED: "OrderedDict[tuple, tuple]" = OrderedDict()
_TRACED_STATS = {"traced": 0, "reused": 0, "direct": 0}


class _Untraceable(Exception):
    """An argument or result :func:`traced_call` cannot trace or key safely: the model is called directly."""


def _is_namedtuple(obj) -> bool:
    return isinstance(obj, tuple) and hasattr(obj, "_fields")


def _parts(obj):
    """``(parts, rebuild)`` of a container :func:`traced_call` looks into -- a dict's values, a list's or a (named)
    tuple's items, an object array's elements, a dataclass's fields -- with ``rebuild(new_parts)`` the same kind of
    container holding them (a dataclass through ``dataclasses.replace``, only where a part changed); None for
    anything else."""
    if isinstance(obj, dict):
        keys = list(obj)
        return [obj[k] for k in keys], lambda values: dict(zip(keys, values))
    if isinstance(obj, (list, tuple)):
        return list(obj), ((lambda values: type(obj)(*values)) if _is_namedtuple(obj)
                           else (lambda values: type(obj)(values)))
    if isinstance(obj, np.ndarray) and obj.dtype == object:
        def rebuild_array(values):
            out = np.empty(obj.shape, dtype=object)
            out.ravel()[:] = values
            return out
        return list(obj.ravel()), rebuild_array
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        fields = dataclasses.fields(obj)

        def rebuild_dataclass(values):
            changes = {}
            for f, v in zip(fields, values):
                if v is not getattr(obj, f.name):
                    if not f.init:        # derived in __post_init__: replace() cannot set it
                        raise _Untraceable(f"{type(obj).__name__}.{f.name}")
                    changes[f.name] = v
            return dataclasses.replace(obj, **changes) if changes else obj
        return [getattr(obj, f.name) for f in fields], rebuild_dataclass
    return None


def _map_leaves(obj, leaf):
    """``(copy, changed)``: ``obj`` with every CasADi ``SX``/``MX`` in it replaced by ``leaf(x)``, looking into the
    containers of :func:`_parts`; ``obj`` itself where nothing changed."""
    if isinstance(obj, _SYMBOLIC_TYPES):
        return leaf(obj), True
    parts = _parts(obj)
    if parts is None:
        return obj, False
    items = [_map_leaves(v, leaf) for v in parts[0]]
    if not any(changed for _, changed in items):
        return obj, False
    return parts[1]([v for v, _ in items]), True


def _leaves(obj, out: list) -> list:
    """The CasADi ``SX``/``MX`` values in ``obj`` (the containers of :func:`_parts`, in :func:`_map_leaves`'
    order)."""
    if isinstance(obj, _SYMBOLIC_TYPES):
        out.append(obj)
    else:
        parts = _parts(obj)
        for v in (parts[0] if parts is not None else ()):
            _leaves(v, out)
    return out


def _skeleton_key(obj):
    """A hashable description of ``obj`` that fixes what a traced kernel computes: its numbers exactly, its CasADi
    ``SX``/``MX`` values by kind, shape and sparsity. Raises :class:`_Untraceable` for any other kind of object
    (its ``repr`` need not show all it holds)."""
    if isinstance(obj, _SYMBOLIC_TYPES):
        rows, cols = obj.sparsity().get_triplet()
        return ("symbolic", type(obj).__name__, obj.shape, tuple(rows), tuple(cols))
    if isinstance(obj, dict):
        return ("dict", tuple((_skeleton_key(k), _skeleton_key(v)) for k, v in obj.items()))
    if isinstance(obj, (list, tuple)):
        return (type(obj).__module__, type(obj).__qualname__, tuple(_skeleton_key(v) for v in obj))
    if isinstance(obj, np.ndarray):
        if obj.dtype == object:
            return ("objects", obj.shape, tuple(_skeleton_key(v) for v in obj.ravel()))
        return ("array", obj.dtype.str, obj.shape, obj.tobytes())
    if isinstance(obj, ca.DM):
        rows, cols = obj.sparsity().get_triplet()
        return ("DM", obj.shape, tuple(obj.nonzeros()), tuple(rows), tuple(cols))
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return (type(obj).__module__, type(obj).__qualname__,
                tuple((f.name, _skeleton_key(getattr(obj, f.name))) for f in dataclasses.fields(obj)))
    if obj is None or isinstance(obj, (bool, int, float, complex, str, bytes, np.generic)):
        return (type(obj).__name__, obj)
    raise _Untraceable(type(obj).__qualname__)


def _kernel_name(fn) -> str:
    """A valid CasADi function name for the kernel of ``fn`` (letters, digits, single underscores)."""
    name = re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9]", "_", getattr(fn, "__name__", "model"))).strip("_")
    return f"traced_{name or 'model'}"


def traced_call(fn, *args, **kwargs):
    """``fn(*args, **kwargs)`` for a dual-typed model ``fn`` whose arguments hold CasADi expressions, evaluated as
    one call of an ``SX`` kernel that is traced once per process and reused.

    The CasADi ``SX``/``MX`` values in the arguments (in dicts, lists, tuples, named tuples, object arrays and
    dataclass fields: a symbolic ``GearPair``) become the kernel's inputs: ``fn`` runs once on ``SX`` symbols in
    their place, the ``SX`` values of its result (the same containers) become the kernel's outputs, and every later
    call of the same ``fn`` object with arguments of the same numbers and the same kinds, shapes and sparsity of
    expressions is one call of that kernel on its own expressions. ``fn`` must be a model of its arguments alone (a
    pure function: what it reads besides them, e.g. a mutated closure, is frozen at the trace). Against building
    ``fn`` on ``MX`` directly: the same values and derivatives (an ``SX`` graph of the same operations), a graph of
    one call node instead of one node per operation (an NLP built on it evaluates, differentiates and expands
    faster), and a model built once per process instead of once per use. A result value that depends on no input
    comes back a number (arrays a fresh copy per call); the warnings ``fn`` raised while traced are raised again at
    every call (a caller that records them sees them each time). ``fn`` is called directly instead where there is
    nothing to trace (arguments without CasADi values), where ``SX`` and ``MX`` are mixed, where an argument is of
    another kind than numbers, strings, arrays, ``DM``, containers and dataclasses (a key could not tell two of them
    apart), and where the trace cannot be taken (a CasADi value in a dataclass field set in ``__post_init__``, an
    ``MX`` made inside ``fn``). Keeps at most :data:`TRACED_KERNELS_MAX` kernels (``traced_kernel_stats``)."""
    collected = (args, kwargs)
    inputs = _leaves(collected, [])
    if not inputs or (any(isinstance(x, ca.SX) for x in inputs) and any(isinstance(x, ca.MX) for x in inputs)):
        return fn(*args, **kwargs)          # nothing to trace / a kernel takes one kind of expression
    try:
        key = (id(fn), _skeleton_key(collected))
    except _Untraceable:
        _TRACED_STATS["direct"] += 1
        return fn(*args, **kwargs)
    entry = _TRACED.get(key)
    if entry is None or entry[0] is not fn:         # the entry holds fn: its id is not reused while it is kept
        try:
            entry = _trace(fn, collected)
        except _Untraceable:
            _TRACED_STATS["direct"] += 1
            return fn(*args, **kwargs)
        _TRACED[key] = entry
        _TRACED_STATS["traced"] += 1
        while len(_TRACED) > TRACED_KERNELS_MAX:
            _TRACED.popitem(last=False)
    else:
        _TRACED.move_to_end(key)
        _TRACED_STATS["reused"] += 1
    _, kernel, skeleton, raised = entry
    for message, category, filename, lineno in raised:
        warnings.warn_explicit(message, category, filename, lineno)
    return _fill_slots(skeleton, kernel.call(inputs))


def _trace(fn, collected) -> tuple:
    """``(fn, kernel, result skeleton, warnings raised)`` of :func:`traced_call`: ``fn`` run on SX symbols in
    place of the CasADi values of ``collected`` (``(args, kwargs)``)."""
    symbols: list = []

    def symbol(x):
        symbols.append(ca.SX.sym(f"in{len(symbols)}", x.sparsity()))
        return symbols[-1]
    (args, kwargs), _ = _map_leaves(collected, symbol)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            result = fn(*args, **kwargs)
        except (TypeError, RuntimeError, NotImplementedError) as exc:   # e.g. an MX made inside fn meets SX
            raise _Untraceable(str(exc)) from exc
    outputs: list = []

    def output(x):
        if x.is_constant():
            return to_float(x) if x.numel() == 1 else np.array(ca.DM(x))
        if not isinstance(x, ca.SX):            # an MX of fn's own, not of the traced symbols
            raise _Untraceable("an MX value in the result")
        outputs.append(x)
        return _Slot(len(outputs) - 1)
    skeleton, _ = _map_leaves(result, output)
    kernel = ca.Function(_kernel_name(fn), symbols, outputs, {"cse": True})
    return fn, kernel, skeleton, [(w.message, w.category, w.filename, w.lineno) for w in caught]


class _Slot:
    """Place of a kernel output in a traced result's skeleton."""
    __slots__ = ("index",)

    def __init__(self, index: int):
        self.index = index


def _fill_slots(obj, values):
    """``obj`` with every :class:`_Slot` replaced by its value (the containers of :func:`_parts`; a numeric array
    copied, so that no two calls share one)."""
    if isinstance(obj, _Slot):
        return values[obj.index]
    if isinstance(obj, np.ndarray) and obj.dtype != object:
        return obj.copy()
    parts = _parts(obj)
    return obj if parts is None else parts[1]([_fill_slots(v, values) for v in parts[0]])


def traced_kernel_stats() -> dict:
    """Counts of :func:`traced_call` in this process: kernels traced, calls that reused one, calls made directly
    (arguments it cannot key or trace), and how many kernels it keeps."""
    return {**_TRACED_STATS, "kept": len(_TRACED)}



def column_max(x):
    """Maximum of every column of a matrix: a row (1 x cols) for CasADi, a 1-D array for numpy. Non-smooth; use it
    for initial guesses and bounds, not inside objectives."""
    if isinstance(x, _CASADI_TYPES):
        return ca.horzcat(*[ca.mmax(x[:, j]) for j in range(x.shape[1])])
    return np.max(np.asarray(x), axis=0)


def column_softmin(x, width):
    """Smooth minimum of every column of a matrix (a row for CasADi, a 1-D array for numpy):
    ``-width * log(sum(exp(-x / width)))``, at most ``width * ln(rows)`` below the true minimum and never above it.
    Evaluated shifted by the column minimum (no overflow); the shift cancels in value and derivative."""
    _check_width(width)
    if isinstance(x, _CASADI_TYPES):
        low = -column_max(-x)
        return low - width * ca.log(ca.sum1(ca.exp(-(x - repeat_rows(low, x.shape[0])) / width)))
    a = np.asarray(x, dtype=float)
    low = a.min(axis=0)
    return low - width * np.log(np.sum(np.exp(-(a - low) / width), axis=0))


def column_sum(x):
    """Sum of every column of a matrix: a row (1 x cols) for CasADi, a 1-D array for numpy."""
    if isinstance(x, _CASADI_TYPES):
        return ca.sum1(x)
    return np.sum(np.asarray(x), axis=0)


def matrix(x, like=None):
    """``x`` as a 2-D CasADi ``DM`` if ``like`` is CasADi (CasADi values pass through), else as a 2-D numpy array."""
    if isinstance(x, _CASADI_TYPES):
        return x
    a = np.asarray(x, dtype=float)
    a = a.reshape(-1, 1) if a.ndim < 2 else a
    return ca.DM(a) if is_casadi(like) else a


def hcat(blocks):
    """Concatenate matrices side by side (CasADi if any block is CasADi)."""
    if is_casadi(*blocks):
        return ca.horzcat(*[matrix(b, True) for b in blocks])
    return np.hstack([matrix(b) for b in blocks])


def vcat(blocks):
    """Stack matrices on top of each other (CasADi if any block is CasADi)."""
    if is_casadi(*blocks):
        return ca.vertcat(*[matrix(b, True) for b in blocks])
    return np.vstack([matrix(b) for b in blocks])


def matmul(a, b):
    """Matrix product, CasADi if either factor is CasADi."""
    if is_casadi(a, b):
        return ca.mtimes(matrix(a, True), matrix(b, True))
    return np.asarray(a) @ np.asarray(b)


def row(x):
    """``x`` (vector of any orientation) as a single row (1 x n)."""
    if isinstance(x, _CASADI_TYPES):
        return ca.reshape(x, 1, x.numel())
    return np.asarray(x, dtype=float).reshape(1, -1)


def repeat_rows(x_row, n: int):
    """A row repeated ``n`` times downwards (n x cols)."""
    if isinstance(x_row, _CASADI_TYPES):
        return ca.repmat(x_row, n, 1)
    return np.repeat(np.asarray(x_row).reshape(1, -1), n, axis=0)


__all__ = [
    "is_casadi", "depends_on", "is_symbolic", "is_numeric", "to_float", "value", "sin", "cos", "tan", "asin", "acos", "atan",
    "atan2", "tanh", "exp", "log", "log1p", "sqrt", "fabs", "sign", "floor", "fmax", "fmin", "clip", "where", "vertcat",
    "sum1", "softplus", "sigmoid", "smooth_max", "smooth_min", "smooth_abs", "sqrt_safe", "acos_safe", "involute",
    "inverse_involute", "INVOLUTE_MAX", "column", "evaluate_stacked", "reshape", "symbol", "function",
    "implicit_scalar_root", "traced_call", "traced_kernel_stats", "TRACED_KERNELS_MAX", "column_max", "column_softmin", "column_sum", "matrix", "hcat", "vcat", "matmul", "row",
    "repeat_rows", "BLAS_THREADS_VARIABLE",
]
