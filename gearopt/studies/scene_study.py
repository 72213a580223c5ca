"""A scene's trade-off study in one call: its front, the sensitivity report of its optimum, its robustness.

:func:`scene_study` runs :func:`~gearopt.studies.pareto.pareto_front` against a second quantity,
solves the scene itself (best of ``starts``), reports its sensitivities
(:func:`~gearopt.studies.sensitivity.sensitivity_report`) and its Monte Carlo under the tolerances
(:func:`~gearopt.studies.monte_carlo.monte_carlo`); :meth:`SceneStudy.markdown` and :meth:`SceneStudy.headline`
give a report section and plain numbers. :func:`relief_scene_from_data` is the data's tip-relief scene of a mesh
(the design torque range and the design limits of ``[design_loads]`` / ``[design_limits]``).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from ..data import System, system_of
from ..design.scene import DesignVariable, Limit, LoadCase, Objective, Scene, SceneResult
from ..nlp import InitialGuessWarning
from .monte_carlo import MonteCarloResult, monte_carlo
from .pareto import ParetoFront, pareto_front
from ..errors import GearoptInputError
from .front_check import verify_front
from .sensitivity import SensitivityReport, sensitivity_report
from .tolerances import Tolerance

RELIEF = ("tip_relief_1_um", "tip_relief_2_um", "tip_relief_1_start_roll_deg", "tip_relief_2_start_roll_deg")


@dataclass
class SceneStudy:
    """``front``, ``optimum`` (the scene's own solve), ``sensitivity`` (of the optimum; ``None`` when the optimum is
    not a regular local optimum, with the reason in ``sensitivity_error``), ``monte_carlo`` (of the optimum under
    the tolerances)."""

    front: ParetoFront
    optimum: SceneResult
    sensitivity: SensitivityReport | None
    monte_carlo: MonteCarloResult
    sensitivity_error: str = ""

    def headline(self, rows: int = 5) -> dict[str, Any]:
        """Plain numbers: the front's ends and knee, the objective, the ``rows`` largest sensitivities, the
        probability of each limit being broken."""
        knee = self.front.knee()
        s = self.monte_carlo.summary
        limits = s[s["lower"].notna() | s["upper"].notna()]
        return {
            "front": {"quantity": self.front.quantity_column, "objective": self.front.objective_column,
                      "points": int(len(self.front.table)),
                      "failed": int((self.front.table["status"] != "ok").sum()), "ends": self.front.ends,
                      "knee": {c: float(knee[c]) for c in (self.front.objective_column, self.front.quantity_column)},
                      **self._front_checks()},
            "objective": ({"name": self.sensitivity.objective_name, "unit": self.sensitivity.objective_unit,
                           "value": self.sensitivity.objective, "exact_value": self.sensitivity.exact_objective}
                          if self.sensitivity is not None else {"value": float(self.optimum.solve.objective)}),
            "design": dict(self.optimum.values),
            "sensitivities": ([{k: (v if isinstance(v, str) else float(v)) for k, v in r.items()}
                               for r in self.sensitivity.table.head(rows)[
                                   ["name", "kind", "value", "unit", "sensitivity", "log_sensitivity"]]
                               .to_dict("records")] if self.sensitivity is not None else []),
            "sensitivity_note": (self.sensitivity.note if self.sensitivity is not None
                                 else f"not available: {self.sensitivity_error}"),
            # the exact re-check's probabilities where it was made (the smooth model's beside them)
            "probability_broken": {str(r["quantity"]): _probability_broken(r) for _, r in limits.iterrows()},
            "probability_broken_smooth": {str(r["quantity"]): float(r["probability_broken"])
                                          for _, r in limits.iterrows()},
            "exact_samples": int(self.monte_carlo.exact_samples),
            "samples": int(len(self.monte_carlo.table)),
            "tolerances": [t.__dict__ for t in self.monte_carlo.tolerances],
        }

    def _front_checks(self) -> dict[str, Any]:
        """The front's requirement and verification counts for the headline."""
        t, out = self.front.table, {"limit": self.front.limit}
        solved = t[t["status"] == "ok"]
        out["beyond_requirement"] = int((~self.front.feasible.loc[solved.index]).sum())
        if "verified" in t.columns:
            out["verified"] = int(solved["verified"].sum())
            v = solved[solved["verified"]]
            gap = (v["exact_objective"] - v[self.front.objective_column]) / v["exact_objective"].abs()
            out["largest_smooth_gap_percent"] = float(100 * gap.max()) if len(v) else None
        return out

    def markdown(self, figure: str | None = None, rows: int = 8) -> str:
        """A report section body: the front's ends and knee (and ``figure``, a relative path), the largest
        sensitivities, the robustness summary."""
        h = self.headline(rows)
        f = h["front"]
        lines = [f"Front of {f['objective']} against {f['quantity']} by ε-constraint continuation: {f['points']} "
                 f"points ({f['failed']} failed), from {f['ends']['objective']['objective']:.4g} at "
                 f"{f['ends']['objective']['quantity']:.4g} to {f['ends']['quantity']['objective']:.4g} at "
                 f"{f['ends']['quantity']['quantity']:.4g}; knee at {f['knee'][f['quantity']]:.4g} "
                 f"({f['knee'][f['objective']]:.4g}).", ""]
        if f.get("limit") is not None:
            lines += [f"The requirement on {f['quantity']} is {f['limit']:.4g}: {f['beyond_requirement']} point(s) lie "
                      f"beyond it (drawn hollow, not part of the front a design may choose from).", ""]
        if f.get("verified") is not None:
            lines += [f"{f['verified']} of {f['points'] - f['failed']} solved points verified by the exact LTCA "
                      f"(column `verified`; `exact_objective` is the verified design's exact value, drawn as x)"
                      + (f"; the smooth front is up to {f['largest_smooth_gap_percent']:.3g} % below the exact "
                         f"objective" if f.get("largest_smooth_gap_percent") is not None else "") + ".", ""]
        if figure:
            lines += [f"![front]({figure})", ""]
        if self.sensitivity is not None:
            note = f" {self.sensitivity.note}." if self.sensitivity.note else ""
            o = h["objective"]
            exact = (f", {o['exact_value']:.4g} {o['unit']} on the exact model at the reported design"
                     if np.isfinite(o["exact_value"]) else "")
            lines += [f"Sensitivities of the optimum -- local first-order estimates, exact only for small changes "
                      f"({o['name']} = {o['value']:.4g} {o['unit']} at the NLP's optimum{exact}; limits from the "
                      f"multipliers, data from the KKT system):{note}", "",
                      self.sensitivity.markdown(rows), ""]
        else:
            lines += [f"Sensitivities of the optimum: not available -- {self.sensitivity_error}", ""]
        mc = self.monte_carlo
        tol = ", ".join(f"{t.name} [{t.lower:+g}, {t.upper:+g}] ({t.distribution})" for t in mc.tolerances)
        cols = ["quantity", "unit", "nominal", "mean", "std", "p05", "p95", "lower", "upper", "probability_broken"]
        exact = ["exact_nominal", "exact_mean", "exact_probability_broken", "exact_probability_broken_se",
                 "smooth_error_max"]
        if mc.exact_samples:
            cols += exact
            how = (f"evaluated by the NLP's smooth model; the reported design and the first {mc.exact_samples} "
                   f"samples also by the exact LTCA (the `exact_` columns, with the probability's standard error, and "
                   f"the largest smooth-exact difference over those samples)")
        else:
            how = "evaluated by the NLP's smooth model" + (f" ({mc.exact_note})" if mc.exact_note else "")
        s = mc.summary[cols]
        lines += [f"Robustness: {len(mc.table)} {mc.method} samples (seed {mc.seed}) of {tol}, {how}:", "",
                  "| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
        for r in s.itertuples(index=False):
            cells = [r.quantity, r.unit] + [_cell(getattr(r, c)) for c in cols[2:]]
            lines.append("| " + " | ".join(cells) + " |")
        return "\n".join(lines)


def scene_study(scene: Scene, quantity: str, target: str, *, points: int = 9, samples: int = 1000, seed: int = 0,
                starts: int = 4, executor: Any = "serial", tolerances: Sequence[Tolerance] | None = None,
                verify: bool = True, verify_ltca_options: dict | None = None, exact_samples: int = 200,
                **ipopt: Any) -> SceneStudy:
    """Front of ``scene`` against ``quantity`` of ``target``, sensitivity report and Monte Carlo of its optimum
    (best of ``starts``, as the front's ends); see the module docstring. ``verify`` (default): every solved point
    of the front re-solved by the scene's exact-LTCA refinement (:func:`verify_front`, with
    ``verify_ltca_options``, default one re-solve): the table says which points verified and their exact
    objective. ``exact_samples``: Monte Carlo samples re-evaluated by the exact LTCA (:func:`monte_carlo`; at most
    ``samples``): the headline's ``probability_broken`` is theirs, the smooth model's ``probability_broken_smooth``
    beside it."""
    front = pareto_front(scene, quantity, target, points=points, executor=executor, starts=starts, **ipopt)
    if verify:
        front = front.with_verification(verify_front(front, scene, executor,
                                                     ltca_options=verify_ltca_options or {"max_refinements": 1},
                                                     **ipopt))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", InitialGuessWarning)
        optimum = scene.build().solve(starts=starts, **ipopt)
    report, error = None, ""
    try:
        report = sensitivity_report(optimum)
    except GearoptInputError as exc:  # not a regular local optimum: said in the study, the study goes on
        error = str(exc)
    mc = monte_carlo(optimum, samples=samples, seed=seed, executor=executor, tolerances=tolerances,
                     exact_samples=exact_samples)
    return SceneStudy(front, optimum, report, mc, error)


def relief_scene_from_data(system: System, train, mesh: str, *, positions: int | None = None,
                           ltca_options: dict | None = None) -> Scene:
    """The tip-relief scene of ``mesh`` of ``system`` (a :class:`~gearopt.data.System`; ``train`` a
    :class:`~gearopt.geometry.GearTrain` holding the mesh): the four relief variables, the largest PPTE over the
    design torque range (``[meshes.<mesh>] design_torque_Nm`` x ``[design_loads] torque_range_fractions``)
    minimised, the loaded contact ratio >= the requirement's ``min_loaded_contact_ratio`` and the largest contact
    stress not above the unmodified pair's own maximum over the range (exact LTCA). ``positions``: NLP positions of
    the smooth LTCA (default 40); ``ltca_options``: further scene LTCA options (e.g. ``max_refinements``,
    :data:`gearopt.design.scene.DEFAULT_LTCA_OPTIONS`)."""
    from ..contact.ltca import ltca

    system = system_of(system, "relief_scene_from_data")
    loads = system.section("design_loads", "relief_scene_from_data")
    design = system.design_torque_Nm(mesh)
    torques = [design * f for f in loads["torque_range_fractions"]]
    stress = max(ltca(train.pairs[mesh], t).max_contact_stress_MPa for t in torques)
    return Scene(f"{mesh} tip relief", train=train, load_cases=[LoadCase(f"T{t:g}", t) for t in torques],
                 variables=[DesignVariable(v, mesh) for v in RELIEF],
                 objectives=[Objective("ppte_um", mesh, aggregate="max")],
                 limits=[Limit("max_contact_stress_MPa", mesh, upper=stress),
                         Limit("loaded_contact_ratio", mesh, lower=system.requirements.min_loaded_contact_ratio)],
                 ltca_options={**({} if positions is None else {"positions": positions}), **(ltca_options or {})})


def _probability_broken(row) -> float:
    """A Monte Carlo summary row's probability of breaking its limit: the exact re-check's where it has one, else
    the smooth model's."""
    exact = float(row.get("exact_probability_broken", np.nan))
    return exact if np.isfinite(exact) else float(row["probability_broken"])


def _cell(v) -> str:
    if v is None or (isinstance(v, float) and np.isnan(v)):
        return ""
    return f"{float(v):.4g}"


__all__ = ["SceneStudy", "scene_study", "relief_scene_from_data"]
