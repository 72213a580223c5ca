"""The transcription of a built scene into one Ipopt NLP (:class:`SceneTranscription`): the declared design
variables, objectives and limits written into a :class:`~gearopt.nlp.problem.Problem` as expressions of the model
graph's models (geometry, ISO 6336, LTCA, joints, blanks) -- epigraph forms for maxima and PPTE, squared stresses,
joint margins with symbolic demands, a minimax of several objectives -- and the quantity table of any solve or
design.

The transcription checks the declaration's targets against the scene (meshes, flanks, joints of the data set, gears
of the train), declares the variables (their default bounds and starts from the present design), and records every
objective and limit quantity (``records``) in the order of the quantity table.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pandas as pd

from .. import numerics as nm
from ..errors import GearoptInputError, GeometryError, InfeasibleProblemError, ViolatedConstraint
from ..joints.walk_off import joint_margins
from ..nlp.result import ProblemResult
from .scene_contact import ContactModels
from .scene_models import TRAIN_TARGET, SceneModels
from .scene_spec import DesignVariable, Limit, LoadCase, Objective
from .scene_terms import QuantityKind, quantity_kind, variable_kind


SCREEN_MIN_ELEMENTS = 1000
"""A per-spring limit with at least this many elements (one mesh, one load case) is screened
(``spring_limit_screen``): the rows Ipopt sees are the springs near the limit, exchanged as the design moves.
Measured on the timing train's low-helix co-design (3 meshes x 4 load cases x 11 slices x 160 positions): 84 480
spring rows of 85 563, of which 1 143 lay within 20 % of their limits at the start; screened, the same optimum
(root shift 0.249188, largest exact PPTE 3.0324 um) in 66 s instead of 220 s, its build 13 s instead of 39 s. A
spur mesh (one slice, a few hundred springs per load case) is left whole: there Ipopt's linear algebra is cheap and
the exchange's different path led a tip-relief refinement (``tests/design/test_scene_codesign.py``) to another
sequence of local optima."""


class SceneTranscription:
    """The NLP of a build (module docstring), written from the model graph ``graph``
    (:class:`~gearopt.design.scene_models.SceneModels`) and its contact models ``contact``
    (:class:`~gearopt.design.scene_contact.ContactModels`) into ``graph.problem``; ``initial``: start values by
    ``"target.variable"`` (a warm start).

    Public interface: :meth:`transcribe` (the whole NLP, in order: targets checked, variables, start constraints,
    objectives, limits, the objective), its steps (:meth:`check_targets`, :meth:`declare_variables`,
    :meth:`start_constraints`, :meth:`add_objective`, :meth:`add_limit`), ``variables`` (``(target, name)`` ->
    symbol, shared with the graph), :attr:`variable_names`, :attr:`records`, :meth:`expressions`,
    :meth:`elements`, :meth:`cases`, :meth:`label`, :meth:`initial`, :meth:`quantity_table`,
    :meth:`quantities_at` and :meth:`evaluator_at`.
    """

    def __init__(self, graph: SceneModels, contact: ContactModels, initial: Mapping[str, float] | None = None):
        self.graph = graph
        self.contact = contact
        self.inputs = graph.inputs
        self.scene = graph.scene
        self.options = graph.options
        self.meshes = graph.meshes
        self.problem = graph.problem
        self.variables: dict[tuple[str, str], Any] = graph.variables
        self.initial_overrides: dict[str, float] = dict(initial or {})
        self._records: list[dict[str, Any]] = []
        self._objective_terms: list[Any] = []
        self._ppte_epigraphs: dict[str, Any] = {}

    # -- the NLP -------------------------------------------------------------------------------------------------

    def transcribe(self) -> None:
        """Write the scene's NLP: variables (macro ones first), the start constraints of free macro geometry, every
        objective and limit, and the objective (a sum, or with ``objective_aggregate="max"`` their largest)."""
        scene = self.scene
        self.declare_variables()
        self.start_constraints()
        for obj in scene.objectives:
            self.add_objective(obj)
        for lim in scene.limits:
            self.add_limit(lim)
        if not self._objective_terms:
            raise GearoptInputError(f"scene {scene.name!r} has no objective")
        terms = self._objective_terms
        if scene.objective_aggregate == "max" and len(terms) > 1:
            starts = [float(np.max(self.initial(t))) for t in terms]
            z = self.problem.variable("objectives.max", init=max(starts))
            self.problem.subject_to("objectives.max.epigraph", nm.vcat([z - t for t in terms]), lower=0.0)
            self.problem.minimize(z)
        else:
            self.problem.minimize(sum(terms[1:], terms[0]))

    @property
    def variable_names(self) -> list[str]:
        """The design variables as ``"target.variable"``, in declaration order."""
        return [f"{t}.{name}" for (t, name) in self.variables]

    @property
    def records(self) -> list[dict[str, Any]]:
        """Every objective and limit quantity as declared, in the order of the quantity table: ``label``,
        ``quantity``, ``target``, ``load_case``, ``kind`` (:class:`QuantityKind`), ``expr`` (its elements),
        ``lower``, ``upper``, ``role``."""
        return list(self._records)

    # -- targets and variables -----------------------------------------------------------------------------------

    def check_targets(self) -> None:
        """Every variable and quantity names a target of its kind in the scene; no mix of train-level and
        mesh-level macro variables; unique load case names."""
        scene = self.scene
        items = [("variable", v.name, v.target, variable_kind(v.name).target_kind) for v in scene.variables]
        items += [("quantity", q.quantity, q.target, quantity_kind(q.quantity).target_kind)
                  for q in (*scene.objectives, *scene.limits)]
        for what, name, target, kind in items:
            if kind == "train" and (target != TRAIN_TARGET or scene.train is None):
                raise GearoptInputError(f"{what} {name!r}: target={target!r} must be {TRAIN_TARGET!r} of a scene "
                                        f"with a train")
            if kind == "flank":
                self.contact.check_flank_target(what, name, target)
            if kind == "mesh" and target not in self.meshes:
                raise GearoptInputError(f"{what} {name!r}: target={target!r} is not a mesh of the scene "
                                        f"({sorted(self.meshes)})")
            if kind == "joint" and not self.inputs.has_joint(target):
                raise GearoptInputError(f"{what} {name!r}: target={target!r} is not a [joints.*] entry "
                                        f"({self.inputs.joint_names()})")
            if kind == "blank" and (scene.train is None or target not in scene.train.gears):
                gears = sorted(scene.train.gears) if scene.train is not None else []
                raise GearoptInputError(f"{what} {name!r}: target={target!r} is not a gear of the scene's train "
                                        f"({gears})")
        if any(variable_kind(v.name).target_kind == "train" for v in scene.variables) and any(
                variable_kind(v.name).group == "macro" for v in scene.variables):
            raise GearoptInputError("train-level and mesh-level macro variables in one scene are not supported: "
                                    "free the train's root_profile_shift/helix_angle_deg or a mesh's macro geometry")
        names = [lc.name for lc in scene.load_cases]
        if len(set(names)) != len(names):
            raise GearoptInputError(f"load case names {names} must be unique")

    def declare_variables(self) -> None:
        """Declare the variables, macro ones first (micro defaults depend on whether the macro geometry is free)."""
        out = self.variables
        order = {"train": 0, "macro": 1}
        for v in sorted(self.scene.variables, key=lambda v: order.get(variable_kind(v.name).group, 2)):
            kind = variable_kind(v.name)
            if (v.target, v.name) in out:
                raise GearoptInputError(f"design variable {v.name!r} of {v.target!r} is declared twice")
            lo, hi, init = self._variable_defaults(v, kind)
            lo = v.lower if v.lower is not None else lo
            hi = v.upper if v.upper is not None else hi
            if lo is None or hi is None:
                raise GearoptInputError(f"design variable {v.name!r} of {v.target!r} needs lower and upper bounds "
                                        f"[{kind.unit or '-'}]")
            init = v.init if v.init is not None else init
            init = self.initial_overrides.get(f"{v.target}.{v.name}", init)
            init = float(np.clip(init if init is not None else 0.5 * (lo + hi), lo, hi))
            out[(v.target, v.name)] = self.problem.variable(
                f"{v.target}.{v.name}", init=init, lower=lo, upper=hi, scale=v.scale or kind.scale, unit=kind.unit)

    def _variable_defaults(self, v: DesignVariable, kind) -> tuple[float | None, float | None, float | None]:
        """Default bounds and start of a variable from the target's present design."""
        lo, hi, init = kind.lower, kind.upper, None
        if kind.target_kind == "train":
            train = self.scene.train
            init = train.profile_shifts[train.root_gear] if v.name == "root_profile_shift" else train.helix_angle_deg
        elif kind.target_kind == "flank" or (kind.target_kind == "mesh" and kind.group == "micro"):
            lo, hi, init = self.contact.micro_bounds(v.target, v.name, kind)
        elif kind.target_kind == "mesh":
            pair = self.meshes[v.target]
            if kind.group == "macro":
                g = pair.geometry()
                i = 0 if v.name.endswith("1_mm") else 1
                init = {"profile_shift_1": pair.profile_shifts[0], "face_width_mm": pair.face_width_mm[0]}.get(
                    v.name, g["tip_diameter_mm"][i])
        elif kind.target_kind == "joint":
            j = self.inputs.joint_entry(v.target)
            key = kind.key or v.name
            if key not in j:
                raise GearoptInputError(f"design variable {v.name!r}: joint {v.target!r} ({j['joint_type']}) has "
                                        f"no {key!r}")
            init = j[key]
        else:
            init = getattr(self.graph.blank(v.target, symbolic=False), v.name)
        return lo, hi, (None if init is None else float(init))

    def start_constraints(self) -> None:
        """With free macro geometry, keep every free tip-relief start between the pitch point and the tip margin of
        the symbolic geometry of each mesh it acts in."""
        margin = self.options.model.start_margin_deg
        for mesh in self.contact.ltca_meshes():
            if not self.graph.macro_free(mesh):
                continue
            g = self.graph.geometry(mesh)
            for i in (0, 1):
                start = self.contact.free_micro(mesh, i, "tip_relief_start_roll_deg", None)
                if start is None:
                    continue
                label = f"{mesh}.tip_relief_start_{i + 1}_in_profile"
                self.problem.subject_to(f"{label}.above_pitch_point", start - g["pitch_point_roll_deg"][i], lower=0.0,
                                        unit="deg")
                self.problem.subject_to(f"{label}.below_tip", g["eap_roll_deg"][i] - margin - start, lower=0.0,
                                        unit="deg")

    # -- quantities ----------------------------------------------------------------------------------------------

    def expressions(self, quantity: str, target: str, load_cases: Sequence[str] | None = None
                    ) -> list[tuple[str, str, Any]]:
        """``(label, load case, expression)`` of a quantity of the vocabulary at each load case (one entry with
        load case ``""`` for a quantity not evaluated per load case): the elements as the NLP sees them (the TE
        column of ``ppte_um``, the squared stresses of a ``squared`` quantity), for studies that add their own
        constraints or objectives to ``problem``."""
        kind = quantity_kind(quantity)
        if kind.shape == "named":
            raise GearoptInputError(f"{quantity!r} is a set of limits, not one quantity")
        if kind.target_kind == "mesh" and target not in self.meshes:
            raise GearoptInputError(f"quantity {quantity!r}: target={target!r} is not a mesh of the scene "
                                    f"({sorted(self.meshes)})")
        return [(self.label(quantity, target, lc), lc.name if lc is not None else "",
                 self.elements(kind, target, lc, {})) for lc in self.cases(kind, load_cases)]

    def elements(self, kind: QuantityKind, target: str, lc: LoadCase | None, options: Mapping[str, Any]):
        """The quantity's expression: a scalar, a vector (shape max/min), the TE column (ppte) or a dict (named)."""
        name = kind.name
        if kind.target_kind == "mesh" and "ltca" in kind.needs:
            return self.contact.elements(name, target, lc)
        if kind.target_kind == "mesh" and "iso6336_rating" in kind.needs:
            sf = self.graph.rating(target, lc).safety_factors
            if name in ("contact_safety_factor", "root_safety_factor"):
                return nm.vcat(list(sf["S_H" if name == "contact_safety_factor" else "S_F"]))
            return sf["S_B" if name == "scuffing_safety_factor_flash" else "S_intS"]
        if kind.target_kind == "mesh" and "iso6336" in kind.needs:
            iso = self.graph.iso(target, lc)
            if name.startswith("root_"):
                key = "sigma_F_MPa" if name == "root_stress_iso6336_MPa" else "safety_factor"
                return nm.vcat([iso["root"][g][key] for g in ("gear1", "gear2")])
            key = "sigma_H_MPa" if name == "contact_stress_iso6336_MPa" else "safety_factor"
            return nm.vcat(list(iso["contact"][key]))
        if kind.target_kind == "mesh":
            g = self.graph.geometry(target)
            if name == "geometry_limits":
                return self.graph.pair(target).constraints(**dict(options))
            if name == "min_tip_thickness_mm":
                return nm.vcat(list(g["tip_thickness_mm"]))
            if name.startswith("tip_thickness_"):
                return g["tip_thickness_mm"][int(name[len("tip_thickness_")]) - 1]
            return g[name]
        if kind.target_kind == "joint":
            cap = self.graph.joint(target, lc)
            if not kind.per_load_case:
                return getattr(cap, name)
            torque_Nm, axial_N = self.graph.joint_torque_Nm(target, lc), self.graph.joint_axial_force_N(target, lc)

            def torque():   # a datum becomes a parameter only where a quantity uses it (Opti drops unused ones)
                return self.inputs.datum(f"joint_torque_Nm[{target}]@{lc.name}", torque_Nm, "N*m")

            def axial():
                return self.inputs.datum(f"joint_axial_force_N[{target}]@{lc.name}", axial_N, "N")
            if name == "torque_margin":
                return _margin(cap.torque_capacity_Nm, torque(), target, "torque", torque_Nm)
            if name == "axial_margin":
                return _margin(cap.axial_capacity_N, axial(), target, "axial force", axial_N)
            if name == "axial_utilisation":       # squared (scene_terms): smooth where the thrust vanishes
                return (axial() / cap.axial_capacity_N) ** 2
            return joint_margins(cap.type, torque(), axial(), cap.torque_capacity_Nm,
                                 cap.axial_capacity_N)["slip_utilisation"]
        blank = self.graph.blank(target)
        return blank.backup_ratio if name == "rim_backup_ratio" else getattr(blank, name)()

    def cases(self, kind: QuantityKind, only: Sequence[str] | None) -> list[LoadCase | None]:
        if not kind.per_load_case:
            return [None]
        cases = self.graph.load_cases
        if only is not None:
            missing = set(only) - {lc.name for lc in cases}
            if missing:
                raise GearoptInputError(f"load_cases {sorted(missing)} are not load cases of the scene")
            cases = [lc for lc in cases if lc.name in only]
        if not cases:
            raise GearoptInputError(f"quantity {kind.name!r} is evaluated per load case; the scene has none")
        return cases

    def initial(self, expr) -> np.ndarray:
        """Value of an expression at the problem's initial guess (starts of epigraph variables)."""
        if nm.is_numeric(expr):
            return np.atleast_1d(np.asarray(expr, dtype=float))
        opti = self.problem.opti
        return np.atleast_1d(np.asarray(opti.value(expr, opti.initial()), dtype=float)).ravel()

    def label(self, quantity: str, target: str, lc: LoadCase | None) -> str:
        return f"{quantity}[{target}]" + (f"@{lc.name}" if lc is not None else "")

    def _ppte(self, te, label: str):
        """PPTE of a TE column by its epigraph: hi >= te >= lo, PPTE = hi - lo (exact at a minimum or an upper limit).
        An objective and a limit on the same PPTE share one epigraph (hi - lo bounds the PPTE from above for both)."""
        if label in self._ppte_epigraphs:
            return self._ppte_epigraphs[label]
        start = self.initial(te)
        p, n = self.problem, int(np.size(start))
        hi = p.variable(f"{label}.te_max_um", init=float(start.max()), scale=5.0, unit="um")
        lo = p.variable(f"{label}.te_min_um", init=float(start.min()), scale=5.0, unit="um")
        p.subject_to(f"{label}.te_below_max", nm.repeat_rows(hi, n) - te, lower=0.0, unit="um")
        p.subject_to(f"{label}.te_above_min", te - nm.repeat_rows(lo, n), lower=0.0, unit="um")
        self._ppte_epigraphs[label] = hi - lo
        return hi - lo

    def add_objective(self, obj: Objective) -> None:
        kind = quantity_kind(obj.quantity)
        if kind.shape == "named":
            raise GearoptInputError(f"{obj.quantity!r} is a set of limits, not an objective")
        minimise = obj.sense == "min"
        if kind.name == "ppte_um_toleranced":
            raise GearoptInputError(f"objective {obj.quantity!r} on {obj.target!r}: the PPTE over the relief "
                                    f"tolerances is a limit (its NLP form is a bound the exact check verifies); "
                                    f"minimise 'ppte_um' and limit 'ppte_um_toleranced'")
        if (kind.shape in ("max", "ppte") and not minimise) or (kind.shape == "min" and minimise):
            raise GearoptInputError(f"objective {obj.quantity!r} with sense={obj.sense!r}: the {kind.shape} of a set "
                                    f"can only be {'minimised' if kind.shape != 'min' else 'maximised'} smoothly")
        per_case = []
        for lc in self.cases(kind, obj.load_cases):
            label = self.label(obj.quantity, obj.target, lc)
            expr = self.elements(kind, obj.target, lc, {})
            self._record(label, obj.quantity, obj.target, lc, kind, expr, None, None, "objective")
            if kind.shape == "ppte":
                f = self._ppte(expr, label)
            elif kind.shape in ("max", "min"):
                start = self.initial(expr)
                t = self.problem.variable(f"{label}.bound", init=float(start.max() if minimise else start.min()),
                                          scale=kind.scale ** (2 if kind.squared else 1), unit=kind.unit)
                n = int(np.size(start))
                gap = nm.repeat_rows(t, n) - expr if minimise else expr - nm.repeat_rows(t, n)
                self.problem.subject_to(f"{label}.epigraph", gap, lower=0.0, unit=kind.unit)
                f = nm.sqrt_safe(t, 1e-12) if kind.squared else t
            else:
                f = expr
            per_case.append(f)
        if len(per_case) == 1:
            f = per_case[0]
        elif obj.aggregate == "mean":
            f = sum(per_case[1:], per_case[0]) / len(per_case)
        else:
            label = f"{obj.quantity}[{obj.target}].{'max' if minimise else 'min'}_over_load_cases"
            starts = [float(self.initial(x).max()) for x in per_case]
            z = self.problem.variable(label, init=max(starts) if minimise else min(starts), scale=kind.scale,
                                      unit=kind.unit)
            gap = nm.vcat([z - x if minimise else x - z for x in per_case])
            self.problem.subject_to(f"{label}.epigraph", gap, lower=0.0, unit=kind.unit)
            f = z
        scale = obj.scale or kind.scale
        self._objective_terms.append((obj.weight / scale) * (f if minimise else -f))

    def add_limit(self, lim: Limit) -> None:
        kind = quantity_kind(lim.quantity)
        if kind.shape == "named":
            margins = self.elements(kind, lim.target, None, lim.options)
            for name, expr in margins.items():
                label = f"{lim.target}.{name}"
                if not nm.is_symbolic(expr):       # a margin no design variable moves: checked here, not carried
                    value = nm.to_float(expr)
                    if value < 0.0:
                        raise GeometryError(f"limit {label} = {value:.6g} < 0 at the scene's fixed geometry (no "
                                            f"design variable of the scene moves it)")
                    continue
                self._record(label, name, lim.target, None, kind, expr, 0.0, None, "limit")
                self.problem.subject_to(label, expr, lower=0.0, unit="mm" if name.endswith("_mm") else "")
            return
        if kind.shape in ("max", "ppte") and lim.lower is not None:
            raise GearoptInputError(f"Limit {lim.quantity!r}: a lower limit on the largest value of a set is not a "
                                    f"smooth constraint; give an upper limit")
        if kind.shape == "min" and lim.upper is not None:
            raise GearoptInputError(f"Limit {lim.quantity!r}: an upper limit on the smallest value of a set is not a "
                                    f"smooth constraint; give a lower limit")
        for lc in self.cases(kind, lim.load_cases):
            label = self.label(lim.quantity, lim.target, lc)
            if self._add_margin_limit(lim, kind, lc, label):
                continue
            if kind.name == "ppte_um_toleranced" and self.options.tolerance.toleranced_ppte_lazy \
                    and label not in dict(self.options.limit_backoff):
                continue     # lazy: carried once an exact check breaks it (the refinement's back-off names it)
            expr = self.elements(kind, lim.target, lc, lim.options)
            self._record(label, lim.quantity, lim.target, lc, kind, expr, lim.lower, lim.upper, "limit")
            if kind.shape == "ppte":
                expr = self._ppte(expr, label)
            lower, upper, scale, unit = lim.lower, lim.upper, kind.scale, kind.unit
            if lower is not None:   # tightened by the refinement where the exact LTCA broke it (scene_refine)
                lower = lower + self.options.backoff(label)
            elif kind.name == "ppte_um_toleranced":
                upper = upper - self.options.backoff(label)
            if kind.squared:
                upper, scale, unit = upper ** 2, upper ** 2 / 100.0, f"({unit})^2"
            if nm.is_numeric(expr) or not self.problem.depends_on_variables(expr):   # data only (parametric)
                _check_constant(label, self.initial(expr), lower, upper, unit)
                continue
            screen, fraction = None, self.options.model.spring_limit_screen
            if fraction is not None and kind.shape == "max" and upper is not None \
                    and int(expr.numel()) >= SCREEN_MIN_ELEMENTS:
                screen = fraction * abs(upper)
            if kind.name == "ppte_um_toleranced":      # a variant's LTCA enters Ipopt only when it can bind
                screen = self.options.tolerance.toleranced_ppte_screen * abs(upper)
            self.problem.subject_to(label, expr, lower=lower, upper=upper, scale=scale, unit=unit, screen=screen)

    def _add_margin_limit(self, lim: Limit, kind: QuantityKind, lc: LoadCase, label: str) -> bool:
        """A lower limit S on a joint margin whose demand is symbolic (walk-off through a free helix angle):
        ``capacity^2 - S^2 demand^2 >= 0`` (smooth also where the demand vanishes); S <= 0 always holds and is only
        recorded (a loose bound, e.g. a trade-off front's). False when not applicable."""
        if kind.name not in ("axial_margin", "torque_margin") or lim.lower is None or lim.upper is not None:
            return False
        demand = (self.graph.joint_axial_force_N if kind.name == "axial_margin" else self.graph.joint_torque_Nm)(lim.target, lc)
        if not nm.is_symbolic(demand):
            return False
        cap = getattr(self.graph.joint(lim.target, lc),
                      "axial_capacity_N" if kind.name == "axial_margin" else "torque_capacity_Nm")
        ratio = cap / nm.fmax(nm.sqrt(demand * demand), 1e-9)
        self._record(label, lim.quantity, lim.target, lc, kind, ratio, lim.lower, None, "limit")
        if lim.lower <= 0.0:
            # a capacity is >= 0, so the limit always holds; squaring it would turn it into |demand| <= cap/|S|
            return True
        c0 = float(np.max(self.initial(cap)))
        self.problem.subject_to(label, (cap * cap - lim.lower ** 2 * demand * demand) / c0 ** 2, lower=0.0)
        return True

    def _record(self, label, quantity, target, lc, kind, expr, lower, upper, role) -> None:
        self._records.append({"label": label, "quantity": quantity, "target": target,
                              "load_case": lc.name if lc is not None else "", "kind": kind, "expr": expr,
                              "lower": lower, "upper": upper, "role": role})

    def quantities_at(self, values: Mapping[str, float]) -> pd.DataFrame:
        """Every objective and limit quantity of the smooth models at a design (``"target.variable"`` values; the
        table of :attr:`SceneResult.quantities`): e.g. two designs compared on one model."""
        missing = {f"{t}.{n}" for (t, n) in self.variables} - set(values)
        if missing:
            raise GearoptInputError(f"quantities_at: values miss {sorted(missing)}")
        return self.quantity_table(None, self.evaluator_at(values))

    def evaluator_at(self, values: Mapping[str, float]) -> Callable:
        """``expr -> value`` of expressions of the design variables at ``values`` (``"target.variable"`` keys)."""
        opti = self.problem.opti
        at = [self.problem._variables[k].symbol == values[k] / self.problem._variables[k].scale[0]
              for k in (f"{t}.{n}" for (t, n) in self.variables)]
        completion = self.problem.start_completion    # dependent variables (lifted contact approaches) at the design
        if completion is not None:
            for name, value in completion(dict(values)).items():
                entry = self.problem._variables[name]
                at.append(entry.symbol == np.asarray(value, dtype=float).reshape(-1) / entry.scale)
        return lambda expr: opti.value(expr, at)

    def quantity_table(self, solved: ProblemResult | None, evaluate: Callable | None = None) -> pd.DataFrame:
        """The quantity table (as ``SceneResult.quantities``) at a solve of ``problem`` or, with ``evaluate``
        (``expr -> value``), at any design."""
        evaluate = evaluate or solved.value
        rows = []
        # one evaluation of every record: the models they share (each mesh's LTCA) run once, not once per record
        for r, v in zip(self._records, nm.evaluate_stacked(evaluate, [r["expr"] for r in self._records])):
            kind = r["kind"]
            if kind.squared:
                v = np.sqrt(np.maximum(v, 0.0))
            value = {"ppte": np.ptp(v), "max": np.max(v), "min": np.min(v)}.get(kind.shape, float(v.ravel()[0]))
            lo, hi = r["lower"], r["upper"]
            margin = min(value - lo if lo is not None else np.inf, hi - value if hi is not None else np.inf)
            rows.append({"quantity": r["quantity"], "target": r["target"], "load_case": r["load_case"],
                         "role": r["role"], "value": float(value), "lower": lo, "upper": hi,
                         "margin": float(margin) if r["role"] == "limit" else np.nan,
                         "unit": kind.unit if kind.shape != "named" else ""})
        return pd.DataFrame(rows)


def _check_constant(label: str, expr, lower, upper, unit: str) -> None:
    """A limit on a quantity no design variable changes: it holds (nothing to impose) or the scene is infeasible."""
    v = np.atleast_1d(np.asarray(expr, dtype=float)).ravel()
    lo = -np.inf if lower is None else lower
    hi = np.inf if upper is None else upper
    excess = np.maximum(lo - v, 0.0) + np.maximum(v - hi, 0.0)
    if np.any(excess > 0.0):
        i = int(np.argmax(excess))
        raise InfeasibleProblemError(
            f"limit {label!r} does not depend on the design variables and is violated ({v[i]:g} {unit} against "
            f"[{lo:g}, {hi:g}])", status="constant constraint violated",
            hint="free a variable that changes this quantity, or change the data",
            violated=[ViolatedConstraint(label, float(excess[i]), float(v[i]), float(lo), float(hi), "scene")])


def _margin(capacity, demand, joint: str, what: str, nominal):
    """``capacity / |demand|``; ``nominal``: the demand's value (``demand`` may be its parameter)."""
    if nm.is_numeric(nominal) and nm.to_float(nominal) == 0.0:
        raise GearoptInputError(f"joint {joint!r}: the {what} demand is zero, its margin is infinite (drop the limit)")
    return capacity / abs(demand)


__all__ = ["SceneTranscription"]
