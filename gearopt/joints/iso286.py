"""ISO 286 limits and fits: a small table for hole-basis interference fits (H holes with m..u shafts), 10-180 mm.

Only the sizes and fits a gear-on-shaft joint uses are held; anything else raises :class:`GearoptInputError`
naming the limit. Values in micrometres; nominal size ranges are "over low up to and including high" (ISO 286-1).

Sources (both read here):

* standard tolerance grades IT5..IT8 -- [V] BIG DAISHOWA tooling catalogue p. 139, "Shaft tolerances" h5..h8
  (catalog.bigdaishowa.com/view/510119233/139); an h shaft's tolerance is the IT value;
* fundamental (lower) deviations ei of shafts m, n, p, r, s, t, u -- [V] Machine Drawing, Table 15.2 "Fundamental
  deviations for shafts of types m to zc of sizes up to 500 mm" (issuhub.com/view/index/5590?pageIndex=239);
  for these letters ei is the same for all grades, and es = ei + IT.

An H hole has EI = 0, ES = +IT. A fit ``"H7/r6"`` then gives the diametral interference range
``[ei_shaft - ES_hole, es_shaft - EI_hole]`` (negative minimum = possible clearance).
"""

from __future__ import annotations

import re

from ..errors import GearoptInputError
from ..validation import check_range

#: Nominal size ranges (over, up to and including) [mm] of the IT table.
_IT_RANGES_MM = ((10.0, 18.0), (18.0, 30.0), (30.0, 50.0), (50.0, 80.0), (80.0, 120.0), (120.0, 180.0))
#: Standard tolerance grades [um] per range, IT5..IT8 ([V] BIG DAISHOWA p. 139, h5..h8 columns).
_IT_UM = {
    5: (8, 9, 11, 13, 15, 18),
    6: (11, 13, 16, 19, 22, 25),
    7: (18, 21, 25, 30, 35, 40),
    8: (27, 33, 39, 46, 54, 63),
}

#: Shaft fundamental deviation ranges [mm] (finer steps than the IT ranges where ISO 286 splits them).
_EI_RANGES_MM = ((10.0, 14.0), (14.0, 18.0), (18.0, 24.0), (24.0, 30.0), (30.0, 40.0), (40.0, 50.0), (50.0, 65.0),
                 (65.0, 80.0), (80.0, 100.0), (100.0, 120.0), (120.0, 140.0), (140.0, 160.0), (160.0, 180.0))
#: Lower deviations ei [um] of shafts m..u, per range above ([V] Machine Drawing Table 15.2); None = not defined.
_EI_UM = {
    "m": (7, 7, 8, 8, 9, 9, 11, 11, 13, 13, 15, 15, 15),
    "n": (12, 12, 15, 15, 17, 17, 20, 20, 23, 23, 27, 27, 27),
    "p": (18, 18, 22, 22, 26, 26, 32, 32, 37, 37, 43, 43, 43),
    "r": (23, 23, 28, 28, 34, 34, 41, 43, 51, 54, 63, 65, 68),
    "s": (28, 28, 35, 35, 43, 43, 53, 59, 71, 79, 92, 100, 108),
    "t": (None, None, None, 41, 48, 54, 66, 75, 91, 104, 122, 134, 146),
    "u": (33, 33, 41, 48, 60, 70, 87, 102, 124, 144, 170, 190, 210),
}

SOURCE = ("[V] IT5-IT8: BIG DAISHOWA catalogue p. 139; shaft ei (m..u): Machine Drawing Table 15.2 "
          "(issuhub.com/view/index/5590?pageIndex=239)")


def _range_index(nominal_mm: float, ranges, what: str) -> int:
    d = float(nominal_mm)
    for i, (lo, hi) in enumerate(ranges):
        if lo < d <= hi:
            return i
    raise GearoptInputError(f"nominal_mm={d:g} mm is outside the {what} table of gearopt.joints.iso286: "
                            f"must be > {ranges[0][0]:g} and <= {ranges[-1][1]:g} mm")


def tolerance_grade_um(nominal_mm: float, grade: int) -> float:
    """Standard tolerance IT<grade> [um] for a nominal size [mm] (ISO 286-1; grades 5-8, 10 < d <= 180 mm)."""
    if grade not in _IT_UM:
        raise GearoptInputError(f"grade=IT{grade} is not tabulated here: must be one of {sorted(_IT_UM)}")
    return float(_IT_UM[grade][_range_index(nominal_mm, _IT_RANGES_MM, "IT")])


def _parse_class(tolerance_class: str, hole: bool) -> tuple[str, int]:
    m = re.fullmatch(r"\s*([A-Za-z])\s*(\d+)\s*", str(tolerance_class))
    if not m:
        raise GearoptInputError(f"tolerance class {tolerance_class!r} must look like 'H7' (hole) or 'r6' (shaft)")
    letter, grade = m.group(1), int(m.group(2))
    if hole and letter != "H":
        raise GearoptInputError(f"hole class {tolerance_class!r}: only H holes (hole-basis fits) are tabulated")
    if not hole and letter not in _EI_UM:
        raise GearoptInputError(f"shaft class {tolerance_class!r}: only shafts {sorted(_EI_UM)} are tabulated")
    return letter, grade


def hole_deviations_um(nominal_mm: float, tolerance_class: str = "H7") -> tuple[float, float]:
    """(lower EI, upper ES) deviations [um] of an H hole: EI = 0, ES = IT."""
    _, grade = _parse_class(tolerance_class, hole=True)
    return 0.0, tolerance_grade_um(nominal_mm, grade)


def shaft_deviations_um(nominal_mm: float, tolerance_class: str) -> tuple[float, float]:
    """(lower ei, upper es) deviations [um] of a shaft class such as ``"r6"``: es = ei + IT."""
    letter, grade = _parse_class(tolerance_class, hole=False)
    ei = _EI_UM[letter][_range_index(nominal_mm, _EI_RANGES_MM, "shaft deviation")]
    if ei is None:
        raise GearoptInputError(f"shaft class {tolerance_class!r} is not defined by ISO 286 at "
                                f"{float(nominal_mm):g} mm (t shafts start above 24 mm)")
    return float(ei), float(ei) + tolerance_grade_um(nominal_mm, grade)


def fit_interference_um(nominal_mm: float, fit: str) -> dict:
    """Diametral interference of a hole-basis fit such as ``"H7/u6"`` at a nominal size [mm].

    Returns ``min_um`` (ei - ES), ``max_um`` (es - EI), ``mean_um`` and the four deviations. ``min_um < 0`` means
    the fit can be a clearance at its limits.
    """
    check_range("nominal_mm", nominal_mm, 0.0, 3150.0, low_inclusive=False, unit="mm")  # ISO 286-1 sizes
    if not isinstance(fit, str):
        raise GearoptInputError(f"fit={fit!r} must be a string like 'H7/r6' (hole/shaft)")
    parts = str(fit).split("/")
    if len(parts) != 2:
        raise GearoptInputError(f"fit={fit!r} must look like 'H7/r6' (hole/shaft)")
    EI, ES = hole_deviations_um(nominal_mm, parts[0])
    ei, es = shaft_deviations_um(nominal_mm, parts[1])
    lo, hi = ei - ES, es - EI
    return {"fit": fit, "nominal_mm": float(nominal_mm), "hole_lower_um": EI, "hole_upper_um": ES,
            "shaft_lower_um": ei, "shaft_upper_um": es, "min_um": lo, "max_um": hi, "mean_um": 0.5 * (lo + hi),
            "source": SOURCE}


__all__ = ["tolerance_grade_um", "hole_deviations_um", "shaft_deviations_um", "fit_interference_um", "SOURCE"]
