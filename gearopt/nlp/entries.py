"""Declaration records of a :class:`~gearopt.nlp.problem.Problem` and the checks on their inputs.

A record keeps what the user declared (name, bounds, scale, unit, the source line of the declaration) next to the
CasADi symbol or expression it produced, so that results and failures can be reported by name. Bounds are stored
as float arrays with ``-inf``/``+inf`` for a missing side; every array has one entry per scalar element.
"""

from __future__ import annotations

import warnings

import inspect
import os
from dataclasses import dataclass
from typing import Any, Union

import casadi as ca
import numpy as np

from gearopt.errors import GearoptInputError

ArrayLike = Union[float, int, np.ndarray, list, tuple]

_INTERNAL_DIRS: set[str] = {os.path.dirname(os.path.abspath(__file__))}


def register_internal_package(module_file: str) -> None:
    """Treat the package directory of ``module_file`` as library code: :func:`caller_source` skips its frames, so a
    constraint declared by a client library (a design layer built on this framework) points at *its* caller."""
    _INTERNAL_DIRS.add(os.path.dirname(os.path.abspath(module_file)))


@dataclass
class VariableEntry:
    """A named design variable. The decision variable Ipopt sees is ``symbol`` (scaled, O(1)); the user's
    expression is ``scale * symbol``. ``init``, ``lower``, ``upper`` are in the variable's own units."""

    name: str
    symbol: ca.MX
    size: int
    vector: bool
    init: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    scale: np.ndarray
    unit: str
    source: str
    bound_rows: np.ndarray | None
    """Rows of Opti's constraint vector holding the bound ``lower/scale <= symbol <= upper/scale`` (None if free)."""


@dataclass
class ParameterEntry:
    """A named parameter: fixed during a solve, changeable between solves without rebuilding the problem."""

    name: str
    symbol: ca.MX
    size: int
    vector: bool
    value: np.ndarray
    unit: str
    source: str


@dataclass
class ConstraintEntry:
    """A named constraint ``lower <= expr <= upper`` (elementwise, in the constraint's units). Ipopt sees
    ``(expr - ref) / scale`` with ``ref`` the lower bound where there is one, else the upper bound."""

    name: str
    expr: ca.MX
    size: int
    vector: bool
    lower: np.ndarray
    upper: np.ndarray
    scale: np.ndarray
    unit: str
    source: str
    rows: np.ndarray
    """Rows of Opti's constraint vector, one per element of :attr:`passed` (in that order)."""
    passed: np.ndarray
    """Indices of the elements handed to Ipopt: all, unless the constraint is screened."""
    screen: np.ndarray | None = None
    """Screened constraint (rows by exchange): an element whose margin to its bound exceeds this (constraint
    units, per element) at a start is held back from Ipopt until a solve breaks it or comes within it."""

    @property
    def ref(self) -> np.ndarray:
        """The bound subtracted from ``expr`` before scaling (constraint units)."""
        return np.where(np.isfinite(self.lower), self.lower, self.upper)

    def element_names(self) -> list[str]:
        """``name`` for a scalar constraint, ``name[i]`` for each element of a vector constraint."""
        return element_names(self.name, self.size, self.vector)


def element_names(name: str, size: int, vector: bool) -> list[str]:
    """Display names of the scalar elements of a named quantity: ``name`` or ``name[0]``, ``name[1]`` ..."""
    return [f"{name}[{i}]" for i in range(size)] if vector else [name]


def caller_source() -> str:
    """``file:line`` of the first stack frame outside this package and the registered client packages (the user's
    declaration).

    Paths below the current working directory are shown relative to it.
    """
    frame = inspect.currentframe()
    try:
        while frame is not None and os.path.dirname(os.path.abspath(frame.f_code.co_filename)) in _INTERNAL_DIRS:
            frame = frame.f_back
        if frame is None:
            return ""
        path = os.path.abspath(frame.f_code.co_filename)
        try:
            rel = os.path.relpath(path)
            path = path if rel.startswith("..") else rel
        except ValueError:  # other drive on Windows
            pass
        return f"{path}:{frame.f_lineno}"
    finally:
        del frame


def check_name(name: object, kind: str) -> str:
    """Return ``name`` if it is a non-empty string, else raise :class:`GearoptInputError`."""
    if not isinstance(name, str) or not name.strip():
        raise GearoptInputError(f"{kind} name={name!r} is invalid: must be a non-empty string")
    return name


#: Ipopt's default ``nlp_lower_bound_inf``/``nlp_upper_bound_inf``: bounds at or beyond it mean "no bound".
IPOPT_INFINITY = 1e19
#: Largest magnitude of initial guesses, parameter values and scales (as ``gearopt.validation.MAX_MAGNITUDE``).
MAX_MAGNITUDE = 1e15


def as_elements(value: ArrayLike, size: int, *, owner: str, what: str, unit: str = "",
                max_magnitude: float = MAX_MAGNITUDE) -> np.ndarray:
    """Broadcast a scalar or a length-``size`` array to a float array of shape ``(size,)``, all finite.

    Raises :class:`GearoptInputError` naming ``owner`` and ``what`` for a wrong length, a non-number (e.g. a CasADi
    expression where a number is required) or a NaN/Inf entry.
    """
    raw = value if isinstance(value, np.ndarray) else None
    if isinstance(value, (str, bytes, bool, np.bool_)) or value is None \
            or (raw is not None and raw.dtype.kind not in "iuf"):
        raise GearoptInputError(f"{owner}: {what}={value!r:.60} must be a number or an array of numbers "
                                f"(not a {type(value).__name__})")
    try:
        arr = np.asarray(value, dtype=float).ravel()
    except (TypeError, ValueError, RuntimeError, NotImplementedError) as exc:
        raise GearoptInputError(
            f"{owner}: {what}={value!r} must be a number or an array of numbers "
            f"(put parameters inside the expression, not in the bounds)") from exc
    if arr.size == 1:
        arr = np.full(size, arr[0])
    if arr.size != size:
        raise GearoptInputError(f"{owner}: {what} has {arr.size} entries; limit: 1 or {size} (the size)")
    bad = ~np.isfinite(arr)
    if bad.any():
        u = f" {unit}" if unit else ""
        advice = " (use None for a missing bound)" if what in ("lower", "upper") else ""
        raise GearoptInputError(
            f"{owner}: {what}={float(arr[bad][0])}{u} at element {int(np.flatnonzero(bad)[0])} is not finite; "
            f"limit: a finite number{advice}")
    big = np.abs(arr) > max_magnitude
    if big.any():
        u = f" {unit}" if unit else ""
        raise GearoptInputError(f"{owner}: {what}={float(arr[big][0]):g}{u} at element {int(np.flatnonzero(big)[0])} "
                                f"is beyond the plausible magnitude {max_magnitude:g}{u}")
    return arr


def as_bound(value: ArrayLike | None, size: int, *, owner: str, what: str, unit: str, missing: float) -> np.ndarray:
    """Like :func:`as_elements`, but ``None`` means no bound and gives an array filled with ``missing`` (±inf);
    finite bounds at or beyond Ipopt's infinity (:data:`IPOPT_INFINITY`) are treated as no bound, with a warning
    (Ipopt would otherwise take 1e200 as a real bound and its barrier terms would overflow)."""
    if value is None:
        return np.full(size, missing)
    arr = as_elements(value, size, owner=owner, what=what, unit=unit, max_magnitude=np.inf)
    beyond = np.abs(arr) >= IPOPT_INFINITY
    if beyond.any():
        warnings.warn(f"{owner}: {what} bound {float(arr[beyond][0]):g} is at or beyond Ipopt's infinity "
                      f"{IPOPT_INFINITY:g}: treated as no bound ({'-' if arr[beyond][0] < 0 else '+'}inf)",
                      UserWarning, stacklevel=3)
        arr = np.where(beyond, np.sign(arr) * np.inf, arr)
    return arr


def check_positive(arr: np.ndarray, *, owner: str, what: str) -> None:
    """Raise :class:`GearoptInputError` if any entry of ``arr`` is not a finite number > 0 (scales, tolerances)."""
    arr = np.atleast_1d(np.asarray(arr, dtype=float))
    bad = ~(np.isfinite(arr) & (arr > 0.0))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise GearoptInputError(f"{owner}: {what}={arr[i]:g} at element {i} is outside its limit: must be > 0 "
                                f"(and finite)")


def check_ordered(lower: np.ndarray, upper: np.ndarray, *, owner: str, unit: str) -> None:
    """Raise :class:`GearoptInputError` naming the first element where ``upper < lower`` (inverted bounds)."""
    bad = upper < lower
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        u = f" {unit}" if unit else ""
        where = f" at element {i}" if lower.size > 1 else ""
        raise GearoptInputError(
            f"{owner}: upper={upper[i]:g}{u} is below lower={lower[i]:g}{u}{where} (inverted bounds)")


def check_size(n: int | None, name: str) -> int:
    """Number of elements of a variable declared with ``n`` (None: a scalar, 1)."""
    if n is None:
        return 1
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise GearoptInputError(f"variable '{name}': n={n!r} is below its limit: must be an integer >= 1")
    return int(n)



def as_mx(expr: Any, owner: str, *, allow_constant: bool = False) -> ca.MX:
    """``expr`` as an MX; numbers only if ``allow_constant``. SX is refused (Opti works on MX)."""
    if isinstance(expr, ca.MX):
        return expr
    if isinstance(expr, ca.SX):
        raise GearoptInputError(f"{owner}: got an SX expression; build it from the problem's MX symbols or call "
                                f"an SX kernel through a casadi.Function")
    try:
        dm = ca.DM(expr)
    except (NotImplementedError, TypeError, RuntimeError) as exc:
        raise GearoptInputError(f"{owner}: {expr!r} is not a CasADi expression or a number") from exc
    if not allow_constant:
        raise GearoptInputError(f"{owner}: the expression is the constant {expr!r}; limit: it must depend on "
                                f"the problem's variables")
    return ca.MX(dm)


def element_rows(expr: ca.MX, elements: list[int]) -> ca.MX:
    """``expr[elements]`` of a column ``expr`` (``elements`` ascending), built from only the blocks that hold them
    where ``expr`` is a vertical concatenation of dense columns. A slice of a concatenation depends on every block:
    CasADi evaluates (and differentiates) them all, so a screened constraint whose elements come from independent
    models -- the LTCA of each relief variant -- would cost every model for the few rows passed to Ipopt."""
    if expr.op() != ca.OP_VERTCAT:
        return expr[elements]
    blocks = [expr.dep(i) for i in range(expr.n_dep())]
    if any(not b.is_dense() or b.size2() != 1 for b in blocks):
        return expr[elements]
    starts = np.cumsum([0] + [b.size1() for b in blocks])
    which = np.searchsorted(starts, elements, side="right") - 1
    parts = []
    for k in dict.fromkeys(which.tolist()):
        local = (np.asarray(elements)[which == k] - starts[k]).tolist()
        parts.append(blocks[k] if len(local) == blocks[k].size1() else blocks[k][local])
    return ca.vertcat(*parts)


def last_line(exc: BaseException | None) -> str:
    """The informative last line of a (multi-line) CasADi error message."""
    text = str(exc).strip() if exc is not None else ""
    return text.splitlines()[-1] if text else "unknown error"
