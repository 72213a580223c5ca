"""Minimum peak-to-peak transmission error by profile modification: an Ipopt NLP over the smooth LTCA.

Design variables (per gear, both gears): linear or parabolic tip relief amount C_a [um] and its start as a roll
angle [deg], and profile crown C_alpha [um] (each group can be switched off). Objective: the PPTE at the design
torque, or the largest / mean PPTE over several load cases (a robust design over a torque range), written exactly
with epigraph variables (``t_hi >= TE_p >= t_lo`` per load case) so Ipopt owns the max/min.
Constraints at every load case:

- Hertzian contact stress of every loaded slice <= ``max_contact_stress_MPa`` (imposed on sigma^2, which is linear
  in the load: no square root in the NLP);
- loaded transverse contact ratio >= ``min_loaded_contact_ratio`` (the smooth count of
  :class:`~gearopt.contact.ltca_smooth.LTCAModel`);
- bounds on the amounts and on the starts (between the working pitch point and just below the tip).

The smooth LTCA is built once (:class:`LTCAModel`); the optimum is then re-evaluated with the exact numeric LTCA
(:func:`gearopt.contact.ltca.ltca`) and compared with the unmodified pair and the minimum tip relief of thesis
Eq. 3.38 (:func:`gearopt.contact.tip_relief.min_tip_relief_um`, linear relief from the highest point of single
contact), so the reported numbers do not depend on the smoothing.
"""

from __future__ import annotations

import copy

from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np
import pandas as pd

from .. import numerics as nm
from ..contact.layout import position_fractions
from ..contact.ltca import LTCAResult, ltca
from ..contact.ltca_smooth import DEFAULT_SMOOTHING_UM, LTCAModel
from ..contact.microgeometry import Microgeometry
from ..contact.tip_relief import min_tip_relief_um
from ..errors import GearoptInputError, SolveError
from ..validation import check_range
from ..geometry.pair import GearPair
from ..nlp.problem import Problem
from ..nlp.result import ProblemResult
from .positions import extreme_fractions, new_fractions, start_bounds

GROUPS = ("tip_relief", "profile_crown")
MIN_SMOOTHING_UM = 0.005
"""Smallest contact smoothing the refinement halves down to (the stability tests solve at 0.005 um)."""


@dataclass
class MicrogeometryDesign:
    """Result of :func:`optimise_microgeometry`: the optimum, the solve, and exact-LTCA comparisons."""

    microgeometry: Microgeometry
    values: dict                  # optimised amounts/starts with units in the keys
    solve: ProblemResult
    exact: dict                   # "unmodified", "min_tip_relief", "optimised" -> {torque: LTCAResult}
    torques_Nm: tuple
    starts: pd.DataFrame = field(default=None)
    table: pd.DataFrame = field(default=None)
    refinement: pd.DataFrame | None = field(default=None)
    limits: dict = field(default_factory=dict)   # the requirements' limits (the NLP may carry them tightened)

    @property
    def ppte_um(self) -> float:
        """The headline: the largest exact-LTCA PPTE of the optimum over its torque range [um] (the value at the
        first, design torque is :attr:`design_torque_ppte_um`)."""
        return max(r.ppte_um for r in self.exact["optimised"].values())

    @property
    def worst_torque_Nm(self) -> float:
        """The load case [N m] of the largest exact PPTE."""
        runs = self.exact["optimised"]
        return max(runs, key=lambda t: runs[t].ppte_um)

    @property
    def design_torque_ppte_um(self) -> float:
        """Exact-LTCA PPTE of the optimum at the first (design) torque [um]."""
        return self.exact["optimised"][self.torques_Nm[0]].ppte_um

    @property
    def worse_than_unmodified_Nm(self) -> list[float]:
        """Load cases [N m] at which the optimum's exact PPTE exceeds the unmodified pair's (flagged: a relief
        sized for the top of the range costs at its light end)."""
        opt, base = self.exact["optimised"], self.exact.get("unmodified", {})
        return sorted(t for t in opt if t in base and opt[t].ppte_um > base[t].ppte_um)


def min_tip_relief_design(pair: GearPair, torque_Nm: float, *, driving_gear: int = 1) -> Microgeometry:
    """The thesis' minimum tip relief (Eq. 3.38, amounts at the pitch point) as a linear relief starting at each
    gear's single-contact boundary next to its tip (the 'long' relief of the double-contact zone)."""
    amounts = min_tip_relief_um(pair, torque_Nm, driving_gear)
    g = pair.geometry()
    starts = tuple(max(float(g["lpstc_roll_deg"][i]), float(g["hpstc_roll_deg"][i])) for i in range(2))
    return Microgeometry(tip_relief_um=tuple(float(a) for a in amounts), tip_relief_start_roll_deg=starts,
                         relief_shape="linear")


def optimise_microgeometry(pair: GearPair, torque_Nm: float | Sequence[float], *, driving_gear: int = 1,
                           groups: Sequence[str] = GROUPS, relief_shape: str = "linear",
                           aggregate: str = "max", max_contact_stress_MPa: float | None = None,
                           min_loaded_contact_ratio: float = 1.2, max_tip_relief_um: float = 40.0,
                           max_profile_crown_um: float = 10.0, start_margin_deg: float = 0.25,
                           stiffness: Any = "iso6336", positions: int = 40,
                           smoothing_um: float = DEFAULT_SMOOTHING_UM, relief_smoothing_deg: float = 0.1,
                           check_positions: int = 1280, polish: bool = False, starts: Any = "load_cases", seed: int = 0, initial: Microgeometry | None = None,
                           max_root_stress_MPa: float | None = None, max_flash_temperature_C: float | None = None,
                           speed_rpm: float | None = None, bulk_temperature_C: float = 100.0,
                           friction_coefficient: float = 0.06, model: LTCAModel | None = None, verbose: bool = False,
                           refine: bool = True, refine_tolerance: float = 0.02, max_refinements: int = 6,
                           stop_without_progress: bool = True,
                           **ipopt) -> MicrogeometryDesign:
    """Minimise the PPTE of ``pair`` over tip relief (amounts and starts, both gears) and profile crown.

    Args:
        torque_Nm: design torque on the driving gear [N m], or a sequence of load cases (the first is the design
            torque used in reports; the objective aggregates all).
        groups: which modifications are free: ``"tip_relief"`` (amount and start per gear), ``"profile_crown"``.
        aggregate: ``"max"`` (minimise the largest PPTE over the load cases) or ``"mean"``.
        max_contact_stress_MPa: limit of the LTCA Hertzian stress at every load case; default: the unmodified pair's
            exact maximum at the largest torque (the modifications must not raise the peak stress).
        min_loaded_contact_ratio: lower limit of the loaded transverse contact ratio at every load case.
        relief_smoothing_deg: blend of each relief start over about this roll angle (``Microgeometry``; softplus).
            It is part of the design: the exact-LTCA results use the same blended relief, so the NLP objective and
            the reported PPTE agree to the contact smoothing. Without it the gaps have a kink wherever a sampled
            position crosses a start, and Ipopt needs hundreds of iterations. ``polish=True`` adds a second solve
            with sharp starts (relief_smoothing_deg = 0) from the blended optimum (slower, may stall).
        initial: starting microgeometry (default: the thesis minimum tip relief, :func:`min_tip_relief_design`).
        max_root_stress_MPa: optional limit of the root stress of both gears at every loaded contact (the LTCA's
            ISO 6336-3 method B at the load point).
        max_flash_temperature_C: optional limit of the contact temperature (bulk + Blok flash); needs
            ``speed_rpm`` (of the driving gear), ``bulk_temperature_C`` and ``friction_coefficient``.
        check_positions: mesh positions of the exact-LTCA check of the designs (``design.exact``/``table``): the
            NLP sees only its own ``positions`` samples, and a minimised PPTE is small, so the check runs at a
            converged resolution (benchmarks/results/ltca.json: 1280 positions keep a sub-micron PPTE within 1 %).
        starts: ``"load_cases"`` (default): one solve from ``initial`` and one from the minimum tip relief at each
            further load case (at the first load case too when ``initial`` is given); an integer n: n starts in
            total, Latin-hypercube points (``seed``) after those. The best optimum is returned; ``design.starts``
            tables every start (status, objective, iterations).
        model: a prebuilt :class:`LTCAModel` of the pair (reused, not rebuilt); else one is built.
        refine: semi-infinite refinement of the best optimum (:mod:`gearopt.design.scene_refine`): while the NLP's
            PPTE at its positions differs from the exact LTCA's at ``check_positions`` by more than
            ``refine_tolerance`` (relative, any load case), add the exact TE's peaks and troughs to the positions
            and re-solve from the optimum, at most ``max_refinements`` times (``design.refinement`` tables them);
            where the smooth model on the check grid itself differs by more than half the tolerance, the contact
            smoothing is halved (down to :data:`MIN_SMOOTHING_UM`). A limit the exact LTCA breaks
            (:func:`exact_limit_violations`) is tightened by 1.25 times the excess for the next solve. The design
            returned is the verified solve (PPTE agreement and every exact limit met) with the lowest exact PPTE,
            else one meeting the exact limits (``design.refinement.attrs``: ``status``, ``chosen``, ``verified``).
        stop_without_progress: end the re-solves as soon as one neither lowers the best exact objective meeting
            the exact limits by more than ``refine_tolerance`` nor gives the first such design (default: refine
            only while it pays; ``False`` re-solves until the smooth and exact PPTE agree or ``max_refinements``,
            which may find a slightly lower design much later. Measured on the packaged spur train's first mesh over
            150/300/450 N m: 6.2 CPU-s and 3.595 um against 49.5 CPU-s and 3.582 um; on the main job's three
            meshes 21.5 against 94 CPU-s, worst exact PPTE +0.02 %, +1.8 %, 0 %).
        ipopt: extra Ipopt options (``max_iter`` ...).
    Raises a :class:`~gearopt.errors.SolveError` subclass naming the violated constraints if Ipopt fails.
    """
    torques = tuple(float(t) for t in np.atleast_1d(np.asarray(torque_Nm, dtype=float)))
    for t in torques:
        check_range("torque_Nm", t, 0.0, None, low_inclusive=False, unit="N*m")
    unknown = set(groups) - set(GROUPS)
    if unknown or not groups:
        raise GearoptInputError(f"groups={tuple(groups)!r} must be a non-empty subset of {GROUPS}")
    if aggregate not in ("max", "mean"):
        raise GearoptInputError(f"aggregate={aggregate!r} must be 'max' or 'mean'")
    check_range("min_loaded_contact_ratio", min_loaded_contact_ratio, 0.0, 3.0)
    if max_flash_temperature_C is not None and speed_rpm is None:
        raise GearoptInputError("max_flash_temperature_C needs speed_rpm (of the driving gear)")
    model = model or LTCAModel(pair, driving_gear=driving_gear, stiffness=stiffness, positions=positions,
                               smoothing_um=smoothing_um, root_stress=max_root_stress_MPa is not None,
                               speed_rpm=speed_rpm if max_flash_temperature_C is not None else None,
                               bulk_temperature_C=bulk_temperature_C, friction_coefficient=friction_coefficient)
    if max_root_stress_MPa is not None and not model.root_stress:
        raise GearoptInputError("max_root_stress_MPa needs a model built with root_stress=True")
    exact_opts = dict(driving_gear=driving_gear, stiffness=model.layout.stiffness, positions=model.layout.positions,
                      slices=model.layout.slices)
    check_opts = dict(exact_opts, positions=max(int(check_positions), model.layout.positions))
    if max_contact_stress_MPa is None:
        # the unmodified pair's peak over the continuum of positions (check grid), not only at the NLP's samples:
        # a refined position set must not find the default limit infeasible
        max_contact_stress_MPa = ltca(pair, max(torques), **(check_opts if refine else exact_opts)
                                      ).max_contact_stress_MPa
    check_range("max_contact_stress_MPa", max_contact_stress_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    minimum = min_tip_relief_design(pair, torques[0], driving_gear=driving_gear)
    start = initial or minimum

    spec = dict(pair=pair, model=model, torques=torques, groups=tuple(groups), relief_shape=relief_shape,
                aggregate=aggregate, max_contact_stress_MPa=float(max_contact_stress_MPa),
                min_loaded_contact_ratio=min_loaded_contact_ratio, max_tip_relief_um=max_tip_relief_um,
                max_profile_crown_um=max_profile_crown_um, start_margin_deg=start_margin_deg, exact_opts=exact_opts,
                max_root_stress_MPa=max_root_stress_MPa, max_flash_temperature_C=max_flash_temperature_C)
    candidates = _starting_points(pair, torques, driving_gear, start, starts, spec, seed, minimum)
    records, best = [], None
    for attempt in range(2):
        for origin, guess in candidates:
            try:
                numbers, solved, current = _solve_from(spec, guess, relief_smoothing_deg, polish, relief_shape,
                                                       verbose, ipopt)
            except SolveError as exc:
                records.append({"start": origin, "status": exc.status, "objective_um": np.nan,
                                "iterations": np.nan, "success": False,
                                "count_width_um": spec["model"].count_width_um})
                best = best or (None, exc)
                continue
            records.append({"start": origin, "status": solved.status, "objective_um": solved.objective,
                            "iterations": solved.iterations, "success": True,
                            "count_width_um": spec["model"].count_width_um})
            if best is None or best[0] is None or solved.objective < best[0][1].objective:
                best = ((numbers, solved, current), None)
        narrowed = _narrowed_count_model(spec) if best[0] is None and attempt == 0 else None
        if narrowed is None:
            break
        spec = {**spec, "model": narrowed}      # every start again on the narrower count (light load)
        model = narrowed
    if best[0] is None:
        raise best[1]
    numbers, solved, current = best[0]
    refinement = None
    if refine:
        def rebuild(fractions, smoothing):
            old = spec["model"]
            return LTCAModel(pair, driving_gear=old.layout.driving_gear, stiffness=old.layout.stiffness,
                             positions=fractions, slices=old.layout.slices, smoothing_um=smoothing,
                             count_width_um=old.count_width_um, root_stress=old.root_stress,
                             speed_rpm=old.speed_rpm, bulk_temperature_C=bulk_temperature_C,
                             friction_coefficient=friction_coefficient)

        numbers, solved, current, refinement = _refine(
            spec, numbers, solved, current, rebuild, check_opts, refine_tolerance, max_refinements,
            lambda sp, guess: _solve_from(sp, guess, relief_smoothing_deg, polish, relief_shape, verbose, ipopt),
            stop_without_progress=stop_without_progress)
    exact = {"unmodified": {t: ltca(pair, t, **check_opts) for t in torques},
             "min_tip_relief": {t: ltca(pair, t, microgeometry=minimum, **check_opts) for t in torques},
             "optimised": {t: ltca(pair, t, microgeometry=current, **check_opts) for t in torques}}
    limits = {"contact_stress": spec["max_contact_stress_MPa"], "root_stress": spec.get("max_root_stress_MPa"),
              "flash_temperature": spec.get("max_flash_temperature_C"),
              "loaded_contact_ratio": spec["min_loaded_contact_ratio"]}
    design = MicrogeometryDesign(microgeometry=current, values=numbers, solve=solved, exact=exact, torques_Nm=torques,
                                 starts=pd.DataFrame(records), refinement=refinement,
                                 limits={k: v for k, v in limits.items() if v is not None})
    design.table = comparison_table(exact, torques)
    return design


def _refine(spec, numbers, solved, current, rebuild, check_opts, tolerance, max_refinements, solve_from,
            stop_without_progress: bool = False):
    """Exchange-method refinement of the NLP's mesh positions (as :mod:`gearopt.design.scene_refine` does for a scene)."""
    pair, torques, rows, solves = spec["pair"], spec["torques"], [], []
    check_positions = int(check_opts["positions"])
    grid = np.arange(check_positions) / check_positions
    for it in range(max_refinements + 1):
        model = spec["model"]
        te = np.asarray(model.evaluate(current, list(torques)).transmission_error_um, dtype=float)
        te = te.reshape(te.shape[0], -1)                                  # (positions, load cases)
        exact = [ltca(pair, t, microgeometry=current, **check_opts) for t in torques]
        errors = [abs(np.ptp(te[:, i]) - r.ppte_um) / max(r.ppte_um, 1e-12) for i, r in enumerate(exact)]
        dense = LTCAModel(pair, driving_gear=model.layout.driving_gear, stiffness=model.layout.stiffness,
                          positions=check_positions, slices=model.layout.slices, smoothing_um=model.smoothing_um)
        dense_te = np.asarray(dense.evaluate(current, list(torques)).transmission_error_um, dtype=float)
        dense_te = dense_te.reshape(dense_te.shape[0], -1)
        smoothing_error = max(abs(np.ptp(dense_te[:, i]) - r.ppte_um) / max(r.ppte_um, 1e-12)
                              for i, r in enumerate(exact))
        violations = exact_limit_violations(spec, exact)
        exact_ppte = [r.ppte_um for r in exact]
        prior_best = min((c[2] for c in solves if c[1]), default=None)   # best exact objective meeting the limits
        solves.append((max(errors) <= tolerance and not violations, not violations,
                       max(exact_ppte) if spec["aggregate"] == "max" else float(np.mean(exact_ppte)), it,
                       (numbers, solved, current)))
        rows.append({"iteration": it, "positions": model.layout.positions, "smoothing_um": model.smoothing_um,
                     "max_ppte_error": float(max(errors)), "smoothing_error": float(smoothing_error),
                     "exact_limit_violations": ", ".join(f"{k} {v:.4g}" for k, v in violations.items()),
                     "objective_um": float(solved.objective), "ipopt_iterations": int(solved.iterations)})
        if (max(errors) <= tolerance and not violations) or it == max_refinements:
            break
        if it > 0 and stop_without_progress and prior_best is not None and not (
                not violations and solves[-1][2] < prior_best - tolerance * max(abs(prior_best), 1e-12)):
            return _best_solve(rows, solves, f"stopped: re-solve {it} did not lower the best exact objective by "
                                             f"more than {100 * tolerance:g} % (stop_without_progress)")
        backoff = dict(spec.get("backoff", {}))
        for name, amount in violations.items():     # the smooth model missed the exact value by this much
            backoff[name] = backoff.get(name, 0.0) + 1.25 * amount
        spec = dict(spec, backoff=backoff)
        fractions = position_fractions(spec["exact_opts"]["positions"])
        new = new_fractions(fractions, [f for r in exact for f in extreme_fractions(r.transmission_error_um, grid)])
        smoothing = model.smoothing_um
        if smoothing_error > 0.5 * tolerance and smoothing > MIN_SMOOTHING_UM:
            smoothing = max(0.5 * smoothing, MIN_SMOOTHING_UM)    # the softplus lowers the TE by up to w ln 2
        if not new and smoothing == model.smoothing_um and not violations:
            break
        fractions = np.sort(np.concatenate([fractions, new]))
        spec = dict(spec, model=rebuild(fractions, smoothing), exact_opts=dict(spec["exact_opts"], positions=fractions))
        try:
            numbers, solved, current = solve_from(spec, current)
        except SolveError as exc:       # keep the best verified design, say why the refinement stopped
            return _best_solve(rows, solves, f"stopped: re-solve {it + 1} failed ({exc.status})")
    last = rows[-1]
    return _best_solve(rows, solves, "converged" if last["max_ppte_error"] <= tolerance and not last[
        "exact_limit_violations"] else "max_refinements reached")


def _best_solve(rows: list, solves: list, status: str):
    """The design the refinement returns: among the solves, a verified one (smooth PPTE within the tolerance and
    every limit met on the exact LTCA) with the lowest exact objective; else one meeting every exact limit; else the
    last. ``attrs``: ``status``, ``chosen`` (the solve's iteration), ``verified``."""
    verified = [c for c in solves if c[0]]
    feasible = [c for c in solves if c[1]]
    pick = min(verified or feasible, key=lambda c: c[2]) if (verified or feasible) else solves[-1]
    numbers, solved, current = pick[4]
    table = pd.DataFrame(rows)
    table.attrs.update(status=status, chosen=int(pick[3]), verified=bool(pick[0]))
    if not pick[1]:
        table.attrs["status"] += f"; the exact LTCA breaks {rows[pick[3]]['exact_limit_violations']}"
    return numbers, solved, current, table


EXACT_LIMIT_TOLERANCE = 1e-3
"""Relative slack of a limit on the exact LTCA before the refinement calls it broken."""


def exact_limit_violations(spec: dict, exact: Sequence) -> dict[str, float]:
    """By how much the exact LTCA results (one per load case) break the NLP's limits, in each limit's unit
    (loaded contact ratio, MPa, K), for those broken by more than :data:`EXACT_LIMIT_TOLERANCE` (relative). The
    smooth model can miss them: its loaded contact ratio counts a pair whose gap has just closed as partly loaded,
    and a stress peak may lie between its positions."""
    out = {}
    lcr = min(float(r.loaded_contact_ratio) for r in exact)
    if lcr < spec["min_loaded_contact_ratio"] * (1.0 - EXACT_LIMIT_TOLERANCE):
        out["loaded_contact_ratio"] = spec["min_loaded_contact_ratio"] - lcr
    checks = [("contact_stress", spec["max_contact_stress_MPa"], lambda r: r.max_contact_stress_MPa)]
    if spec.get("max_root_stress_MPa") is not None:
        checks.append(("root_stress", spec["max_root_stress_MPa"], lambda r: max(r.max_root_stress_MPa)))
    if spec.get("max_flash_temperature_C") is not None and getattr(exact[0], "speed_rpm", None) is not None:
        checks.append(("flash_temperature", spec["max_flash_temperature_C"], lambda r: r.max_flash_temperature_C))
    for name, limit, value in checks:
        worst = max(float(value(r)) for r in exact)
        if worst > limit * (1.0 + EXACT_LIMIT_TOLERANCE):
            out[name] = worst - limit
    return out


def _solve_from(spec, guess, relief_smoothing_deg, polish, relief_shape, verbose, ipopt):
    stages = [relief_smoothing_deg, 0.0] if (polish and relief_smoothing_deg > 0) else [relief_smoothing_deg]
    numbers, solved, current = None, None, guess
    for width in stages:
        p, values = _build_problem(spec, current, width)
        solved = p.solve(verbose=verbose, **ipopt)
        numbers = _clipped_values(p, solved, values)
        current = _numeric_mods(numbers, relief_shape, width)
    return numbers, solved, current


COUNT_WIDTH_HALVINGS = 6
"""Most halvings of the smooth loaded-contact count's width by :func:`_narrowed_count_model` (0.25 um -> 4 nm)."""


def _narrowed_count_model(spec):
    """A model like ``spec["model"]`` with a narrower smooth loaded-contact count, when the smooth count refuses the
    unmodified pair at the lightest torque (below the limit) while the exact LTCA accepts it: at light load the
    mesh deflection is comparable with the count's width (0.25 um by default), the sigmoid counts closed springs as
    partly loaded and no design meets the limit. The width is halved (at most :data:`COUNT_WIDTH_HALVINGS` times)
    until the smooth count of the unmodified pair is within 1 % of the exact one. ``None`` when the smooth count is
    not to blame (the exact LTCA refuses the unmodified pair too, or the count already agrees)."""
    model, pair, limit = spec["model"], spec["pair"], spec["min_loaded_contact_ratio"]
    torque = min(spec["torques"])
    exact = float(ltca(pair, torque, **spec["exact_opts"]).loaded_contact_ratio)

    def smooth(m) -> float:
        return float(np.min(np.asarray(m.evaluate(Microgeometry(), [torque]).loaded_contact_ratio, dtype=float)))
    if exact < limit or smooth(model) >= min(limit, 0.99 * exact):
        return None
    width = model.count_width_um
    for _ in range(COUNT_WIDTH_HALVINGS):
        width *= 0.5
        narrow = copy.copy(model)          # the same layout and kernels; the count's width is read when evaluated
        narrow.count_width_um = width
        if smooth(narrow) >= 0.99 * exact:
            return narrow
    return None


def _starting_points(pair, torques, driving_gear, first, starts, spec, seed,
                     minimum=None) -> list[tuple[str, Microgeometry]]:
    """The first guess, then the minimum tip relief at each load case ("load_cases"; at the first one too when the
    first guess is the caller's, ``minimum``: a given start that leads Ipopt to a point of local infeasibility does
    not fail the design), then Latin-hypercube points inside the variable bounds up to ``starts`` in total (an
    int)."""
    points = [("initial", first)]
    if minimum is not None and first is not minimum:
        points.append((f"min_tip_relief@{torques[0]:g}Nm", minimum))
    for t in torques[1:]:
        points.append((f"min_tip_relief@{t:g}Nm", min_tip_relief_design(pair, t, driving_gear=driving_gear)))
    if starts == "load_cases":
        return points
    if not isinstance(starts, int) or starts < 1:
        raise GearoptInputError(f"starts={starts!r} must be 'load_cases' or an integer >= 1")
    if starts <= len(points):
        return points[:starts]
    g = pair.geometry()
    bounds = [start_bounds(g, i, spec["start_margin_deg"]) for i in range(2)]
    lo = np.array([0.0, 0.0, bounds[0][0], bounds[1][0], 0.0])
    hi = np.array([spec["max_tip_relief_um"], spec["max_tip_relief_um"], bounds[0][1], bounds[1][1],
                   spec["max_profile_crown_um"]])
    n = starts - len(points)
    rng = np.random.default_rng(seed)
    u = (np.argsort(rng.random((n, 5)), axis=0) + rng.random((n, 5))) / n     # Latin hypercube in [0, 1)^5
    for k, x in enumerate(lo + u * (hi - lo)):
        points.append((f"latin_hypercube_{k}", Microgeometry(
            tip_relief_um=(x[0], x[1]), tip_relief_start_roll_deg=(x[2], x[3]), profile_crown_um=(x[4], x[4]),
            relief_shape=spec["relief_shape"])))
    return points


def _build_problem(spec: dict, start: Microgeometry, relief_smoothing_deg: float) -> tuple[Problem, dict]:
    """The NLP of :func:`optimise_microgeometry` started at ``start``; returns it and the design-variable
    expressions by name."""
    pair, model, torques, groups = spec["pair"], spec["model"], spec["torques"], spec["groups"]
    g = pair.geometry()
    p = Problem(name="microgeometry")
    kw: dict[str, Any] = {"relief_shape": spec["relief_shape"], "relief_smoothing_deg": relief_smoothing_deg}
    values: dict[str, Any] = {}
    if "tip_relief" in groups:
        bounds = [start_bounds(g, i, spec["start_margin_deg"]) for i in range(2)]
        amount = [p.variable(f"tip_relief_{i + 1}_um", init=float(start.tip_relief_um[i]), lower=0.0,
                             upper=spec["max_tip_relief_um"], scale=10.0, unit="um") for i in range(2)]
        s0 = [start.tip_relief_start_roll_deg[i] if start.tip_relief_start_roll_deg[i] is not None
              else 0.5 * sum(bounds[i]) for i in range(2)]
        roll = [p.variable(f"tip_relief_{i + 1}_start_roll_deg", init=float(np.clip(s0[i], *bounds[i])),
                           lower=bounds[i][0], upper=bounds[i][1], scale=1.0, unit="deg") for i in range(2)]
        kw.update(tip_relief_um=tuple(amount), tip_relief_start_roll_deg=tuple(roll))
        values.update({f"tip_relief_{i + 1}_um": amount[i] for i in range(2)})
        values.update({f"tip_relief_{i + 1}_start_roll_deg": roll[i] for i in range(2)})
    if "profile_crown" in groups:
        crown = [p.variable(f"profile_crown_{i + 1}_um", init=float(start.profile_crown_um[i]), lower=0.0,
                            upper=spec["max_profile_crown_um"], scale=1.0, unit="um") for i in range(2)]
        kw.update(profile_crown_um=tuple(crown))
        values.update({f"profile_crown_{i + 1}_um": crown[i] for i in range(2)})
    res = model.evaluate(Microgeometry(**kw), list(torques))
    P, L = model.layout.positions, len(torques)
    te = nm.reshape(res.transmission_error_um, P, L)
    start_te = np.column_stack([ltca(pair, t, microgeometry=start, **spec["exact_opts"]).transmission_error_um
                                for t in torques])
    hi = p.variable("te_max_um", init=start_te.max(axis=0), scale=5.0, unit="um", n=L)
    lo = p.variable("te_min_um", init=start_te.min(axis=0), scale=5.0, unit="um", n=L)
    p.subject_to("te_below_max", nm.repeat_rows(nm.row(hi), P) - te, lower=0.0, scale=1.0, unit="um")
    p.subject_to("te_above_min", te - nm.repeat_rows(nm.row(lo), P), lower=0.0, scale=1.0, unit="um")
    ppte = hi - lo
    if spec["aggregate"] == "max" and L > 1:
        z = p.variable("ppte_max_um", init=float(np.ptp(start_te, axis=0).max()), scale=5.0, unit="um")
        p.subject_to("ppte_below_max", z - ppte, lower=0.0, scale=1.0, unit="um")
        p.minimize(z, scale=5.0)
    else:
        p.minimize(nm.column_sum(ppte) / L, scale=5.0)
    on_path = np.flatnonzero(np.tile(model.layout.on_path.reshape(P, -1).T, (1, L)).reshape(-1, order="F"))
    backoff = spec.get("backoff", {})         # limit tightening by the exact model's past violations (_refine)
    limit = spec["max_contact_stress_MPa"] - backoff.get("contact_stress", 0.0)
    p.subject_to("contact_stress", _select(res.contact_stress_squared_MPa2, on_path), upper=limit ** 2,
                 scale=limit ** 2 / 100.0, unit="MPa^2")
    p.subject_to("loaded_contact_ratio", res.loaded_contact_ratio,
                 lower=spec["min_loaded_contact_ratio"] + backoff.get("loaded_contact_ratio", 0.0), scale=0.1)
    if spec.get("max_root_stress_MPa") is not None:
        lim = spec["max_root_stress_MPa"] - backoff.get("root_stress", 0.0)
        for g in (0, 1):
            p.subject_to(f"root_stress_{g + 1}", _select(res.root_stress_MPa[g], on_path), upper=lim,
                         scale=lim / 100.0, unit="MPa")
    if spec.get("max_flash_temperature_C") is not None:
        lim = spec["max_flash_temperature_C"] - res.bulk_temperature_C - backoff.get("flash_temperature", 0.0)
        if lim <= 0:
            raise GearoptInputError(f"max_flash_temperature_C={spec['max_flash_temperature_C']:g} C is not above "
                                    f"the bulk temperature {res.bulk_temperature_C:g} C")
        p.subject_to("flash_temperature_rise", _select(res.flash_temperature_rise_K, on_path), upper=lim,
                     scale=max(lim / 10.0, 1.0), unit="K")
    return p, values


def _clipped_values(p: Problem, solved: ProblemResult, values: dict) -> dict:
    """Optimal design values as floats, clipped into their bounds (Ipopt may end a hair outside)."""
    out = {}
    for name in values:
        entry = p._variables[name]
        v = float(np.asarray(solved.values[name]).reshape(-1)[0])
        out[name] = float(np.clip(v, entry.lower[0], entry.upper[0]))
    return out


def _select(matrix, flat_indices):
    col = nm.reshape(matrix, int(np.prod(matrix.shape)), 1)
    return col[flat_indices.tolist()]


def _numeric_mods(v: dict, shape: str, relief_smoothing_deg: float = 0.0) -> Microgeometry:
    kw: dict[str, Any] = {"relief_shape": shape, "relief_smoothing_deg": relief_smoothing_deg}
    if "tip_relief_1_um" in v:
        kw["tip_relief_um"] = (v["tip_relief_1_um"], v["tip_relief_2_um"])
        kw["tip_relief_start_roll_deg"] = (v["tip_relief_1_start_roll_deg"], v["tip_relief_2_start_roll_deg"])
    if "profile_crown_1_um" in v:
        kw["profile_crown_um"] = (v["profile_crown_1_um"], v["profile_crown_2_um"])
    return Microgeometry(**kw)


def comparison_table(exact: dict[str, dict[float, LTCAResult]], torques: Sequence[float]) -> pd.DataFrame:
    """Exact-LTCA comparison of designs per torque: PPTE, max contact stress, loaded contact ratio, max LID."""
    rows = []
    for name, by_torque in exact.items():
        for t in torques:
            r = by_torque[t]
            rows.append({"design": name, "torque_Nm": t, "ppte_um": r.ppte_um,
                         "max_contact_stress_MPa": r.max_contact_stress_MPa,
                         "loaded_contact_ratio": r.loaded_contact_ratio,
                         "max_load_intensity_N_per_mm": r.max_load_intensity_N_per_mm})
    return pd.DataFrame(rows)


__all__ = ["optimise_microgeometry", "MicrogeometryDesign", "min_tip_relief_design", "comparison_table"]
