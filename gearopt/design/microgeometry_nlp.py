"""Minimum peak-to-peak transmission error of one gear pair by profile modification: a thin client of the scene.

:func:`optimise_microgeometry` declares a :class:`~gearopt.design.scene.Scene` of one mesh -- design variables
(per gear, both gears) linear or parabolic tip relief amount C_a [um] and its start as a roll angle [deg], and
profile crown C_alpha [um]; objective the largest (or mean) PPTE over the load cases; limits at every load case:
Hertzian contact stress of every loaded slice, loaded transverse contact ratio, optionally root stress and contact
temperature -- and solves it with the scene's machinery: the exact screen and polish, Ipopt on the smooth LTCA, the
semi-infinite refinement against the exact LTCA (:mod:`gearopt.design.scene_refine`). It adds only what a stand-alone
pair needs: the default stress limit (the unmodified pair's), the loaded-contact count narrowed at light load
(:func:`narrowed_count_width`), and the exact-LTCA comparison with the unmodified pair and the thesis' minimum tip
relief (:func:`gearopt.design.positions.min_tip_relief_design`), so the reported numbers do not depend on the
smoothing.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from ..contact.ltca import LTCAResult, ltca
from ..contact.ltca_smooth import DEFAULT_COUNT_WIDTH_UM, DEFAULT_SMOOTHING_UM, LTCAModel
from ..contact.microgeometry import Microgeometry
from ..errors import GearoptInputError, SolveError
from ..geometry.pair import GearPair
from ..nlp.result import ProblemResult
from ..validation import check_range
from .positions import min_tip_relief_design
from .scene import Scene
from .scene_result import SceneResult
from .scene_spec import DesignVariable, Limit, LoadCase, Objective
from .scene_terms import QUANTITIES

GROUPS = ("tip_relief", "profile_crown")


@dataclass
class MicrogeometryDesign:
    """Result of :func:`optimise_microgeometry`: the optimum, the solve, and exact-LTCA comparisons.

    ``values``: the optimum by variable name (``tip_relief_1_um``, ``tip_relief_1_start_roll_deg``,
    ``profile_crown_1_um``, ... for gear 1 and 2); ``solve``: the chosen Ipopt solve (its objective is the scene's
    scaled objective; the PPTE in um is :attr:`ppte_um`); ``exact``: ``"unmodified"``, ``"min_tip_relief"``,
    ``"optimised"`` -> {torque: exact :class:`LTCAResult` at the check resolution}; ``starts``: one row per start
    (``start``, ``origin``, ``status``, ``success``, ``objective_um`` the exact objective of its refined design,
    ``exact_violation`` of the exact limits, ``chosen``, ``iterations``, ``count_width_um``); ``refinement``: the scene's refinement table; ``limits``: the requirements' limits;
    ``scene``: the :class:`~gearopt.design.scene_result.SceneResult` behind it (quantities, exact check, screen)."""

    microgeometry: Microgeometry
    values: dict                  # optimised amounts/starts with units in the keys
    solve: ProblemResult
    exact: dict                   # "unmodified", "min_tip_relief", "optimised" -> {torque: LTCAResult}
    torques_Nm: tuple
    starts: pd.DataFrame = field(default=None)
    table: pd.DataFrame = field(default=None)
    refinement: pd.DataFrame | None = field(default=None)
    limits: dict = field(default_factory=dict)
    scene: SceneResult | None = field(default=None, repr=False)

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


def optimise_microgeometry(pair: GearPair, torque_Nm: float | Sequence[float], *, driving_gear: int = 1,
                           groups: Sequence[str] = GROUPS, relief_shape: str = "linear",
                           aggregate: str = "max", max_contact_stress_MPa: float | None = None,
                           min_loaded_contact_ratio: float = 1.2, max_tip_relief_um: float = 40.0,
                           max_profile_crown_um: float = 10.0, start_margin_deg: float = 0.25,
                           stiffness: Any = "iso6336", positions: int = 40,
                           smoothing_um: float = DEFAULT_SMOOTHING_UM, count_width_um: float = DEFAULT_COUNT_WIDTH_UM,
                           relief_smoothing_deg: float = 0.1, check_positions: int = 1280, starts: int | None = None,
                           seed: int = 0, initial: Microgeometry | None = None,
                           max_root_stress_MPa: float | None = None, max_flash_temperature_C: float | None = None,
                           speed_rpm: float | None = None, bulk_temperature_C: float = 100.0,
                           friction_coefficient: float = 0.06, verbose: bool = False,
                           refine: bool = True, refine_tolerance: float = 0.02, max_refinements: int = 6,
                           stop_without_progress: bool = True, ltca_options: Mapping[str, Any] | None = None,
                           **ipopt) -> MicrogeometryDesign:
    """Minimise the PPTE of ``pair`` over tip relief (amounts and starts, both gears) and profile crown: the scene
    of the module docstring, solved by :meth:`~gearopt.design.scene.BuiltScene.solve`.

    Args:
        torque_Nm: design torque on the driving gear [N m], or a sequence of distinct load cases (the first is the
            design torque used in reports; the objective aggregates all).
        groups: which modifications are free: ``"tip_relief"`` (amount and start per gear), ``"profile_crown"``.
        aggregate: ``"max"`` (minimise the largest PPTE over the load cases) or ``"mean"``.
        max_contact_stress_MPa: limit of the LTCA Hertzian stress at every load case; default: the unmodified pair's
            exact maximum at the largest torque on the check grid (the modifications must not raise the peak stress).
        min_loaded_contact_ratio: lower limit of the loaded transverse contact ratio at every load case.
        max_tip_relief_um, max_profile_crown_um: upper bounds of the amounts [um]; ``start_margin_deg``: a relief
            start lies between the working pitch point and this far below the tip [deg].
        positions, smoothing_um, count_width_um, stiffness: the smooth LTCA of the NLP (mesh positions per base
            pitch, contact-law and loaded-contact-count widths [um], single-pair stiffness). At light load the count
            is narrowed when it refuses a pair the exact LTCA accepts (:func:`narrowed_count_width`;
            ``design.starts["count_width_um"]``).
        relief_smoothing_deg: blend of each relief start over about this roll angle (``Microgeometry``). It is part
            of the design: the exact-LTCA results use the same blended relief.
        check_positions: mesh positions of the exact-LTCA check (``design.exact``/``table``) and of the refinement.
        starts: Ipopt starts, the best designs of the scene's exact screen (default 1: the exact screen's best;
            with ``refine=False`` the declared start and Latin-hypercube points); ``design.starts`` tables them.
        initial: the declared start (default: the thesis minimum tip relief at the design torque,
            :func:`~gearopt.design.positions.min_tip_relief_design`); it joins the exact screen's candidates.
        max_root_stress_MPa: optional limit of the root stress of both gears at every loaded contact (the LTCA's
            ISO 6336-3 method B at the load point).
        max_flash_temperature_C: optional limit of the contact temperature (bulk + Blok flash); needs
            ``speed_rpm`` (of the driving gear), ``bulk_temperature_C`` and ``friction_coefficient``.
        refine, refine_tolerance, max_refinements, stop_without_progress: the semi-infinite refinement
            (:mod:`gearopt.design.scene_refine`): re-solve on the exact TE's peak positions while the smooth and
            exact PPTE differ by more than ``refine_tolerance``, at most ``max_refinements`` times, and (default)
            only while a re-solve lowers the best exact objective; then polish on the exact model; the starts come
            from the exact screen. ``refine=False``: the quick local answer -- one Ipopt solve on the ``positions``
            from the declared start (no screen, no refinement, no polish), checked by the exact LTCA.
        ltca_options: further options of the scene by their flat names
            (:class:`~gearopt.design.scene_options.LTCAOptions`), e.g. ``{"polish_evaluations_per_variable": 10}``;
            they override the arguments above.
        ipopt: extra Ipopt options (``max_iter`` ...).
    Raises a :class:`~gearopt.errors.SolveError` subclass naming the violated constraints if no start solves.
    """
    torques = tuple(float(t) for t in np.atleast_1d(np.asarray(torque_Nm, dtype=float)))
    for t in torques:
        check_range("torque_Nm", t, 0.0, None, low_inclusive=False, unit="N*m")
    if len(set(torques)) != len(torques):
        raise GearoptInputError(f"torque_Nm={list(torques)} repeats a load case: give each torque once")
    unknown = set(groups) - set(GROUPS)
    if unknown or not groups:
        raise GearoptInputError(f"groups={tuple(groups)!r} must be a non-empty subset of {GROUPS}")
    if aggregate not in ("max", "mean"):
        raise GearoptInputError(f"aggregate={aggregate!r} must be 'max' or 'mean'")
    check_range("min_loaded_contact_ratio", min_loaded_contact_ratio, 0.0, 3.0)
    if max_flash_temperature_C is not None and speed_rpm is None:
        raise GearoptInputError("max_flash_temperature_C needs speed_rpm (of the driving gear)")
    if starts is not None and (not isinstance(starts, (int, np.integer)) or starts < 1):
        raise GearoptInputError(f"starts={starts!r} must be an integer >= 1")
    check_opts = dict(driving_gear=driving_gear, stiffness=stiffness, positions=max(int(check_positions),
                                                                                    int(positions)))
    if max_flash_temperature_C is not None:
        check_opts.update(speed_rpm=speed_rpm, bulk_temperature_C=bulk_temperature_C,
                          friction_coefficient=friction_coefficient)
    unmodified = {t: ltca(pair, t, **check_opts) for t in torques}
    if max_contact_stress_MPa is None:
        # the unmodified pair's peak over the continuum of positions (check grid), not only at the NLP's samples
        max_contact_stress_MPa = unmodified[max(torques)].max_contact_stress_MPa
    check_range("max_contact_stress_MPa", max_contact_stress_MPa, 0.0, None, low_inclusive=False, unit="MPa")
    minimum = min_tip_relief_design(pair, torques[0], driving_gear=driving_gear)
    mesh = _mesh_name(pair)
    options = dict(positions=positions, smoothing_um=smoothing_um, count_width_um=count_width_um,
                   stiffness=stiffness, relief_smoothing_deg=relief_smoothing_deg, start_margin_deg=start_margin_deg,
                   check_positions=check_positions, refine_tolerance=refine_tolerance,
                   max_refinements=max_refinements, stop_without_progress=stop_without_progress,
                   **({} if refine else {"screen_samples": 0}),
                   bulk_temperature_C=bulk_temperature_C, friction_coefficient=friction_coefficient,
                   **dict(ltca_options or {}))
    scene = Scene("microgeometry", pairs={mesh: pair}, driving_gear=driving_gear,
                  load_cases=[LoadCase(f"{t:g}Nm", t, speed_rpm=speed_rpm) for t in torques],
                  variables=_variables(mesh, groups, initial, max_tip_relief_um, max_profile_crown_um),
                  objectives=[Objective("ppte_um", mesh, aggregate=aggregate)],
                  limits=_limits(mesh, max_contact_stress_MPa, min_loaded_contact_ratio, max_root_stress_MPa,
                                 max_flash_temperature_C),
                  microgeometry={mesh: Microgeometry(relief_shape=relief_shape)}, ltca_options=options)

    def solve(declared: Scene) -> SceneResult:
        return declared.build().solve(starts=starts, seed=seed, verbose=verbose, refine=refine, **ipopt)

    records = []
    try:
        result = solve(scene)
    except SolveError as exc:
        width = narrowed_count_width(pair, min(torques), min_loaded_contact_ratio, driving_gear=driving_gear,
                                     stiffness=stiffness, positions=positions, smoothing_um=smoothing_um,
                                     count_width_um=count_width_um)
        if width is None:
            raise
        records.append({"start": 0, "origin": "declared or screened", "status": exc.status, "success": False,
                        "objective_um": np.nan, "exact_violation": np.nan, "chosen": False, "iterations": np.nan,
                        "count_width_um": count_width_um})
        scene = _with_options(scene, count_width_um=width)     # every start again on the narrower count
        result = solve(scene)
    values = {name.split(".", 1)[1]: v for name, v in result.values.items()}
    current = result.microgeometry[mesh]
    exact = {"unmodified": unmodified,
             "min_tip_relief": {t: ltca(pair, t, microgeometry=minimum, **check_opts) for t in torques},
             "optimised": {t: ltca(pair, t, microgeometry=current, **check_opts) for t in torques}}
    final = [r.ppte_um for r in exact["optimised"].values()]
    records += _start_rows(result, len(records), scene.ltca_options["count_width_um"],
                           max(final) if aggregate == "max" else float(np.mean(final)))
    limits = {"contact_stress": float(max_contact_stress_MPa), "root_stress": max_root_stress_MPa,
              "flash_temperature": max_flash_temperature_C, "loaded_contact_ratio": min_loaded_contact_ratio}
    return MicrogeometryDesign(microgeometry=current, values=values, solve=result.solve, exact=exact,
                               torques_Nm=torques, starts=pd.DataFrame(records), table=comparison_table(exact, torques),
                               refinement=result.refinement, scene=result,
                               limits={k: v for k, v in limits.items() if v is not None})


def _mesh_name(pair: GearPair) -> str:
    """The scene's name of the pair's mesh: its gears' names joined (``"pinion-wheel"``)."""
    return f"{pair.names[0]}-{pair.names[1]}"


def _variables(mesh: str, groups, initial: Microgeometry | None, max_tip_relief_um: float,
               max_profile_crown_um: float) -> list[DesignVariable]:
    """The free modifications of both gears, started at ``initial`` where given (else the scene's default start,
    the minimum tip relief)."""
    out = []
    for i in (0, 1):
        n = i + 1
        if "tip_relief" in groups:
            start = None if initial is None else initial.tip_relief_start_roll_deg[i]
            out += [DesignVariable(f"tip_relief_{n}_um", mesh, 0.0, max_tip_relief_um,
                                   init=None if initial is None else float(initial.tip_relief_um[i])),
                    DesignVariable(f"tip_relief_{n}_start_roll_deg", mesh,
                                   init=None if start is None else float(start))]
        if "profile_crown" in groups:
            out.append(DesignVariable(f"profile_crown_{n}_um", mesh, 0.0, max_profile_crown_um,
                                      init=None if initial is None else float(initial.profile_crown_um[i])))
    return out


def _limits(mesh: str, max_contact_stress_MPa: float, min_loaded_contact_ratio: float,
            max_root_stress_MPa: float | None, max_flash_temperature_C: float | None) -> list[Limit]:
    out = [Limit("max_contact_stress_MPa", mesh, upper=float(max_contact_stress_MPa)),
           Limit("loaded_contact_ratio", mesh, lower=float(min_loaded_contact_ratio))]
    if max_root_stress_MPa is not None:
        out.append(Limit("max_root_stress_MPa", mesh, upper=float(max_root_stress_MPa)))
    if max_flash_temperature_C is not None:
        out.append(Limit("max_contact_temperature_C", mesh, upper=float(max_flash_temperature_C)))
    return out


def _with_options(scene: Scene, **options) -> Scene:
    return replace(scene, ltca_options={**scene.ltca_options, **options})


def _start_rows(result: SceneResult, first: int, count_width_um: float, final_um: float) -> list[dict]:
    """One row per start of the scene's solve: ``objective_um`` the exact objective [um] its refined design reached
    (``final_um``, the returned design's, for a single start), ``exact_violation`` and ``chosen`` (the best on the
    exact model: meeting every exact limit first, then the lowest objective)."""
    t = result.starts
    if t is None or "refined_exact_objective" not in t:
        origin = "single" if t is None else str(t["origin"].iloc[0])
        return [{"start": first, "origin": origin, "status": result.solve.status, "success": True,
                 "objective_um": final_um, "exact_violation": 0.0, "chosen": True,
                 "iterations": int(result.solve.iterations), "count_width_um": count_width_um}]
    scale = QUANTITIES["ppte_um"].scale          # the scene's objective is the PPTE over its scale
    return [{"start": first + k, "origin": str(t["origin"].iloc[k]), "status": t["status"].iloc[k],
             "success": bool(t["success"].iloc[k]), "objective_um": float(t["refined_exact_objective"].iloc[k]) * scale,
             "exact_violation": float(t["refined_exact_violation"].iloc[k]), "chosen": bool(t["chosen"].iloc[k]),
             "iterations": t["iterations"].iloc[k], "count_width_um": count_width_um} for k in range(len(t))]


COUNT_WIDTH_HALVINGS = 6
"""Most halvings of the smooth loaded-contact count's width by :func:`narrowed_count_width` (0.25 um -> 4 nm)."""


def narrowed_count_width(pair: GearPair, torque_Nm: float, min_loaded_contact_ratio: float, *,
                         driving_gear: int = 1, stiffness: Any = "iso6336", positions: int = 40,
                         smoothing_um: float = DEFAULT_SMOOTHING_UM,
                         count_width_um: float = DEFAULT_COUNT_WIDTH_UM) -> float | None:
    """A narrower width [um] of the smooth loaded-contact count, when that count refuses the unmodified pair at
    ``torque_Nm`` (below ``min_loaded_contact_ratio``) while the exact LTCA accepts it: at light load the mesh
    deflection is comparable with the count's width (0.25 um by default), the sigmoid counts closed springs as
    partly loaded and no design meets the limit. The width is halved (at most :data:`COUNT_WIDTH_HALVINGS` times)
    until the smooth count of the unmodified pair is within 1 % of the exact one. ``None`` when the smooth count is
    not to blame (the exact LTCA refuses the unmodified pair too, or the count already agrees)."""
    check_range("min_loaded_contact_ratio", min_loaded_contact_ratio, 0.0, 3.0)
    exact = float(ltca(pair, torque_Nm, driving_gear=driving_gear, stiffness=stiffness,
                       positions=positions).loaded_contact_ratio)
    model = LTCAModel(pair, driving_gear=driving_gear, stiffness=stiffness, positions=positions,
                      smoothing_um=smoothing_um, count_width_um=count_width_um)

    def smooth() -> float:
        return float(np.min(np.asarray(model.evaluate(Microgeometry(), [torque_Nm]).loaded_contact_ratio,
                                       dtype=float)))
    if exact < min_loaded_contact_ratio or smooth() >= min(min_loaded_contact_ratio, 0.99 * exact):
        return None
    for _ in range(COUNT_WIDTH_HALVINGS):
        model.count_width_um *= 0.5     # the same layout and kernels; the count's width is read when evaluated
        if smooth() >= 0.99 * exact:
            return model.count_width_um
    return None


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


__all__ = ["optimise_microgeometry", "MicrogeometryDesign", "min_tip_relief_design", "comparison_table",
           "narrowed_count_width"]
