"""Enumeration of integer tooth counts at fixed centre distances, screening partial assignments by speed ratio,
centre distance, sum of shifts, shift limits and a sampled precheck, each rejection with its reason. Part of
:mod:`gearopt.design.tooth_counts`."""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping

import numpy as np
import pandas as pd

from ... import numerics as nm
from ...data import System
from ...errors import GearoptInputError, GeometryError
from ...validation import check_range
from ...geometry.train import GearTrain
from .candidates import (CandidateModel, _RATIO_EPS_PERCENT, _tree_order, candidate_model, gear_shift_limits,
                         mesh_sum_of_shifts, reference_speed_ratios)


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
                           system: System | None = None,
                           max_partial_assignments: int = 200_000) -> ToothCountEnumeration:
    """Enumerate the integer tooth counts of ``train`` that fit its centre distances (module docstring, step 1).

    Args:
        train: the train (its meshes' centre distances [mm], rack, helix angle, root mesh/gear are kept).
        ratio_tolerance_percent: allowed |speed-ratio error| [%] by mesh name (ratio z1/z2 of the mesh) or by gear
            name (the gear's speed relative to the root gear), e.g. ``{"pinion-idler": 3.0}``.
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
        system: the :class:`~gearopt.data.System` for ``reference`` "data"/"helical_original" (required for
            those).
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
    ref = reference_speed_ratios(train, reference, system)
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
