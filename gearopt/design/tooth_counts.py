"""Integer tooth counts of a gear train at fixed centre distances: enumerate, fit by profile shift, optimise, rank.

The thesis (section 3.4.1, Eq. 3.1, Table 3.1) converted a helical timing train to spur gears in the same housing:
tooth counts z = d/m at the spur module, a 2.7027 % speed-ratio error accepted on the crank-LPI (lube pump) branch,
centre distances closed by profile shift (section 3.4.2). Here that choice is made systematically:

1. **Enumerate** integer tooth counts per gear (a range or ``span`` around the train's teeth), walking the train's
   tree from its root gear so each mesh is checked as soon as both its gears have teeth. A partial assignment that
   fails is reported once in :attr:`ToothCountEnumeration.rejected` (it stands for every completion of it), with
   the stage and the reason:

   - ``speed_ratio``: a mesh's ratio ``n2/n1 = z1/z2`` or a gear's speed relative to the root ``z_root/z_gear``
     (intermediate idlers cancel) differs from the reference by more than its tolerance [%];
   - ``centre_distance``: the housing's centre distance cannot be reached (no working pressure angle in
     (0, 45] deg, ISO 21771 eq. 46);
   - ``sum_of_shifts``: the sum of profile shifts x1 + x2 that closes the centre distance (ISO 21771 eq. 44, thesis
     Eqs. 3.2-3.5) lies outside the sum of the two gears' lower limits (ISO/TR 4467 recommended lower limit, thesis
     Eqs. 3.8-3.12, or the undercut limit, whichever is higher) and upper limits (ISO/TR 4467 upper limit);
   - ``shift_limits``: with every mesh's sum fixed, each gear's shift is ``x_g = s_g +- x_root`` (x_root: the root
     gear's shift, the one free split of the tree). The per-gear limits give an interval of x_root; empty = rejected,
     naming the two gears whose limits conflict;
   - ``precheck``: sampled feasibility of the nonlinear limits (worst-case contact ratio, tip thickness,
     interference, bottom clearance, backlash) at ``precheck_samples`` root shifts evenly spread over the interval.
     A sampled check: a candidate feasible only inside a window narrower than the sample spacing would be rejected
     (spacing reported in the reason; ``precheck=False`` sends every interval-feasible candidate to the NLP).

2. **Optimise** each admissible candidate with Ipopt (:class:`~gearopt.nlp.problem.Problem`): variable = the root
   gear's profile shift x_root within its interval (the rest of the tree follows, :class:`GearTrain`), constraints =
   every mesh's :meth:`GearPair.constraints` (worst-case contact ratio, tip thickness, undercut, interference,
   bottom clearance, ISO/TR 4467 limits, backlash; per-gear limits once per gear), objective = the smallest
   worst-case transverse contact ratio of all meshes, or the smallest normal tip thickness of all gears [mm]
   (epigraph form, maximised). Candidates are solved in enumeration order, each warm-started at the previous
   candidate's optimal x_root (clipped into its own interval); cold start = the train's ISO/TR 4467 split; or
   each starts at its best precheck sample. (Each candidate has its own NLP, so only the primal start carries
   over: the constraint sets differ in size between candidates.)
   A failed solve is kept in the table with its typed error's status and the violated constraints by name.

3. **Rank** by the objective (best first), ties by the largest absolute speed-ratio error.

Optionally, :func:`bonmin_cross_check` solves a relaxed mixed-integer model (integer teeth, the speed-ratio
tolerances as linear constraints, the sums of shifts as continuous functions of the tooth sums, the per-gear shift
limits as piecewise-linear functions of z; objective: the widest margin to the shift limits) with CasADi's Bonmin
and compares its integer solution with the enumeration's best candidate by the same measure.

Conventions: angles in degrees, lengths in mm, profile shifts and contact ratios dimensionless, speed-ratio errors
in percent (``(candidate / reference - 1) * 100``). Speed ratios here are magnitudes (the sense of rotation is
fixed by the tree). Validity: external involute gears, teeth >= 5, the train's rack and helix angle.
"""

from __future__ import annotations

import math
import os
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, Iterable, Mapping

import casadi as ca
import numpy as np
import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError, GeometryError, SolveError
from ..validation import check_range
from ..geometry import involute as inv
from ..geometry.shift import (check_centre_distance_reachable, iso_tr_4467_shift_limits, shift_split_iso_tr_4467,
                              sum_of_profile_shifts, working_pressure_angle_from_centre_distance)
from ..geometry.train import GearTrain
from ..units import DEG_PER_RAD, RAD_PER_DEG
from ..nlp.problem import Problem

OBJECTIVES = ("max_min_worst_case_contact_ratio", "max_min_tip_thickness")
REFERENCES = ("teeth", "data", "helical_original")
STAGES = ("speed_ratio", "centre_distance", "sum_of_shifts", "shift_limits", "precheck")

_RATIO_EPS_PERCENT = 1e-9      # floating-point slack of the tolerance comparison [%]
_PER_GEAR_CONSTRAINTS = ("undercut_margin", "tip_thickness_margin", "shift_upper_margin", "shift_lower_margin")
_NO_LIMIT = 10.0               # stands for "no ISO/TR 4467 limit" in the relaxed Bonmin model (|x| <= 3 anyway)


# ----------------------------------------------------------------------------------------------------------------
# tree and reference ratios
# ----------------------------------------------------------------------------------------------------------------

def _tree_order(train: GearTrain) -> list[tuple[str, str | None, str | None]]:
    """(gear, mesh through which it is reached, parent gear) in breadth-first order from the root gear."""
    order, seen, queue = [(train.root_gear, None, None)], {train.root_gear}, [train.root_gear]
    while queue:
        g = queue.pop(0)
        for name, mesh in train.meshes.items():
            if g in mesh.gears:
                other = mesh.gears[1] if mesh.gears[0] == g else mesh.gears[0]
                if other not in seen:
                    seen.add(other)
                    order.append((other, name, g))
                    queue.append(other)
    return order


def _ratios_from_teeth(train: GearTrain, teeth: Mapping[str, int]) -> dict[str, float]:
    """Speed of every gear relative to the root gear (magnitude): z_root / z_gear."""
    z0 = teeth[train.root_gear]
    return {g: z0 / teeth[g] for g in train.gears}


def reference_speed_ratios(train: GearTrain, reference: str | Mapping[str, float] = "teeth",
                           data: Mapping[str, Any] | None = None) -> dict[str, float]:
    """Reference speed of every gear relative to the train's root gear (magnitudes, dimensionless).

    ``reference``:

    - ``"teeth"``: the train's own tooth counts, z_root / z_gear;
    - ``"data"``: the data file's ``[gears.*] speed_ratio_to_crank`` (printed to 4 decimals), each read as the
      nearest fraction with denominator <= 1000 when that is within the printed rounding (5e-5), and divided by the
      root gear's value;
    - ``"helical_original"``: the original helical train the thesis converted (Table 3.1): each mesh's reference
      ratio is the train's z1/z2 divided by (1 + ``speed_ratio_error_percent``/100) of the data's mesh table (the
      error of the spur tooth counts against the helical pair), propagated from the root;
    - a mapping gear -> ratio (every gear of the train; the root's value is divided out).

    ``data``: parsed data of the default schema (default: the packaged ``default_train.toml``).
    """
    from ..data import load_default_data, values

    if isinstance(reference, Mapping):
        missing = sorted(set(train.gears) - set(reference))
        if missing:
            raise GearoptInputError(f"reference speed ratios miss gears {missing}; limit: one ratio per gear of "
                                    f"{list(train.gears)}")
        for g in train.gears:
            check_range(f"reference[{g!r}]", reference[g], 0.0, None, low_inclusive=False)
        root = float(reference[train.root_gear])
        return {g: float(reference[g]) / root for g in train.gears}
    if reference not in REFERENCES:
        raise GearoptInputError(f"reference={reference!r} must be one of {REFERENCES} or a mapping gear -> ratio")
    teeth = {g: spec.teeth for g, spec in train.gears.items()}
    if reference == "teeth":
        return _ratios_from_teeth(train, teeth)
    d = values(dict(data) if data is not None else load_default_data())
    if reference == "data":
        out = {}
        for g in train.gears:
            try:
                v = float(d["gears"][g]["speed_ratio_to_crank"])
            except KeyError:
                raise GearoptInputError(f"reference='data': the data has no gears.{g}.speed_ratio_to_crank") from None
            check_range(f"gears.{g}.speed_ratio_to_crank", v, 0.0, None, low_inclusive=False)
            frac = Fraction(v).limit_denominator(1000)
            out[g] = float(frac) if abs(float(frac) - v) <= 5e-5 else v
        root = out[train.root_gear]
        return {g: r / root for g, r in out.items()}
    ratios = {train.root_gear: 1.0}
    for gear, mesh_name, parent in _tree_order(train)[1:]:
        try:
            err = float(d["meshes"][mesh_name]["speed_ratio_error_percent"])
        except KeyError:
            raise GearoptInputError(f"reference='helical_original': the data has no "
                                    f"meshes.{mesh_name}.speed_ratio_error_percent") from None
        g1, g2 = train.meshes[mesh_name].gears
        q = (teeth[g1] / teeth[g2]) / (1.0 + err / 100.0)  # reference n2/n1 of this mesh
        ratios[gear] = ratios[parent] * q if parent == g1 else ratios[parent] / q
    return ratios


# ----------------------------------------------------------------------------------------------------------------
# per-gear and per-mesh closed forms
# ----------------------------------------------------------------------------------------------------------------

def _rack_angles(train: GearTrain) -> tuple[float, float, float, float]:
    alpha_n = float(train.rack.pressure_angle_deg) * RAD_PER_DEG
    beta = float(train.helix_angle_deg) * RAD_PER_DEG
    alpha_t = float(inv.transverse_pressure_angle(alpha_n, beta))
    h_ff = float(inv.tool_form_height_coefficient(train.rack.dedendum_coefficient, train.rack.root_radius_coefficient,
                                                  alpha_n))
    return alpha_n, beta, alpha_t, h_ff


def gear_shift_limits(train: GearTrain, teeth: int, *, iso_tr_4467_limits: bool = True
                      ) -> tuple[float, float, str, str]:
    """Admissible profile-shift range (lower, upper) of a gear of ``teeth`` on the train's rack, with the name of
    each limit: lower = max(undercut limit x_min = h_FfP0* - z sin^2(alpha_t)/(2 cos beta), ISO/TR 4467 lower
    limit), upper = ISO/TR 4467 upper limit (thesis Eqs. 3.8-3.12; ``inf`` where the standard gives none or
    ``iso_tr_4467_limits`` is False). The same limits as :meth:`GearPair.constraints`' undercut and shift margins."""
    _, beta, alpha_t, h_ff = _rack_angles(train)
    x_u = float(inv.undercut_limit_profile_shift(teeth, alpha_t, beta, h_ff))
    lo_iso, hi_iso = iso_tr_4467_shift_limits(teeth) if iso_tr_4467_limits else (-math.inf, math.inf)
    if lo_iso > x_u:
        return lo_iso, hi_iso, "ISO/TR 4467 lower limit", "ISO/TR 4467 upper limit"
    return x_u, hi_iso, "undercut limit", "ISO/TR 4467 upper limit"


def mesh_sum_of_shifts(train: GearTrain, mesh: str, teeth: tuple[int, int]) -> tuple[float, float]:
    """Sum of profile shifts x1 + x2 [-] and working transverse pressure angle [deg] that close ``mesh``'s housing
    centre distance with ``teeth`` (ISO 21771 eqs. 44 and 46; thesis Eqs. 3.2-3.5). Raises ``GeometryError`` if the
    centre distance is unreachable (working pressure angle outside (0, 45] deg)."""
    alpha_n, beta, alpha_t, _ = _rack_angles(train)
    a = float(train.meshes[mesh].centre_distance_mm)
    m_t = float(inv.transverse_module(float(train.rack.module_mm), beta))
    a_d = 0.5 * (teeth[0] + teeth[1]) * m_t
    check_centre_distance_reachable(a_d, a, alpha_t)
    alpha_wt = float(working_pressure_angle_from_centre_distance(a_d, a, alpha_t))
    return float(sum_of_profile_shifts(teeth[0] + teeth[1], alpha_wt, alpha_t, alpha_n)), alpha_wt * DEG_PER_RAD


def _train_with_teeth(train: GearTrain, teeth: Mapping[str, int], root_profile_shift) -> GearTrain:
    gears = {g: replace(spec, teeth=int(teeth[g])) for g, spec in train.gears.items()}
    return GearTrain(gears=gears, meshes=dict(train.meshes), rack=train.rack, helix_angle_deg=train.helix_angle_deg,
                     root_mesh=train.root_mesh, root_gear=train.root_gear, root_profile_shift=root_profile_shift,
                     root_shift_split=train.root_shift_split, root_hand=train.root_hand, name=train.name)


# ----------------------------------------------------------------------------------------------------------------
# the candidate model: constraints, contact ratios and tip thicknesses as a function of the root shift
# ----------------------------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Limits:
    min_contact_ratio: float
    min_tip_thickness_ratio: float
    iso_tr_4467_limits: bool
    min_backlash_mm: float | None


@dataclass(frozen=True)
class CandidateModel:
    """One tooth-count candidate as a CasADi function of the root gear's profile shift x_root:
    ``function(x_root) -> (margins, worst_case_contact_ratios, tip_thicknesses_mm)``; the names of the margins
    (``gear:undercut_margin``, ``mesh:contact_ratio_margin`` ..., units in the names, ``g >= 0``), the meshes and
    the gears in output order."""

    function: Any = field(repr=False)
    margin_names: tuple[str, ...]
    meshes: tuple[str, ...]
    gears: tuple[str, ...]

    def evaluate(self, root_profile_shift) -> dict[str, np.ndarray]:
        """Numeric outputs at one or more root shifts (columns = samples)."""
        xs = np.atleast_1d(np.asarray(root_profile_shift, dtype=float))
        f = self.function if xs.size == 1 else self.function.map(int(xs.size))
        g, eps, s = f(xs.reshape(1, -1))
        return {"margins": np.asarray(g).reshape(len(self.margin_names), -1),
                "worst_case_contact_ratio": np.asarray(eps).reshape(len(self.meshes), -1),
                "tip_thickness_mm": np.asarray(s).reshape(len(self.gears), -1)}


def candidate_model(train: GearTrain, teeth: Mapping[str, int], *, min_contact_ratio: float = 1.2,
                    min_tip_thickness_ratio: float = 0.2, iso_tr_4467_limits: bool = True,
                    min_backlash_mm: float | None = 0.0) -> CandidateModel:
    """Build the :class:`CandidateModel` of ``train`` with ``teeth`` (gear -> z): the train is propagated from a
    symbolic root shift (:class:`GearTrain`), every mesh's :meth:`GearPair.constraints` become named margins
    (per-gear limits once per gear, from the first mesh that holds the gear)."""
    x = nm.symbol("root_profile_shift")
    tr = _train_with_teeth(train, teeth, x)
    names, exprs, eps, seen = [], [], [], set()
    tips: dict[str, Any] = {}
    for mesh_name, pair in tr.pairs.items():
        cons = pair.constraints(min_tip_thickness_ratio=min_tip_thickness_ratio, min_contact_ratio=min_contact_ratio,
                                worst_case=True, iso_tr_4467_limits=iso_tr_4467_limits,
                                min_backlash_mm=min_backlash_mm)
        geo = pair.geometry()
        for i, gear in enumerate(pair.names):
            tips.setdefault(gear, geo["tip_thickness_mm"][i])
        for key, expr in cons.items():
            base, unit = (key[:-3], "_mm") if key.endswith("_mm") else (key, "")
            if base[-2:] in ("_1", "_2"):
                gear = pair.names[int(base[-1]) - 1]
                stem = base[:-2]
                if stem in _PER_GEAR_CONSTRAINTS:
                    name = f"{gear}:{stem}{unit}"
                    if name in seen:
                        continue
                else:
                    name = f"{mesh_name}:{stem}_{gear}{unit}"
            else:
                name = f"{mesh_name}:{key}"
            seen.add(name)
            names.append(name)
            exprs.append(expr)
        eps.append(geo["worst_case_transverse_contact_ratio"])
    gears = tuple(train.gears)
    f = nm.function("tooth_count_candidate", [x],
                    [nm.vertcat(*exprs), nm.vertcat(*eps), nm.vertcat(*[tips[g] for g in gears])],
                    ["root_profile_shift"], ["margins", "worst_case_contact_ratio", "tip_thickness_mm"])
    return CandidateModel(function=f, margin_names=tuple(names), meshes=tuple(tr.pairs), gears=gears)


# ----------------------------------------------------------------------------------------------------------------
# enumeration
# ----------------------------------------------------------------------------------------------------------------

@dataclass
class ToothCountEnumeration:
    """Result of :func:`enumerate_tooth_counts` (plain data).

    ``admissible``: one row per admissible assignment: ``teeth_<gear>``, ``speed_ratio_error_<gear>_percent``
    (gear speed relative to the root vs the reference), ``ratio_error_<mesh>_percent`` (mesh ratio z1/z2 vs the
    reference), ``max_abs_ratio_error_percent``, ``sum_profile_shift_<mesh>``, ``working_pressure_angle_<mesh>_deg``,
    ``root_shift_min``/``root_shift_max`` (admissible interval of the root gear's shift), ``shift_margin`` (half its
    width = the largest achievable smallest margin to the per-gear shift limits),
    ``precheck_min_worst_case_contact_ratio`` / ``precheck_min_tip_thickness_mm`` (best feasible sample of each
    objective) at ``precheck_root_shift_contact_ratio`` / ``precheck_root_shift_tip_thickness``.
    ``rejected``: one row per rejected (partial) assignment: the teeth assigned so far (others missing), ``stage``
    (one of :data:`STAGES`), ``reason``, and for the precheck stage the interval columns.
    """

    train: GearTrain = field(repr=False)
    admissible: pd.DataFrame
    rejected: pd.DataFrame
    reference_ratios: dict[str, float]
    mesh_tolerance_percent: dict[str, float]
    gear_tolerance_percent: dict[str, float]
    teeth_ranges: dict[str, tuple[int, int]]
    limits: dict[str, Any]
    elapsed_s: float
    models: dict[tuple, CandidateModel] = field(default_factory=dict, repr=False, compare=False)

    def teeth(self, row) -> dict[str, int]:
        """Teeth per gear of an admissible row (index label or the row itself)."""
        r = self.admissible.loc[row] if not isinstance(row, pd.Series) else row
        return {g: int(r[f"teeth_{g}"]) for g in self.train.gears}

    def model(self, teeth: Mapping[str, int]) -> CandidateModel:
        key = tuple(int(teeth[g]) for g in self.train.gears)
        if key not in self.models:
            self.models[key] = candidate_model(self.train, teeth, **self.limits)
        return self.models[key]


def _teeth_ranges(train: GearTrain, teeth_range, span) -> dict[str, tuple[int, int]]:
    if teeth_range is None:
        if isinstance(span, bool) or not float(span).is_integer():
            raise GearoptInputError(f"span={span!r} must be a non-negative integer")
        check_range("span", span, 0, 50)
        s = int(span)
        return {g: (max(spec.teeth - s, 5), spec.teeth + s) for g, spec in train.gears.items()}
    if not isinstance(teeth_range, Mapping):
        raise GearoptInputError(f"teeth_range={teeth_range!r} must be a mapping gear -> (min, max) or iterable")
    unknown = sorted(set(teeth_range) - set(train.gears))
    if unknown:
        raise GearoptInputError(f"teeth_range names unknown gears {unknown}; gears: {list(train.gears)}")
    out = {}
    for g, spec in train.gears.items():
        r = teeth_range.get(g, (spec.teeth, spec.teeth))
        if isinstance(r, range):
            if len(r) == 0:
                raise GearoptInputError(f"teeth_range[{g!r}]={r!r} is empty; limit: at least one tooth count")
            r = (min(r), max(r))
        if not isinstance(r, (tuple, list)) or len(r) != 2:
            raise GearoptInputError(f"teeth_range[{g!r}]={r!r} must be (min, max) or a range")
        for v in r:
            if isinstance(v, bool) or not float(v).is_integer():
                raise GearoptInputError(f"teeth_range[{g!r}]={r!r} must hold integers")
        lo, hi = int(r[0]), int(r[1])
        if lo > hi:
            raise GearoptInputError(f"teeth_range[{g!r}]={r!r} is empty: min {lo} > max {hi}")
        check_range(f"teeth_range[{g!r}] min", lo, 5, None)
        out[g] = (lo, hi)
    return out


def _tolerances(train: GearTrain, ratio_tolerance_percent, default_tolerance_percent, exact_ratio_gears):
    check_range("default_tolerance_percent", default_tolerance_percent, 0.0, 100.0, high_inclusive=False, unit="%")
    given = dict(ratio_tolerance_percent or {})
    for key, tol in given.items():
        if key not in train.meshes and key not in train.gears:
            raise GearoptInputError(f"ratio_tolerance_percent names {key!r}, which is neither a mesh "
                                    f"{list(train.meshes)} nor a gear {list(train.gears)}")
        check_range(f"ratio_tolerance_percent[{key!r}]", tol, 0.0, 100.0, high_inclusive=False, unit="%")
    if exact_ratio_gears is None:
        exact_ratio_gears = tuple(g for g, s in train.gears.items() if "camshaft" in s.role.lower())
    exact = tuple(exact_ratio_gears)
    for g in exact:
        if g not in train.gears:
            raise GearoptInputError(f"exact_ratio_gears names {g!r}, which is not a gear {list(train.gears)}")
        if float(given.get(g, 0.0)) != 0.0:
            raise GearoptInputError(f"ratio_tolerance_percent[{g!r}]={given[g]} conflicts with exact_ratio_gears "
                                    f"(limit 0 %)")
    mesh_tol = {m: float(given.get(m, default_tolerance_percent)) for m in train.meshes}
    gear_tol = {g: float(given[g]) for g in train.gears if g in given}
    gear_tol.update({g: 0.0 for g in exact})
    gear_tol.pop(train.root_gear, None)  # the root's speed ratio to itself is 1 by definition
    return mesh_tol, gear_tol


def _ratio_errors(train, teeth, ref, mesh_names=None) -> tuple[dict, dict]:
    """Percent errors: per gear (z_root/z_g vs reference) and per mesh (z1/z2 vs reference), for the gears and
    meshes whose teeth are known."""
    z0 = teeth[train.root_gear]
    gear_err = {g: (z0 / z / ref[g] - 1.0) * 100.0 for g, z in teeth.items()}
    mesh_err = {}
    for name in (mesh_names or train.meshes):
        g1, g2 = train.meshes[name].gears
        if g1 in teeth and g2 in teeth:
            mesh_err[name] = ((teeth[g1] / teeth[g2]) / (ref[g2] / ref[g1]) - 1.0) * 100.0
    return gear_err, mesh_err


def _interval(train, order, teeth, sums, shift_limits):
    """Root-shift interval from the per-gear limits with every mesh's sum fixed: x_g = off_g + sgn_g x_root."""
    off, sgn = {train.root_gear: 0.0}, {train.root_gear: 1.0}
    for gear, mesh, parent in order[1:]:
        off[gear] = sums[mesh] - off[parent]
        sgn[gear] = -sgn[parent]
    lo, hi = -3.0, 3.0   # GearPair's admissible profile_shift1 range
    lo_by, hi_by = ("GearPair profile_shift1 range", -3.0), ("GearPair profile_shift1 range", 3.0)
    for g in train.gears:
        x_lo, x_hi, lo_name, hi_name = shift_limits[teeth[g]]
        if sgn[g] > 0:
            a, b, a_by, b_by = x_lo - off[g], x_hi - off[g], (f"{g} {lo_name}", x_lo), (f"{g} {hi_name}", x_hi)
        else:
            a, b, a_by, b_by = off[g] - x_hi, off[g] - x_lo, (f"{g} {hi_name}", x_hi), (f"{g} {lo_name}", x_lo)
        if a > lo:
            lo, lo_by = a, a_by
        if b < hi:
            hi, hi_by = b, b_by
    return lo, hi, lo_by, hi_by, off, sgn


def enumerate_tooth_counts(train: GearTrain, *, ratio_tolerance_percent: Mapping[str, float] | None = None,
                           default_tolerance_percent: float = 0.0,
                           reference: str | Mapping[str, float] = "teeth",
                           exact_ratio_gears: Iterable[str] | None = None, span: int = 4,
                           teeth_range: Mapping[str, Any] | None = None, min_contact_ratio: float = 1.2,
                           min_tip_thickness_ratio: float = 0.2, iso_tr_4467_limits: bool = True,
                           min_backlash_mm: float | None = 0.0, precheck: bool = True, precheck_samples: int = 41,
                           data: Mapping[str, Any] | None = None,
                           max_partial_assignments: int = 200_000) -> ToothCountEnumeration:
    """Enumerate the integer tooth counts of ``train`` that fit its centre distances (module docstring, step 1).

    Args:
        train: the train (its meshes' centre distances [mm], rack, helix angle, root mesh/gear are kept).
        ratio_tolerance_percent: allowed |speed-ratio error| [%] by mesh name (ratio z1/z2 of the mesh) or by gear
            name (the gear's speed relative to the root gear), e.g. ``{"crank-lpi": 3.0}``.
        default_tolerance_percent: tolerance [%] of every mesh not named (gears not named are not checked
            individually, except ``exact_ratio_gears``).
        reference: reference speed ratios (:func:`reference_speed_ratios`: "teeth", "data", "helical_original" or
            a mapping gear -> ratio).
        exact_ratio_gears: gears whose speed relative to the root must be exact (0 %); default: the gears whose
            role mentions "camshaft" (a four-stroke camshaft turns at exactly half crank speed).
        span: teeth range per gear = the train's teeth +- span (at least 5), unless ``teeth_range`` is given.
        teeth_range: gear -> (min, max) teeth (inclusive); gears not named keep their teeth.
        min_contact_ratio, min_tip_thickness_ratio, iso_tr_4467_limits, min_backlash_mm: limits of
            :meth:`GearPair.constraints` (worst-case transverse contact ratio; normal tip thickness / m_n; ISO/TR
            4467 recommended shift range; smallest normal backlash [mm], ``None`` = unchecked).
        precheck: run the sampled feasibility check of the nonlinear limits (stage ``precheck``).
        precheck_samples: root shifts sampled per candidate (>= 2).
        data: parsed data for ``reference`` "data"/"helical_original" (default: the packaged data).
        max_partial_assignments: guard against an enumeration explosion (raise above it).

    Returns:
        :class:`ToothCountEnumeration` (``admissible`` and ``rejected`` tables, reference ratios, tolerances).
    """
    t0 = time.perf_counter()
    if not isinstance(train, GearTrain):
        raise GearoptInputError(f"train={type(train).__name__} must be a GearTrain")
    if nm.is_symbolic(train.rack.module_mm, train.rack.pressure_angle_deg, train.helix_angle_deg,
                      *(m.centre_distance_mm for m in train.meshes.values())):
        raise GearoptInputError("enumerate_tooth_counts needs a numeric train (module, angles, centre distances)")
    check_range("min_contact_ratio", min_contact_ratio, 1.0, 3.0)
    check_range("min_tip_thickness_ratio", min_tip_thickness_ratio, 0.0, 1.0)
    check_range("precheck_samples", precheck_samples, 2, 10_000)
    check_range("max_partial_assignments", max_partial_assignments, 1, None)
    ranges = _teeth_ranges(train, teeth_range, span)
    mesh_tol, gear_tol = _tolerances(train, ratio_tolerance_percent, default_tolerance_percent, exact_ratio_gears)
    ref = reference_speed_ratios(train, reference, data)
    order = _tree_order(train)
    gears = list(train.gears)
    limits = dict(min_contact_ratio=float(min_contact_ratio), min_tip_thickness_ratio=float(min_tip_thickness_ratio),
                  iso_tr_4467_limits=bool(iso_tr_4467_limits), min_backlash_mm=min_backlash_mm)
    all_z = sorted({z for lo, hi in ranges.values() for z in range(lo, hi + 1)})
    shift_limits = {z: gear_shift_limits(train, z, iso_tr_4467_limits=iso_tr_4467_limits) for z in all_z}
    mesh_cache: dict[tuple, Any] = {}
    rejected: list[dict] = []

    def reject(teeth, stage, reason, **extra):
        rejected.append({**{f"teeth_{g}": teeth.get(g) for g in gears}, "stage": stage, "reason": reason, **extra})

    # depth-first over the tree order: partial assignments that pass every mesh closed so far
    partial = [({train.root_gear: z}, {}) for z in range(ranges[train.root_gear][0], ranges[train.root_gear][1] + 1)]
    count = len(partial)
    for gear, mesh_name, parent in order[1:]:
        g1, g2 = train.meshes[mesh_name].gears
        nxt = []
        for teeth, sums in partial:
            for z in range(ranges[gear][0], ranges[gear][1] + 1):
                count += 1
                if count > max_partial_assignments:
                    raise GearoptInputError(f"the enumeration exceeds max_partial_assignments="
                                            f"{max_partial_assignments}; narrow span/teeth_range or the tolerances")
                t = {**teeth, gear: z}
                gear_err, mesh_err = _ratio_errors(train, t, ref, [mesh_name])
                e = mesh_err[mesh_name]
                if abs(e) > mesh_tol[mesh_name] + _RATIO_EPS_PERCENT:
                    reject(t, "speed_ratio", f"{mesh_name}: speed ratio z1/z2 = {t[g1]}/{t[g2]} is {e:+.4f} % off "
                                             f"its reference, beyond the tolerance {mesh_tol[mesh_name]:g} %")
                    continue
                if gear in gear_tol and abs(gear_err[gear]) > gear_tol[gear] + _RATIO_EPS_PERCENT:
                    reject(t, "speed_ratio", f"{gear}: speed relative to {train.root_gear} "
                                             f"{t[train.root_gear]}/{z} is {gear_err[gear]:+.4f} % off its reference "
                                             f"{ref[gear]:.6g}, beyond the tolerance {gear_tol[gear]:g} %")
                    continue
                key = (mesh_name, t[g1], t[g2])
                if key not in mesh_cache:
                    try:
                        mesh_cache[key] = mesh_sum_of_shifts(train, mesh_name, (t[g1], t[g2]))
                    except GeometryError as exc:
                        mesh_cache[key] = exc
                res = mesh_cache[key]
                if isinstance(res, GeometryError):
                    reject(t, "centre_distance", f"{mesh_name} (z {t[g1]}/{t[g2]}): {res}")
                    continue
                sum_x = res[0]
                (lo1, hi1, _, _), (lo2, hi2, _, _) = shift_limits[t[g1]], shift_limits[t[g2]]
                if sum_x > hi1 + hi2 + 1e-12:
                    reject(t, "sum_of_shifts", f"{mesh_name}: sum of profile shifts x1+x2={sum_x:.4f} exceeds the "
                                               f"limit {hi1 + hi2:.4f} (ISO/TR 4467 upper limits {hi1:.4f} for "
                                               f"z={t[g1]} + {hi2:.4f} for z={t[g2]})")
                    continue
                if sum_x < lo1 + lo2 - 1e-12:
                    reject(t, "sum_of_shifts", f"{mesh_name}: sum of profile shifts x1+x2={sum_x:.4f} is below the "
                                               f"limit {lo1 + lo2:.4f} (lower limits {lo1:.4f} for z={t[g1]} + "
                                               f"{lo2:.4f} for z={t[g2]}, undercut or ISO/TR 4467)")
                    continue
                nxt.append((t, {**sums, mesh_name: res}))
        partial = nxt

    rows = []
    for teeth, sums in partial:
        sum_x = {m: v[0] for m, v in sums.items()}
        lo, hi, lo_by, hi_by, _, _ = _interval(train, order, teeth, sum_x, shift_limits)
        gear_err, mesh_err = _ratio_errors(train, teeth, ref)
        row = {**{f"teeth_{g}": teeth[g] for g in gears},
               **{f"speed_ratio_error_{g}_percent": gear_err[g] for g in gears},
               **{f"ratio_error_{m}_percent": mesh_err[m] for m in train.meshes},
               "max_abs_ratio_error_percent": max(abs(v) for v in list(gear_err.values()) + list(mesh_err.values())),
               **{f"sum_profile_shift_{m}": sums[m][0] for m in train.meshes},
               **{f"working_pressure_angle_{m}_deg": sums[m][1] for m in train.meshes},
               "root_shift_min": lo, "root_shift_max": hi, "shift_margin": 0.5 * (hi - lo)}
        if lo > hi + 1e-12:
            reject(teeth, "shift_limits",
                   f"no shift of the root gear {train.root_gear} meets every gear's limits: {lo_by[0]} "
                   f"({lo_by[1]:.4f}) needs x_{train.root_gear} >= {lo:.4f}, {hi_by[0]} ({hi_by[1]:.4f}) needs "
                   f"x_{train.root_gear} <= {hi:.4f}", root_shift_min=lo, root_shift_max=hi,
                   shift_margin=0.5 * (hi - lo))
            continue
        row.update(precheck_root_shift_contact_ratio=np.nan, precheck_min_worst_case_contact_ratio=np.nan,
                   precheck_root_shift_tip_thickness=np.nan, precheck_min_tip_thickness_mm=np.nan)
        if precheck:
            key = tuple(teeth[g] for g in gears)
            model = candidate_model(train, teeth, **limits)
            xs = np.linspace(lo, hi, int(precheck_samples)) if hi > lo else np.array([lo])
            out = model.evaluate(xs)
            worst = out["margins"].min(axis=0)
            ok = worst >= 0.0
            if not ok.any():
                j = int(np.argmax(worst))
                bad = [f"{n} = {v:.4g}" for n, v in zip(model.margin_names, out["margins"][:, j]) if v < 0.0]
                step = (hi - lo) / max(len(xs) - 1, 1)
                reject(teeth, "precheck",
                       f"no sampled root shift in [{lo:.4f}, {hi:.4f}] (step {step:.4f}) meets every limit; at the "
                       f"best sample x_{train.root_gear}={xs[j]:.4f}: " + ", ".join(bad),
                       root_shift_min=lo, root_shift_max=hi, shift_margin=0.5 * (hi - lo))
                continue
            eps_min = np.where(ok, out["worst_case_contact_ratio"].min(axis=0), -np.inf)
            tip_min = np.where(ok, out["tip_thickness_mm"].min(axis=0), -np.inf)
            j, k = int(np.argmax(eps_min)), int(np.argmax(tip_min))
            row.update(precheck_root_shift_contact_ratio=float(xs[j]),
                       precheck_min_worst_case_contact_ratio=float(eps_min[j]),
                       precheck_root_shift_tip_thickness=float(xs[k]), precheck_min_tip_thickness_mm=float(tip_min[k]))
            rows.append((row, key, model))
        else:
            rows.append((row, None, None))
    admissible = pd.DataFrame([r for r, _, _ in rows])
    if admissible.empty:
        admissible = pd.DataFrame(columns=[f"teeth_{g}" for g in gears])
    rej = pd.DataFrame(rejected, columns=[f"teeth_{g}" for g in gears] + ["stage", "reason", "root_shift_min",
                                                                          "root_shift_max", "shift_margin"])
    for g in gears:
        rej[f"teeth_{g}"] = rej[f"teeth_{g}"].astype("Int64")
    models = {k: m for _, k, m in rows if k is not None}
    return ToothCountEnumeration(train=train, admissible=admissible, rejected=rej, reference_ratios=ref,
                                 mesh_tolerance_percent=mesh_tol, gear_tolerance_percent=gear_tol,
                                 teeth_ranges=ranges, limits=limits, elapsed_s=time.perf_counter() - t0,
                                 models=models)


# ----------------------------------------------------------------------------------------------------------------
# continuous NLP per candidate, ranking
# ----------------------------------------------------------------------------------------------------------------

@dataclass
class ToothCountStudy:
    """Result of :func:`tooth_count_study` (plain data except ``best``).

    ``table``: the admissible candidates ranked by ``objective_value`` (best first; failed solves last): the
    enumeration columns plus ``rank``, ``status`` (Ipopt's, or ``not_solved`` beyond ``top``), ``iterations``,
    ``solve_time_s``, ``start`` ("previous"/"precheck"/"iso"), ``start_root_shift``, ``objective_value`` (the
    smallest worst-case
    contact ratio, or the smallest tip thickness [mm]), ``profile_shift_<gear>``, ``worst_case_contact_ratio_<mesh>``,
    ``tip_thickness_<gear>_mm``, ``min_worst_case_contact_ratio``, ``min_tip_thickness_mm``, ``limiting`` (the
    meshes or gears that set the objective), ``active`` (active constraints and bounds), ``violated`` (names of
    violated constraints of a failed solve). ``rejected``: the enumeration's
    rejections. ``best``: the best candidate as a numeric :class:`GearTrain` (``None`` if no solve succeeded).
    ``solves``: one dict per NLP in solve order. ``bonmin``: :func:`bonmin_cross_check`'s result or ``None``.
    """

    objective: str
    table: pd.DataFrame
    rejected: pd.DataFrame
    best: GearTrain | None = field(repr=False)
    solves: list[dict]
    enumeration: ToothCountEnumeration = field(repr=False)
    bonmin: dict | None = None
    elapsed_s: float = 0.0


def _iso_start(train: GearTrain, teeth: Mapping[str, int], lo: float, hi: float) -> float:
    """The train's own ISO/TR 4467 split of the root mesh (lambda = root_shift_split), clipped into [lo, hi]."""
    mesh = train.meshes[train.root_mesh]
    z = (teeth[mesh.gears[0]], teeth[mesh.gears[1]])
    sum_x, _ = mesh_sum_of_shifts(train, train.root_mesh, z)
    split = train.root_shift_split if nm.is_numeric(train.root_shift_split) else 0.5
    x = shift_split_iso_tr_4467(z, sum_x, float(split))
    x_root = float(x[mesh.gears.index(train.root_gear)])
    return _clip(x_root, lo, hi)


def _clip(x: float, lo: float, hi: float) -> float:
    return float(min(max(x, lo), hi))


def _element_name(name: str, model: CandidateModel, objective_terms) -> str:
    """``limits[i]`` -> the margin's name, ``epigraph[i]`` -> the mesh/gear of objective term i."""
    base, _, rest = name.partition("[")
    if not rest:
        return name
    i = int(rest.rstrip("]"))
    if base == "limits":
        return model.margin_names[i]
    if base == "epigraph":
        return str(objective_terms[i])
    return name


def solve_candidate(enumeration: ToothCountEnumeration, teeth: Mapping[str, int], *,
                    objective: str = "max_min_worst_case_contact_ratio", root_shift_start: float | None = None,
                    root_shift_bounds: tuple[float, float] | None = None, verbose: bool = False, **ipopt) -> dict:
    """Optimise the root gear's profile shift of one candidate (module docstring, step 2); returns a plain dict
    (``status``, ``iterations``, ``solve_time_s``, ``root_profile_shift``, ``objective_value``, ``active``,
    ``violated``, ``error`` (the typed :class:`SolveError` or ``None``)). ``root_shift_start`` defaults to the
    ISO/TR 4467 split; ``root_shift_bounds`` to the candidate's admissible interval."""
    if objective not in OBJECTIVES:
        raise GearoptInputError(f"objective={objective!r} must be one of {OBJECTIVES}")
    train = enumeration.train
    model = enumeration.model(teeth)
    if root_shift_bounds is None:
        sums = {m: mesh_sum_of_shifts(train, m, tuple(teeth[g] for g in train.meshes[m].gears))[0]
                for m in train.meshes}
        limits = {teeth[g]: gear_shift_limits(train, teeth[g],
                                              iso_tr_4467_limits=enumeration.limits["iso_tr_4467_limits"])
                  for g in train.gears}
        lo, hi = _interval(train, _tree_order(train), teeth, sums, limits)[:2]
    else:
        lo, hi = root_shift_bounds
    if lo > hi:
        lo = hi = 0.5 * (lo + hi)  # no admissible split: Ipopt reports the violated limits at the compromise
    x0 = _iso_start(train, teeth, lo, hi) if root_shift_start is None else _clip(root_shift_start, lo, hi)
    label = "/".join(str(teeth[g]) for g in train.gears)
    p = Problem(name=f"tooth counts {label}")
    x = p.variable(f"{train.root_gear}:profile_shift", init=x0, lower=lo, upper=hi, scale=0.5)
    margins, eps, tips = model.function(x)
    # one vector constraint (declaring ~60 scalar ones costs more than the solve); element i is margin_names[i]
    p.subject_to("limits", margins, lower=0.0, source="gearopt.design.tooth_counts")
    start = model.evaluate(x0)
    m = float(train.rack.module_mm)
    if objective == "max_min_worst_case_contact_ratio":
        terms, names, scale, unit = eps, model.meshes, 1.0, ""
        t0 = float(start["worst_case_contact_ratio"].min())
    else:
        terms, names, scale, unit = tips, model.gears, m, "mm"
        t0 = float(start["tip_thickness_mm"].min())
    t = p.variable(objective, init=t0, scale=scale, unit=unit)
    p.subject_to("epigraph", terms - t, lower=0.0, scale=scale, unit=unit, source="gearopt.design.tooth_counts")
    p.maximize(t, scale=scale)
    options = {"bound_relax_factor": 0.0, **ipopt}
    try:
        res = p.solve(verbose=verbose, **options)
        err = None
    except SolveError as exc:
        res, err = exc.result, exc
    out = {"teeth": dict(teeth), "status": res.status if res is not None else getattr(err, "status", "error"),
           "iterations": int(res.iterations) if res is not None else -1,
           "solve_time_s": float(res.solve_time_s) if res is not None else float("nan"),
           "start_root_shift": x0, "root_shift_bounds": (lo, hi), "error": err,
           "violated": [_element_name(v.name, model, names) for v in err.violated] if err is not None else [],
           "root_profile_shift": float(res.values[f"{train.root_gear}:profile_shift"]) if res is not None else None,
           "objective_value": float(res.values[objective]) if err is None else float("nan"),
           "active": [], "limiting": []}
    if err is None:
        active = [str(n) for n in res.constraints.loc[res.constraints["active"], "name"]]
        out["active"] = [_element_name(n, model, names) for n in active if not n.startswith("epigraph")]
        out["limiting"] = [_element_name(n, model, names) for n in active if n.startswith("epigraph")]
        x_opt, tol = out["root_profile_shift"], 1e-6
        if hi > lo and x_opt <= lo + tol:
            out["active"].append(f"{train.root_gear}:profile_shift at its lower bound {lo:.6g}")
        elif hi > lo and x_opt >= hi - tol:
            out["active"].append(f"{train.root_gear}:profile_shift at its upper bound {hi:.6g}")
    return out


STARTS = ("previous", "precheck", "iso")


def tooth_count_study(train: GearTrain, *, objective: str = "max_min_worst_case_contact_ratio",
                      top: int | None = None, start: str = "previous", bonmin: bool = False,
                      enumeration: ToothCountEnumeration | None = None, verbose: bool = False,
                      **enumerate_options) -> ToothCountStudy:
    """Enumerate (unless ``enumeration`` is given), optimise each admissible candidate, rank (module docstring).

    Args:
        train: the train; ``enumerate_options`` go to :func:`enumerate_tooth_counts`.
        objective: one of :data:`OBJECTIVES` (smallest worst-case transverse contact ratio of all meshes, or
            smallest normal tip thickness of all gears [mm], maximised).
        top: solve only the ``top`` candidates with the best precheck value of the objective (the others get
            status ``not_solved``); ``None``: all.
        start: initial root shift of each NLP: ``"previous"`` (warm start: the previous candidate's optimum,
            clipped into this candidate's interval; the first candidate starts at the ISO/TR 4467 split),
            ``"precheck"`` (the best precheck sample of the objective) or ``"iso"`` (cold: the train's ISO/TR 4467
            split of the root mesh, ``root_shift_split``).
        bonmin: also run :func:`bonmin_cross_check` (raises ``GearoptInputError`` if CasADi has no Bonmin).
    """
    t_start = time.perf_counter()
    if objective not in OBJECTIVES:
        raise GearoptInputError(f"objective={objective!r} must be one of {OBJECTIVES}")
    if top is not None:
        check_range("top", top, 1, None)
    if start not in STARTS:
        raise GearoptInputError(f"start={start!r} must be one of {STARTS}")
    if bonmin and not ca.has_nlpsol("bonmin"):
        raise GearoptInputError("bonmin=True: this CasADi build has no Bonmin plugin (casadi.has_nlpsol('bonmin') "
                                "is False); install a CasADi wheel with Bonmin or use bonmin=False")
    if enumeration is None:
        enumeration = enumerate_tooth_counts(train, **enumerate_options)
    elif enumerate_options:
        raise GearoptInputError(f"enumeration is given: options {sorted(enumerate_options)} would be ignored")
    train = enumeration.train
    adm = enumeration.admissible.copy()
    pre_col = ("precheck_min_worst_case_contact_ratio" if objective == "max_min_worst_case_contact_ratio"
               else "precheck_min_tip_thickness_mm")
    chosen = list(adm.index)
    if top is not None and len(chosen) > top:
        chosen = list(adm[pre_col].sort_values(ascending=False, na_position="last").index[:top])
        chosen.sort()
    solves, previous = [], None
    results: dict[Any, dict] = {}
    for idx in chosen:
        teeth = enumeration.teeth(idx)
        lo, hi = float(adm.at[idx, "root_shift_min"]), float(adm.at[idx, "root_shift_max"])
        x0, kind = None, "iso"
        if start == "previous" and previous is not None:
            x0, kind = previous, "previous"
        elif start == "precheck":
            col = ("precheck_root_shift_contact_ratio" if objective == "max_min_worst_case_contact_ratio"
                   else "precheck_root_shift_tip_thickness")
            if col in adm and math.isfinite(float(adm.at[idx, col])):
                x0, kind = float(adm.at[idx, col]), "precheck"
        r = solve_candidate(enumeration, teeth, objective=objective, root_shift_start=x0,
                            root_shift_bounds=(lo, hi), verbose=verbose)
        r["start"] = kind
        if r["error"] is None:
            previous = r["root_profile_shift"]
        solves.append({k: v for k, v in r.items() if k != "error"})
        results[idx] = r
    rows = []
    best_idx, best_x = None, None
    for idx in adm.index:
        row = adm.loc[idx].to_dict()
        r = results.get(idx)
        if r is None:
            row.update(status="not_solved", iterations=np.nan, solve_time_s=np.nan, start="", objective_value=np.nan)
            rows.append(row)
            continue
        row.update(status=r["status"], iterations=r["iterations"], solve_time_s=r["solve_time_s"], start=r["start"],
                   start_root_shift=r["start_root_shift"], objective_value=r["objective_value"],
                   limiting=", ".join(r["limiting"]), active=", ".join(r["active"]),
                   violated=", ".join(r["violated"]))
        x_root = r["root_profile_shift"]
        if x_root is not None and math.isfinite(x_root):
            tr = _train_with_teeth(train, enumeration.teeth(idx), x_root)
            for g, x in tr.profile_shifts.items():
                row[f"profile_shift_{g}"] = float(x)
            out = enumeration.model(enumeration.teeth(idx)).evaluate(x_root)
            for i, mname in enumerate(train.meshes):
                row[f"worst_case_contact_ratio_{mname}"] = float(out["worst_case_contact_ratio"][i, 0])
            for i, g in enumerate(train.gears):
                row[f"tip_thickness_{g}_mm"] = float(out["tip_thickness_mm"][i, 0])
            row["min_worst_case_contact_ratio"] = float(out["worst_case_contact_ratio"].min())
            row["min_tip_thickness_mm"] = float(out["tip_thickness_mm"].min())
        rows.append(row)
    table = pd.DataFrame(rows, index=adm.index)
    if not table.empty:
        solved = table["objective_value"].notna()
        table["_solved"] = ~solved
        table = table.sort_values(["_solved", "objective_value", "max_abs_ratio_error_percent"],
                                  ascending=[True, False, True], kind="mergesort").drop(columns="_solved")
        table.insert(0, "rank", np.arange(1, len(table) + 1))
        if solved.any():
            best_idx = table.index[0]
            best_x = results[best_idx]["root_profile_shift"]
    table = table.reset_index(drop=True)
    for g in train.gears:
        if f"teeth_{g}" in table:
            table[f"teeth_{g}"] = table[f"teeth_{g}"].astype(int)
    best = _train_with_teeth(train, enumeration.teeth(enumeration.admissible.loc[best_idx]), best_x) \
        if best_idx is not None else None
    study = ToothCountStudy(objective=objective, table=table, rejected=enumeration.rejected, best=best,
                            solves=solves, enumeration=enumeration)
    if bonmin:
        study.bonmin = bonmin_cross_check(enumeration)
    study.elapsed_s = time.perf_counter() - t_start
    return study


# ----------------------------------------------------------------------------------------------------------------
# Bonmin cross-check on a relaxed mixed-integer model
# ----------------------------------------------------------------------------------------------------------------

def _iso_limits_relaxed(z, iso: bool):
    """ISO/TR 4467 recommended shift range (thesis Eqs. 3.8-3.12) as continuous piecewise-linear functions of a
    relaxed tooth count (continuous at z = 20 and 50); +-_NO_LIMIT where the standard gives no value."""
    if not iso:
        return -_NO_LIMIT, _NO_LIMIT
    lower = nm.where(z <= 12, -_NO_LIMIT, nm.where(z <= 20, 0.0375 * (20 - z),
                                                   nm.where(z <= 50, (20 - z) / 60.0, -0.5)))
    upper = nm.where(z <= 10, _NO_LIMIT, nm.where(z <= 50, 0.5 + 0.01 * z, 1.0))
    return lower, upper


@contextmanager
def _quiet_native_stdout(quiet: bool):
    """Silence the C-level stdout while Bonmin runs (its per-node NLP lines ignore the log-level options)."""
    if not quiet:
        yield
        return
    sys.stdout.flush()
    try:
        fd = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # no real file descriptor (e.g. captured): nothing to silence
        yield
        return
    saved = os.dup(fd)
    try:
        with open(os.devnull, "w") as null:
            os.dup2(null.fileno(), fd)
            yield
    finally:
        os.dup2(saved, fd)
        os.close(saved)


def bonmin_cross_check(enumeration: ToothCountEnumeration, *, options: Mapping[str, Any] | None = None,
                       verbose: bool = False) -> dict:
    """Cross-check the enumeration with CasADi's Bonmin on a relaxed mixed-integer model.

    Variables: the teeth of every gear (integer, within the enumeration's ranges), the root gear's shift x_root and
    an epigraph variable t. Constraints: every mesh's and every toleranced gear's speed-ratio error within its
    tolerance (linear in the teeth: ``z1 - (1 +- tol) q z2``), the centre distance reachable
    (``cos 45 deg <= a_d(z) cos(alpha_t)/a < 1``), the sums of shifts x1 + x2 (ISO 21771 eqs. 44/46 with the tooth
    sum relaxed to a real number), the shifts propagated from x_root through the tree, and
    ``t <= x_g - x_lower(z_g)``, ``t <= x_upper(z_g) - x_g`` for every gear (undercut limit and ISO/TR 4467 limits
    as functions of the relaxed z, :func:`_iso_limits_relaxed`). Objective: maximise t, i.e. the widest margin to the
    per-gear shift limits. The enumeration's counterpart is each candidate's ``shift_margin`` (half the width of its
    root-shift interval, exact for the linear limits), over every candidate that passed the ``shift_limits`` stage
    (admissible or rejected only by the sampled precheck). The contact-ratio and tip-thickness limits are not in
    the relaxed model.

    Bonmin's default B-BB algorithm is exact for convex relaxations only; this model is nonconvex (the involute
    relation), so agreement is evidence, not proof. Returns a dict: ``status``, ``teeth``, ``shift_margin``,
    ``root_profile_shift``, ``enumeration_teeth`` (best by shift margin, ties: all listed),
    ``enumeration_shift_margin``,
    ``agrees`` (Bonmin's teeth among the enumeration's best and margins equal within 1e-6), ``solve_time_s``.
    ``options``: extra Bonmin options (``bonmin.`` names without the prefix); ``verbose``: keep Bonmin's log.
    Raises ``GearoptInputError`` if this CasADi has no Bonmin.
    """
    if not ca.has_nlpsol("bonmin"):
        raise GearoptInputError("bonmin_cross_check: this CasADi build has no Bonmin plugin "
                                "(casadi.has_nlpsol('bonmin') is False)")
    train = enumeration.train
    gears = list(train.gears)
    iso = bool(enumeration.limits["iso_tr_4467_limits"])
    alpha_n, beta, alpha_t, h_ff = _rack_angles(train)
    m_t = float(inv.transverse_module(float(train.rack.module_mm), beta))
    z = nm.symbol("teeth", len(gears))
    x_root = nm.symbol("root_profile_shift")
    t = nm.symbol("shift_margin")
    zg = {g: z[i] for i, g in enumerate(gears)}
    ref = enumeration.reference_ratios
    g_exprs, g_lo, g_hi = [], [], []

    def con(expr, lo, hi):
        g_exprs.append(expr)
        g_lo.append(lo)
        g_hi.append(hi)

    for name, mesh in train.meshes.items():
        g1, g2 = mesh.gears
        q = ref[g2] / ref[g1]
        tol = enumeration.mesh_tolerance_percent[name] / 100.0 + _RATIO_EPS_PERCENT / 100.0
        con(zg[g1] - (1.0 + tol) * q * zg[g2], -math.inf, 0.0)
        con(zg[g1] - (1.0 - tol) * q * zg[g2], 0.0, math.inf)
    root = train.root_gear
    for g, tol_pc in enumeration.gear_tolerance_percent.items():
        tol = tol_pc / 100.0 + _RATIO_EPS_PERCENT / 100.0
        con(zg[root] - (1.0 + tol) * ref[g] * zg[g], -math.inf, 0.0)
        con(zg[root] - (1.0 - tol) * ref[g] * zg[g], 0.0, math.inf)
    x = {root: x_root}
    for gear, mesh_name, parent in _tree_order(train)[1:]:
        g1, g2 = train.meshes[mesh_name].gears
        a = float(train.meshes[mesh_name].centre_distance_mm)
        c = 0.5 * (zg[g1] + zg[g2]) * m_t * math.cos(alpha_t) / a
        con(c, math.cos(math.radians(45.0)), 1.0 - 1e-9)
        alpha_wt = nm.acos_safe(c, 1e-12)
        x[gear] = sum_of_profile_shifts(zg[g1] + zg[g2], alpha_wt, alpha_t, alpha_n) - x[parent]
    for g in gears:
        x_u = inv.undercut_limit_profile_shift(zg[g], alpha_t, beta, h_ff)
        lo_iso, hi_iso = _iso_limits_relaxed(zg[g], iso)
        con(x[g] - x_u - t, 0.0, math.inf)
        con(x[g] - lo_iso - t, 0.0, math.inf)
        con(hi_iso - x[g] - t, 0.0, math.inf)
    con(3.0 - x_root - t, 0.0, math.inf)
    con(x_root + 3.0 - t, 0.0, math.inf)
    w = nm.vertcat(z, x_root, t)
    nlp = {"x": w, "f": -t, "g": nm.vertcat(*g_exprs)}
    opts = {"discrete": [True] * len(gears) + [False, False], "print_time": False,
            "bonmin": {"print_level": 0, "bb_log_level": 0, "nlp_log_level": 0, "algorithm": "B-BB"}}
    opts["bonmin"].update(dict(options or {}))
    solver = ca.nlpsol("tooth_count_bonmin", "bonmin", nlp, opts)
    lbx = [enumeration.teeth_ranges[g][0] for g in gears] + [-3.0, -_NO_LIMIT]
    ubx = [enumeration.teeth_ranges[g][1] for g in gears] + [3.0, _NO_LIMIT]
    x0 = [min(max(train.gears[g].teeth, lbx[i]), ubx[i]) for i, g in enumerate(gears)]
    x0 += [float(train.profile_shifts[root]) if nm.is_numeric(train.profile_shifts[root]) else 0.0, 0.0]
    t0 = time.perf_counter()
    with _quiet_native_stdout(not verbose):
        sol = solver(x0=x0, lbx=lbx, ubx=ubx, lbg=g_lo, ubg=g_hi)
    elapsed = time.perf_counter() - t0
    stats = solver.stats()
    wv = np.asarray(sol["x"]).reshape(-1)
    teeth = {g: int(round(wv[i])) for i, g in enumerate(gears)}
    # the enumeration's candidates that passed the shift-limits stage
    cols = [f"teeth_{g}" for g in gears] + ["shift_margin"]
    pool = [enumeration.admissible[cols]] if not enumeration.admissible.empty else []
    pre = enumeration.rejected[enumeration.rejected["stage"] == "precheck"]
    if not pre.empty:
        pool.append(pre[cols])
    both = pd.concat(pool, ignore_index=True) if pool else pd.DataFrame(columns=cols)
    if both.empty:
        best_teeth, best_margin = [], float("nan")
    else:
        best_margin = float(both["shift_margin"].max())
        tops = both[both["shift_margin"] >= best_margin - 1e-9]
        best_teeth = [{g: int(r[f"teeth_{g}"]) for g in gears} for _, r in tops.iterrows()]
    margin = float(wv[-1])
    success = bool(stats.get("success", False))
    return {"status": str(stats.get("return_status", "")), "success": success, "teeth": teeth,
            "shift_margin": margin, "root_profile_shift": float(wv[len(gears)]),
            "enumeration_teeth": best_teeth, "enumeration_shift_margin": best_margin,
            "agrees": success and teeth in best_teeth and abs(margin - best_margin) <= 1e-6,
            "solve_time_s": elapsed}
