"""Scene families of the solver stability study, shared by tests/stability (small samples) and
benchmarks/bench_stability.py (larger samples).

Every case is a plain dict of inputs; :func:`run_case` solves it and classifies the outcome:

- ``"solved"``: the solver returned, nothing is NaN, and the exact re-check meets every constraint within the
  tolerances below;
- ``"check_failed"``: the solver returned but the exact re-check violates a constraint beyond its tolerance;
- ``"typed_failure"``: a gearopt ``SolveError`` or ``GearoptInputError`` whose message names at least one
  constraint or input parameter of the case;
- ``"unnamed_failure"``: such an error with a message naming nothing the user declared;
- ``"untyped_failure"``: any other exception, or NaN in a returned result.

Families around the default spur crank-cam pair (z 38/76, m 3, a = 172.24 mm; ``gearopt/data/default_train.toml``):

- ``shift_split_random``: :func:`gearopt.design.shift_distribution.optimise_shift_split` with the centre distance
  uniform in its feasible range (found by brute force over the split, :func:`feasible_centre_distance_range`), face
  widths x U(0.9, 1.1), the initial split (ISO/TR 4467 lambda) uniform in [0, 1], both objectives;
- ``shift_split_extreme``: contact-ratio limit and minimum tip thickness ratio just below / just above the largest
  achievable value (brute force, :func:`split_limits`), centre distances at the ends of the feasible range;
- ``microgeometry_random``: :func:`gearopt.design.optimise_microgeometry` (20-30 positions, exact check on 160)
  with the torque x U(0.5, 1.5) of 300 N m, face widths x U(0.9, 1.1) and a random initial microgeometry inside the
  variable bounds (or the default start);
- ``microgeometry_load``: torque from 5 N m to 3 x 300 N m (log-uniform in the benchmark; 5 and 900 in the tests);
- ``microgeometry_smoothing``: contact smoothing widths of the smooth LTCA towards zero (0.05 .. 0.005 um).

Tolerances of the exact re-check (stated, and why):

- shift split: every margin of ``GearPair.constraints`` >= -1e-6 (mm or dimensionless); the NLP uses the same
  expressions, so only Ipopt's tolerance (1e-8 scaled) separates them;
- microgeometry: the NLP samples 20-30 mesh positions with a softplus contact of width ``smoothing_um``; the check
  is the exact LTCA on 160 positions, which also sees the mesh between the NLP's samples. Contact stress <=
  limit x (1 + 2 %) and loaded contact ratio >= limit - 0.05 (one NLP position spacing is 1/20 of a mesh cycle,
  i.e. 0.05 in contact ratio).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import lru_cache
from typing import Any

import numpy as np

import gearopt as go
from gearopt.contact.ltca import ltca
from gearopt.contact.ltca_smooth import DEFAULT_COUNT_WIDTH_UM
from gearopt.contact.microgeometry import Microgeometry
from gearopt.design import optimise_microgeometry
from gearopt.design.shift_distribution import optimise_shift_split
from gearopt.errors import GearoptInputError, SolveError
from gearopt.geometry.pair import GearPair

DESIGN_TORQUE_NM = 300.0          # crank-gear torque of the microgeometry study (benchmarks/bench_microgeometry_nlp.py)
MIN_CONTACT_RATIO = 1.2           # optimise_shift_split default
MIN_TIP_THICKNESS_RATIO = 0.2     # optimise_shift_split default
MIN_LOADED_CONTACT_RATIO = 1.2    # optimise_microgeometry default
MARGIN_TOL = 1e-6                 # shift split: margins in mm or dimensionless
STRESS_REL_TOL = 0.02             # microgeometry: exact stress on 160 positions vs limit
LCR_TOL = 0.05                    # microgeometry: one NLP position spacing in contact ratio
CHECK_POSITIONS = 160
SPLIT_GRID_STEP = 1e-4            # brute-force split grid
KINDS = ("solved", "check_failed", "typed_failure", "unnamed_failure", "untyped_failure")

SPLIT_CONSTRAINTS = ("undercut_margin_1", "undercut_margin_2", "tip_thickness_margin_1_mm",
                     "tip_thickness_margin_2_mm", "interference_margin_1_mm", "interference_margin_2_mm",
                     "contact_ratio_margin", "shift_upper_margin_1", "shift_upper_margin_2", "shift_lower_margin_1",
                     "shift_lower_margin_2", "epigraph", "profile_shift", "bottom_clearance")
MICRO_CONSTRAINTS = ("contact_stress", "loaded_contact_ratio", "te_below_max", "te_above_min", "ppte_below_max",
                     "tip_relief", "profile_crown")
PARAMETERS = ("centre_distance_mm", "torque_Nm", "smoothing_um", "min_contact_ratio", "min_tip_thickness_ratio",
              "face_width_mm", "positions", "max_contact_stress_MPa", "profile_shift")


@dataclass
class Outcome:
    """One solved (or failed) case."""

    family: str
    case: dict
    kind: str
    error: str = ""
    message: str = ""
    time_s: float = 0.0
    iterations: int | None = None
    details: dict = field(default_factory=dict)

    def describe(self) -> str:
        return f"{self.family} {self.case}: {self.kind} {self.error} {self.message[:300]!r} {self.details}"


# --------------------------------------------------------------------------- pairs and brute-force references

@lru_cache(maxsize=1)
def default_pair() -> GearPair:
    return go.load_default_train("spur").pairs["crank-cam"]


def pair_at(centre_distance_mm: float | None = None, face_width_factor: float = 1.0) -> GearPair:
    """The default crank-cam pair moved to another centre distance (ISO/TR 4467 split, lambda 0.5) and/or with
    scaled face widths."""
    base = default_pair()
    faces = tuple(float(b) * face_width_factor for b in base.face_width_mm)
    if centre_distance_mm is None:
        return replace(base, face_width_mm=faces)
    return GearPair.from_centre_distance(
        teeth=base.teeth, centre_distance_mm=centre_distance_mm, module_mm=base.module_mm,
        pressure_angle_deg=base.pressure_angle_deg, helix_angle_deg=base.helix_angle_deg, face_width_mm=faces,
        addendum_coefficient=base.addendum_coefficient, dedendum_coefficient=base.dedendum_coefficient,
        root_radius_coefficient=base.root_radius_coefficient, tip_shortening=base.tip_shortening,
        tolerances=base.tolerances, names=base.names)


def split_margins(pair: GearPair, x1: np.ndarray, *, min_contact_ratio: float = MIN_CONTACT_RATIO,
                  min_tip_thickness_ratio: float = MIN_TIP_THICKNESS_RATIO) -> tuple[dict, np.ndarray]:
    """Margins of optimise_shift_split's limits for the splits ``x1`` (vectorised) and the smaller tip thickness."""
    total = float(pair.profile_shifts[0] + pair.profile_shifts[1])
    trial = replace(pair, profile_shifts=(x1, total - x1), tip_diameters_mm=None)
    margins = trial.constraints(min_tip_thickness_ratio=min_tip_thickness_ratio,
                                min_contact_ratio=min_contact_ratio, worst_case=True, iso_tr_4467_limits=True,
                                min_backlash_mm=None)
    margins = {k: np.asarray(v, dtype=float) for k, v in margins.items()}
    shift = min_tip_thickness_ratio * float(pair.module_mm)   # margin = tip thickness - ratio m
    tip = np.minimum(margins["tip_thickness_margin_1_mm"], margins["tip_thickness_margin_2_mm"]) + shift
    return margins, tip


def split_limits(pair: GearPair) -> dict:
    """Brute force over x1 in [-1, 2] (step 1e-4, the NLP's bounds): the largest worst-case contact ratio among
    splits meeting every other limit (tip thickness ratio 0.2), and the largest smaller-tip-thickness ratio
    s_a,min / m among splits meeting every other limit (contact ratio >= 1.2)."""
    x1 = np.arange(-1.0, 2.0 + 1e-12, SPLIT_GRID_STEP)
    margins, tip = split_margins(pair, x1, min_contact_ratio=0.0, min_tip_thickness_ratio=MIN_TIP_THICKNESS_RATIO)
    eps = margins.pop("contact_ratio_margin")
    ok = np.all([v >= 0.0 for v in margins.values()], axis=0)
    margins, _ = split_margins(pair, x1, min_tip_thickness_ratio=0.0)
    ok_tip = np.all([v >= 0.0 for k, v in margins.items() if not k.startswith("tip_thickness")], axis=0)
    m = float(pair.module_mm)
    return {"max_contact_ratio": float(eps[ok].max()) if ok.any() else math.nan,
            "max_tip_thickness_ratio": float(tip[ok_tip].max() / m) if ok_tip.any() else math.nan}


def _feasible_count(centre_distance_mm: float) -> int:
    try:
        pair = pair_at(centre_distance_mm)
    except GearoptInputError:
        return 0
    x1 = np.arange(-1.0, 2.0 + 1e-12, 1e-3)
    margins, _ = split_margins(pair, x1)
    return int(np.all([v >= 0.0 for v in margins.values()], axis=0).sum())


@lru_cache(maxsize=1)
def feasible_centre_distance_range() -> tuple[float, float]:
    """Centre distances [mm] of the default crank-cam teeth at which some split x1 in [-1, 2] (grid 1e-3) meets every
    limit of optimise_shift_split (contact ratio 1.2, tip thickness 0.2 m, undercut, interference, ISO/TR 4467);
    bisection to 1e-3 mm from the nominal 172.24 mm outwards."""
    nominal = float(default_pair().centre_distance_mm)
    ends = []
    for outer in (nominal - 10.0, nominal + 10.0):
        good, bad = nominal, outer
        assert _feasible_count(good) > 0 and _feasible_count(bad) == 0
        while abs(bad - good) > 1e-3:
            mid = 0.5 * (good + bad)
            good, bad = (mid, bad) if _feasible_count(mid) > 0 else (good, mid)
        ends.append(good)
    return ends[0], ends[1]


def shift_split_problem(pair: GearPair, *, min_contact_ratio: float = MIN_CONTACT_RATIO,
                        min_tip_thickness_ratio: float = MIN_TIP_THICKNESS_RATIO, init: float = 0.2):
    """The Problem of optimise_shift_split ('max_min_tip_thickness') with the limits of these families, so that
    Problem-level tools (multistart, solve_elastic) apply to it."""
    from gearopt.design.shift_distribution import shift_split_problem as build

    return build(pair, min_contact_ratio=min_contact_ratio, min_tip_thickness_ratio=min_tip_thickness_ratio,
                 init=init)


# --------------------------------------------------------------------------- running and classifying

def _classify(family: str, case: dict, run: Callable[[], tuple[str, dict, int | None]], names: tuple) -> Outcome:
    t0 = time.perf_counter()
    try:
        kind, details, iterations = run()
        return Outcome(family, case, kind, time_s=time.perf_counter() - t0, iterations=iterations, details=details)
    except (SolveError, GearoptInputError) as exc:
        message = str(exc)
        named = bool(message.strip()) and any(name in message for name in names)
        if isinstance(exc, SolveError):
            named = named and bool(exc.status)
        return Outcome(family, case, "typed_failure" if named else "unnamed_failure", error=type(exc).__name__,
                       message=message, time_s=time.perf_counter() - t0,
                       iterations=getattr(getattr(exc, "result", None), "iterations", None))
    except Exception as exc:  # noqa: BLE001 - the point of the study is to catch these
        return Outcome(family, case, "untyped_failure", error=type(exc).__name__, message=str(exc),
                       time_s=time.perf_counter() - t0)


def run_shift_split(case: dict, family: str = "shift_split") -> Outcome:
    """Case keys: centre_distance_mm (None: nominal), face_width_factor, shift_split (initial lambda), objective,
    min_contact_ratio, min_tip_thickness_ratio."""
    limits = dict(min_contact_ratio=case.get("min_contact_ratio", MIN_CONTACT_RATIO),
                  min_tip_thickness_ratio=case.get("min_tip_thickness_ratio", MIN_TIP_THICKNESS_RATIO))

    def run():
        pair = pair_at(case.get("centre_distance_mm"), case.get("face_width_factor", 1.0))
        res = optimise_shift_split(pair, objective=case.get("objective", "max_min_tip_thickness"),
                                   shift_split=case.get("shift_split", 0.5), **limits)
        x = np.asarray(res["profile_shifts"], dtype=float)
        margins, tip = split_margins(pair, np.array([x[0]]), **limits)
        worst = min(float(v[0]) for v in margins.values())
        finite = bool(np.all(np.isfinite(x))) and np.isfinite(res["objective_value"]) and np.isfinite(worst)
        total_error = abs(x.sum() - float(pair.profile_shifts[0] + pair.profile_shifts[1]))
        details = {"profile_shift_1": float(x[0]), "worst_margin": worst, "sum_error": total_error,
                   "objective_value": float(res["objective_value"])}
        if not finite:
            return "untyped_failure", details, res["iterations"]
        ok = worst >= -MARGIN_TOL and total_error < 1e-9
        if case.get("objective", "max_min_tip_thickness") == "max_min_tip_thickness":
            details["objective_error_mm"] = abs(float(res["objective_value"]) - float(tip[0]))
            ok = ok and details["objective_error_mm"] < 1e-6
        return ("solved" if ok else "check_failed"), details, res["iterations"]

    return _classify(family, case, run, SPLIT_CONSTRAINTS + PARAMETERS)


def _random_microgeometry(pair: GearPair, rng: np.random.Generator) -> Microgeometry:
    """A start inside optimise_microgeometry's bounds: amounts 0..40 um, starts between the working pitch point
    and 0.25 deg below the tip, crowns 0..10 um."""
    g = pair.geometry()
    starts = tuple(float(rng.uniform(g["pitch_point_roll_deg"][i], g["eap_roll_deg"][i] - 0.25)) for i in range(2))
    return Microgeometry(tip_relief_um=tuple(rng.uniform(0.0, 40.0, 2)), tip_relief_start_roll_deg=starts,
                         profile_crown_um=tuple(rng.uniform(0.0, 10.0, 2)))


def run_microgeometry(case: dict, family: str = "microgeometry") -> Outcome:
    """Case keys: torque_Nm, face_width_factor, positions, smoothing_um, count_width_um (smooth loaded-contact
    count), initial_seed (None: the library's default start, the thesis minimum tip relief)."""
    torque = float(case.get("torque_Nm", DESIGN_TORQUE_NM))
    positions = int(case.get("positions", 20))

    def run():
        pair = pair_at(None, case.get("face_width_factor", 1.0))
        seed = case.get("initial_seed")
        initial = None if seed is None else _random_microgeometry(pair, np.random.default_rng(seed))
        limit = ltca(pair, torque, positions=positions).max_contact_stress_MPa
        design = optimise_microgeometry(pair, torque, positions=positions, check_positions=CHECK_POSITIONS,
                                        smoothing_um=case.get("smoothing_um", 0.05),
                                        count_width_um=case.get("count_width_um", DEFAULT_COUNT_WIDTH_UM),
                                        initial=initial, max_contact_stress_MPa=limit)
        exact = design.exact["optimised"][torque]
        numbers = np.array([exact.ppte_um, exact.max_contact_stress_MPa, exact.loaded_contact_ratio,
                            design.solve.objective] + list(design.values.values()), dtype=float)
        details = {"ppte_um": float(exact.ppte_um), "stress_ratio": float(exact.max_contact_stress_MPa / limit),
                   "loaded_contact_ratio": float(exact.loaded_contact_ratio)}
        if not np.all(np.isfinite(numbers)):
            return "untyped_failure", details, design.solve.iterations
        ok = (details["stress_ratio"] <= 1.0 + STRESS_REL_TOL
              and details["loaded_contact_ratio"] >= MIN_LOADED_CONTACT_RATIO - LCR_TOL)
        return ("solved" if ok else "check_failed"), details, design.solve.iterations

    return _classify(family, case, run, MICRO_CONSTRAINTS + PARAMETERS)


RUNNERS: dict[str, Callable[[dict, str], Outcome]] = {
    "shift_split_random": run_shift_split, "shift_split_extreme": run_shift_split,
    "microgeometry_random": run_microgeometry, "microgeometry_load": run_microgeometry,
    "microgeometry_smoothing": run_microgeometry}


def run_case(family: str, case: dict) -> Outcome:
    return RUNNERS[family](case, family)


# --------------------------------------------------------------------------- random families

def shift_split_random_cases(n: int, seed: int) -> list[dict]:
    rng = np.random.default_rng(seed)
    lo, hi = feasible_centre_distance_range()
    return [{"centre_distance_mm": float(rng.uniform(lo, hi)), "face_width_factor": float(rng.uniform(0.9, 1.1)),
             "shift_split": float(rng.uniform(0.0, 1.0)),
             "objective": ("max_min_tip_thickness", "balance_specific_sliding")[int(rng.integers(2))]}
            for _ in range(n)]


def shift_split_extreme_cases(n: int, seed: int, delta: float | None = 0.002) -> list[dict]:
    """Eight kinds in turn: the contact-ratio limit at the brute-force maximum - / + ``delta``, the tip thickness
    ratio likewise, the centre distance up to 0.01 mm inside each end of the feasible range, and 0.05 mm outside
    each end. ``delta=None`` draws it from U(0.0005, 0.02) (benchmark). ``expected`` says whether a feasible
    point exists (``"feasible"``/``"infeasible"``)."""
    rng = np.random.default_rng(seed)
    limits = split_limits(default_pair())
    lo, hi = feasible_centre_distance_range()
    cases = []
    for k in range(n):
        d = delta if delta is not None else float(rng.uniform(0.0005, 0.02))
        kind = k % 8
        sign = -1.0 if kind % 2 == 0 else 1.0
        expected = "feasible" if kind in (0, 2, 4, 5) else "infeasible"
        case: dict[str, Any] = {"shift_split": float(rng.uniform(0.0, 1.0)), "expected": expected}
        if kind < 2:
            case["min_contact_ratio"] = limits["max_contact_ratio"] + sign * d
        elif kind < 4:
            case["min_tip_thickness_ratio"] = limits["max_tip_thickness_ratio"] + sign * d
        elif kind < 6:
            case["centre_distance_mm"] = lo + float(rng.uniform(0.0, 0.01)) if sign < 0 else \
                hi - float(rng.uniform(0.0, 0.01))
        else:
            case["centre_distance_mm"] = lo - 0.05 if sign < 0 else hi + 0.05
        cases.append(case)
    return cases


def microgeometry_random_cases(n: int, seed: int) -> list[dict]:
    rng = np.random.default_rng(seed)
    return [{"torque_Nm": DESIGN_TORQUE_NM * float(rng.uniform(0.5, 1.5)),
             "face_width_factor": float(rng.uniform(0.9, 1.1)), "positions": int(rng.integers(20, 31)),
             "initial_seed": None if k % 2 == 0 else int(rng.integers(1 << 30))} for k in range(n)]


def microgeometry_load_cases(n: int, seed: int) -> list[dict]:
    rng = np.random.default_rng(seed)
    return [{"torque_Nm": float(np.exp(rng.uniform(np.log(5.0), np.log(3 * DESIGN_TORQUE_NM))))} for _ in range(n)]


def microgeometry_smoothing_cases(n: int, seed: int) -> list[dict]:
    rng = np.random.default_rng(seed)
    return [{"smoothing_um": float(np.exp(rng.uniform(np.log(0.005), np.log(0.05)))),
             "torque_Nm": DESIGN_TORQUE_NM * float(rng.uniform(0.5, 1.5))} for _ in range(n)]


FAMILIES: dict[str, Callable[[int, int], list[dict]]] = {
    "shift_split_random": shift_split_random_cases, "shift_split_extreme": shift_split_extreme_cases,
    "microgeometry_random": microgeometry_random_cases, "microgeometry_load": microgeometry_load_cases,
    "microgeometry_smoothing": microgeometry_smoothing_cases}


def assert_finite_or_typed(outcome: Outcome) -> None:
    """The stability contract: solved and re-checked, or a typed failure naming a constraint or parameter."""
    assert outcome.kind in ("solved", "typed_failure"), outcome.describe()


__all__ = [
    "FAMILIES",
    "KINDS",
    "Outcome",
    "assert_finite_or_typed",
    "default_pair",
    "feasible_centre_distance_range",
    "pair_at",
    "run_case",
    "shift_split_problem",
    "split_limits",
]

