"""Scenes: a declared study that builds only the models its quantities need, builds each once, and says what it built.

A :class:`Scene` names the gears or meshes, the load cases, the design variables with bounds, the objectives and the
limits (:mod:`gearopt.design.scene_spec`), in the vocabulary of :mod:`gearopt.design.scene_terms`. ``scene.build()``
resolves the chain of models behind each requested quantity -- PPTE needs the smooth LTCA, which needs the stiffness,
the microgeometry and the geometry; a contact-ratio limit needs the geometry only; a dynamic load case needs the
timing model and one simulation -- builds each once, and turns the scene into one Ipopt NLP
(:class:`~gearopt.nlp.problem.Problem`). Nothing else is built: no LTCA for a geometry-only scene, no dynamics
unless a load case asks for it, one face slice for a spur pair without lead modification, only the targets named.
``built.built`` lists the models in build order; ``built.build_table`` adds details and build times.

Example (robust PPTE of one mesh over a torque range)::

    scene = Scene("crank-cam micro", train=go.load_default_train("spur"),
                  load_cases=[LoadCase("low", 150.0), LoadCase("design", 300.0), LoadCase("high", 450.0)],
                  variables=[DesignVariable(v, "crank-cam") for v in ("tip_relief_1_um", "tip_relief_2_um",
                             "tip_relief_1_start_roll_deg", "tip_relief_2_start_roll_deg")],
                  objectives=[Objective("ppte_um", "crank-cam", aggregate="max")],
                  limits=[Limit("max_contact_stress_MPa", "crank-cam", upper=1100.0),
                          Limit("loaded_contact_ratio", "crank-cam", lower=1.2)])
    built = scene.build()
    built.built          # ['geometry:crank-cam', 'ltca_smooth:crank-cam', 'ltca_evaluation:crank-cam']
    result = built.solve()
    result.values, result.quantities, result.exact_check

Co-design (macro and micro geometry in one NLP): train-level variables (``DesignVariable("root_profile_shift",
"train", ...)``, ``DesignVariable("helix_angle_deg", "train", ...)``) make every mesh of the train symbolic at its
fixed centre distance, and a mesh with LTCA quantities then uses the macro-symbolic smooth LTCA
(:mod:`gearopt.design.scene_contact`); micro variables may target a gear flank (``"cam:driving"``) shared by every
mesh that loads it; joint margins take their axial demand from the mesh forces and the helix angle
(:mod:`gearopt.design.scene_train`).

PPTE over the mesh cycle is a minimax over a continuum of positions: :meth:`BuiltScene.solve` solves on a coarse set
of positions, re-evaluates the optimum by the exact LTCA and adds the exact TE's peak and trough positions until the
smooth and exact PPTE agree within ``refine_tolerance`` (:mod:`gearopt.design.scene_refine`;
``SceneResult.refinement`` tables the iterations). Contact temperature needs one speed for all load cases of a mesh
(the LTCA model is built for one speed).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pandas as pd

from ..contact.ltca_macro import DEFAULT_ENGAGEMENT_WIDTH_MM
from ..contact.ltca_smooth import DEFAULT_SMOOTHING_UM
from ..contact.microgeometry import Microgeometry
from .. import numerics as nm
from ..errors import GearoptInputError
from ..geometry.pair import GearPair
from ..geometry.train import GearTrain
from ..nlp.problem import Problem
from ..nlp.result import ProblemResult
from .scene_contact import ContactModels
from .scene_quantities import QuantityTerms
from .scene_spec import DesignVariable, Limit, LoadCase, Objective
from .scene_terms import quantity_kind, variable_kind
from .scene_train import TRAIN_TARGET, TrainModels

DEFAULT_LTCA_OPTIONS: dict[str, Any] = {
    "positions": 40, "smoothing_um": DEFAULT_SMOOTHING_UM, "stiffness": "iso6336", "relief_smoothing_deg": 0.1,
    "bulk_temperature_C": 100.0, "friction_coefficient": 0.06, "check_positions": 1280, "start_margin_deg": 0.25,
    "helical_slices": 11, "engagement_width_mm": DEFAULT_ENGAGEMENT_WIDTH_MM, "root_rotation": "cw",
    "refine_tolerance": 0.02, "max_refinements": 6, "max_helical_slices": 41, "min_smoothing_um": 0.005,
    "refine_abs_tolerance_um": 0.01, "refine_stress_tolerance": 0.01,
    "refine_neighbours": 3, "approach": "nested"}
"""LTCA settings of a scene (override per scene with ``ltca_options``): the NLP's initial uniform positions and
contact smoothing (:class:`~gearopt.contact.ltca_smooth.LTCAModel`), the relief-start blend of the design, the oil
temperature and friction of the flash temperature, the positions of the exact-LTCA check of the optimum
(benchmarks/results/ltca.json); for free macro geometry the face slices of a possibly helical mesh and the
engagement width (:class:`~gearopt.contact.ltca_macro.MacroLTCAModel`); the crank's sense of rotation seen from the
front (walk-off); and the semi-infinite refinement: relative PPTE agreement of smooth and exact model (with an absolute floor) and of their
stress and temperature maxima (``refine_stress_tolerance``), the most
re-solves, the most face slices it may raise a helical mesh to, the smallest contact smoothing it may halve down to
and the grid neighbours added on either side of each worst position (:mod:`gearopt.design.scene_refine`);
``approach``: ``"nested"`` (Newton's method inside the model, as the macro-symbolic LTCA does) or ``"lifted"`` (a
mesh at fixed macro geometry: each position's approach an NLP variable held by an equality constraint; cheaper
iterations, same optima, but from the same start it may reach another local optimum, so it is opt-in)."""


@dataclass
class Scene:
    """A declared optimal-design study (see the module docstring).

    Args:
        name: scene name (problem name in reports).
        train: the gear train whose meshes (``train.pairs``) and gears the targets name; or give ``pairs``.
        pairs: mesh name -> :class:`GearPair` (instead of, or in addition to, ``train``).
        load_cases: :class:`LoadCase` list; per-load-case quantities are evaluated at each.
        variables, objectives, limits: :class:`DesignVariable`, :class:`Objective`, :class:`Limit` lists.
        microgeometry: fixed modifications per mesh (free ones come from ``variables``).
        driving_gear: 1 or 2, per mesh (mapping) or for all.
        data: the data set of joints and blanks (default: the packaged default data).
        ltca_options: overrides of :data:`DEFAULT_LTCA_OPTIONS`; iso6336_options: keyword arguments of
            :func:`~gearopt.rating.contact_stress_iso6336` / :func:`~gearopt.rating.root_stress_iso6336` (K_A, ...).
        objective_aggregate: how several objectives combine: ``"sum"`` (their weighted, scaled sum) or ``"max"``
            (the largest of them, by an epigraph variable ``objectives.max``: e.g. the largest PPTE of several
            meshes, each objective divided by its scale and multiplied by its weight). A pure minimax: the
            objectives below the largest are left wherever its optimum puts them.
    """

    name: str
    train: GearTrain | None = None
    pairs: Mapping[str, GearPair] | None = None
    load_cases: Sequence[LoadCase] = ()
    variables: Sequence[DesignVariable] = ()
    objectives: Sequence[Objective] = ()
    limits: Sequence[Limit] = ()
    microgeometry: Mapping[str, Microgeometry] = field(default_factory=dict)
    driving_gear: int | Mapping[str, int] = 1
    data: dict | None = None
    ltca_options: Mapping[str, Any] = field(default_factory=dict)
    iso6336_options: Mapping[str, Any] = field(default_factory=dict)
    objective_aggregate: str = "sum"

    def meshes(self) -> dict[str, GearPair]:
        out = dict(self.train.pairs) if self.train is not None else {}
        out.update(self.pairs or {})
        return out

    def needs(self) -> dict[str, set[str]]:
        """Model families each target needs (target -> families), from the requested quantities, without building
        anything."""
        out: dict[str, set[str]] = {}
        for item in (*self.objectives, *self.limits):
            out.setdefault(item.target, set()).update(quantity_kind(item.quantity).needs)
        for v in self.variables:
            out.setdefault(v.target, set())
        return out

    def build(self, *, positions: Mapping[str, Any] | None = None,
              initial: Mapping[str, float] | None = None, parametric: bool = False) -> "BuiltScene":
        """Build the models the scene needs (each once) and its NLP; see :class:`BuiltScene` (``positions``: mesh
        positions per mesh, e.g. ``SceneResult.positions`` of a related scene; ``initial``: start values by
        ``"target.variable"``, e.g. its ``SceneResult.values`` -- a warm start of both the design and the
        semi-infinite refinement). ``parametric``: the data the quantities use (load-case torques and joint demands,
        the oil temperature and the friction coefficient of contact temperatures) enter the NLP as
        :class:`Problem` parameters named like ``torque_Nm[crank-cam]@design`` (for parametric sensitivities and
        sampling, :mod:`gearopt.studies`)."""
        return BuiltScene(self, positions=positions, initial=initial, parametric=parametric)


JOINT_DATA = {"press_fit": (("friction_coefficient", ""), ("diametral_interference_um", "um"), ("fit_length_mm", "mm"),
                           ("shaft_diameter_mm", "mm"), ("hub_outer_diameter_mm", "mm")),
              "taper_nut": (("friction_coefficient", ""), ("nut_torque_Nm", "N*m"), ("nut_factor", ""),
                            ("taper_length_mm", "mm"))}
"""Entries of a ``[joints.*]`` record that a parametric build declares as NLP parameters (name, unit): the data a
joint's capacity depends on most (friction, interference or preload, fit geometry)."""


class BuiltScene(ContactModels, TrainModels, QuantityTerms):
    """A built scene: its models (``models``, in build order ``built``), its :class:`Problem` and :meth:`solve`.

    ``positions``: mesh -> fractions of a base pitch at which the smooth LTCA samples that mesh (default: the uniform
    ``ltca_options["positions"]``); ``initial``: ``"target.variable"`` -> start value (a warm start); ``reuse``:
    models of an earlier build that do not depend on these (data, dynamics), taken over unbuilt; ``options``:
    overrides of the scene's ``ltca_options`` for this build (the refinement's smoothing continuation).
    """

    def __init__(self, scene: Scene, *, positions: Mapping[str, Any] | None = None,
                 initial: Mapping[str, float] | None = None, reuse: Mapping[str, Any] | None = None,
                 options: Mapping[str, Any] | None = None, parametric: bool = False):
        self.scene = scene
        self.parametric = bool(parametric)
        self.data_parameters: dict[str, dict[str, Any]] = {}
        self.models: dict[str, Any] = dict(reuse or {})
        self._log: list[dict[str, Any]] = []
        self._options_override = dict(options or {})
        self._opts = {**DEFAULT_LTCA_OPTIONS, **dict(scene.ltca_options), **self._options_override}
        unknown = set(scene.ltca_options) - set(DEFAULT_LTCA_OPTIONS)
        if unknown:
            raise GearoptInputError(f"ltca_options {sorted(unknown)} are unknown ({sorted(DEFAULT_LTCA_OPTIONS)})")
        if scene.objective_aggregate not in ("sum", "max"):
            raise GearoptInputError(f"objective_aggregate={scene.objective_aggregate!r} must be 'sum' or 'max'")
        if scene.objective_aggregate == "max" and any(o.sense != "min" for o in scene.objectives):
            raise GearoptInputError("objective_aggregate='max' takes objectives to be minimised (sense='min'): the "
                                    "largest of them is minimised")
        if self._opts["approach"] not in ("lifted", "nested"):
            raise GearoptInputError(f"ltca_options approach={self._opts['approach']!r} must be 'lifted' or 'nested'")
        self._meshes = scene.meshes()
        self._needs = scene.needs()
        self._position_sets = dict(positions or {})
        self._initial_overrides = dict(initial or {})
        self._check_targets()
        self.problem = Problem(name=scene.name)
        self._records: list[dict[str, Any]] = []
        self._objective_terms: list[Any] = []
        self.load_cases = [self._resolve_load_case(lc) for lc in scene.load_cases]
        self._variables: dict[tuple[str, str], Any] = {}
        self._declare_variables()
        self._start_constraints()
        for obj in scene.objectives:
            self._add_objective(obj)
        for lim in scene.limits:
            self._add_limit(lim)
        if not self._objective_terms:
            raise GearoptInputError(f"scene {scene.name!r} has no objective")
        terms = self._objective_terms
        if scene.objective_aggregate == "max" and len(terms) > 1:
            starts = [float(np.max(self._initial(t))) for t in terms]
            z = self.problem.variable("objectives.max", init=max(starts))
            self.problem.subject_to("objectives.max.epigraph", nm.vcat([z - t for t in terms]), lower=0.0)
            self.problem.minimize(z)
        else:
            self.problem.minimize(sum(terms[1:], terms[0]))

    # -- what was built ----------------------------------------------------------------------------------------

    @property
    def built(self) -> list[str]:
        """Keys of the models built, in build order (``family:target``)."""
        return [r["model"] for r in self._log]

    @property
    def build_table(self) -> pd.DataFrame:
        """One row per built model: ``model``, ``detail`` (settings), ``build_time_s``."""
        return pd.DataFrame(self._log, columns=["model", "detail", "build_time_s"])

    def _model(self, key: str, build: Callable[[], Any], detail: Callable[[Any], str] | str = "") -> Any:
        if key not in self.models:
            t0 = time.perf_counter()
            obj = build()
            self.models[key] = obj
            self._log.append({"model": key, "detail": detail(obj) if callable(detail) else detail,
                              "build_time_s": time.perf_counter() - t0})
        return self.models[key]

    # -- targets, load cases, variables ------------------------------------------------------------------------

    def _data(self) -> dict:
        if self.scene.data is None:
            from ..data import load_default_data
            return self._model("data:default", load_default_data, "packaged default data")
        return self.scene.data

    def _check_targets(self) -> None:
        items = [("variable", v.name, v.target, variable_kind(v.name).target_kind) for v in self.scene.variables]
        items += [("quantity", q.quantity, q.target, quantity_kind(q.quantity).target_kind)
                  for q in (*self.scene.objectives, *self.scene.limits)]
        for what, name, target, kind in items:
            if kind == "train" and (target != TRAIN_TARGET or self.scene.train is None):
                raise GearoptInputError(f"{what} {name!r}: target={target!r} must be {TRAIN_TARGET!r} of a scene "
                                        f"with a train")
            if kind == "flank":
                self._check_flank_target(what, name, target)
            if kind == "mesh" and target not in self._meshes:
                raise GearoptInputError(f"{what} {name!r}: target={target!r} is not a mesh of the scene "
                                        f"({sorted(self._meshes)})")
            if kind == "joint" and target not in self._data_values().get("joints", {}):
                raise GearoptInputError(f"{what} {name!r}: target={target!r} is not a [joints.*] entry "
                                        f"({sorted(self._data_values().get('joints', {}))})")
            if kind == "blank" and (self.scene.train is None or target not in self.scene.train.gears):
                gears = sorted(self.scene.train.gears) if self.scene.train is not None else []
                raise GearoptInputError(f"{what} {name!r}: target={target!r} is not a gear of the scene's train "
                                        f"({gears})")
        if any(variable_kind(v.name).target_kind == "train" for v in self.scene.variables) and any(
                variable_kind(v.name).group == "macro" for v in self.scene.variables):
            raise GearoptInputError("train-level and mesh-level macro variables in one scene are not supported: "
                                    "free the train's root_profile_shift/helix_angle_deg or a mesh's macro geometry")
        names = [lc.name for lc in self.scene.load_cases]
        if len(set(names)) != len(names):
            raise GearoptInputError(f"load case names {names} must be unique")

    def _data_values(self) -> dict:
        from ..data import values
        return values(self._data())

    def _driving_gear(self, mesh: str) -> int:
        d = self.scene.driving_gear
        g = d.get(mesh, 1) if isinstance(d, Mapping) else d
        if g not in (1, 2):
            raise GearoptInputError(f"driving_gear[{mesh}]={g!r} must be 1 or 2")
        return int(g)

    def _resolve_load_case(self, lc: LoadCase) -> LoadCase:
        """A dynamic load case becomes a given one: mesh torques and joint demands from one simulation."""
        if lc.dynamics is None:
            return lc
        from ..dynamics import default_timing_model, walk_off_history
        from ..geometry.forces import mesh_torque_Nm

        dyn = lc.dynamics
        model = self._model(f"dynamics:{dyn['kind']}", lambda: default_timing_model(dyn["kind"]),
                            f"default timing model ({dyn['kind']})")
        key = f"simulation:{dyn['kind']}@{lc.speed_rpm:g}rpm{',backlash' if dyn['backlash'] else ''}"
        sim = self._model(key, lambda: model.simulate(speed_rpm=lc.speed_rpm, cycles=dyn["cycles"],
                                                      backlash=dyn["backlash"]),
                          f"{dyn['cycles']} cycle(s), statistic {dyn['statistic']}")
        torques = {}
        for mesh in sim.mesh_force_N.columns:
            force = np.abs(sim.mesh_force_N[mesh].to_numpy())
            stat = force.max() if dyn["statistic"] == "peak" else np.sqrt(np.mean(force ** 2))
            torques[mesh] = float(mesh_torque_Nm(stat, sim.mesh_base_radii_mm[mesh][0]))
        joints = {t for t, needs in self._needs.items() if "joint" in needs}
        jt, ja = {}, {}
        for joint in sorted(joints):
            w = walk_off_history(model, sim, joint)
            jt[joint] = float(np.max(np.abs(w["joint_torque_Nm"])))
            ja[joint] = float(np.max(np.abs(w["axial_force_N"])))
        return LoadCase(name=lc.name, torque_Nm=torques, speed_rpm=lc.speed_rpm, joint_torque_Nm=jt,
                        joint_axial_force_N=ja)

    def _declare_variables(self) -> None:
        """Declare the variables, macro ones first (micro defaults depend on whether the macro geometry is free)."""
        out = self._variables
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
            init = self._initial_overrides.get(f"{v.target}.{v.name}", init)
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
            lo, hi, init = self.micro_bounds(v.target, v.name, kind)
        elif kind.target_kind == "mesh":
            pair = self._meshes[v.target]
            if kind.group == "macro":
                g = pair.geometry()
                i = 0 if v.name.endswith("1_mm") else 1
                init = {"profile_shift_1": pair.profile_shifts[0], "face_width_mm": pair.face_width_mm[0]}.get(
                    v.name, g["tip_diameter_mm"][i])
        elif kind.target_kind == "joint":
            j = self._data_values()["joints"][v.target]
            key = kind.key or v.name
            if key not in j:
                raise GearoptInputError(f"design variable {v.name!r}: joint {v.target!r} ({j['joint_type']}) has "
                                        f"no {key!r}")
            init = j[key]
        else:
            init = getattr(self._blank(v.target, symbolic=False), v.name)
        return lo, hi, (None if init is None else float(init))

    def _iso(self, mesh: str, lc: LoadCase) -> dict:
        from ..rating import contact_stress_iso6336, root_stress_iso6336

        opts = dict(self.scene.iso6336_options)
        contact_keys = {"K_A", "K_v", "K_Hbeta", "K_Halpha", "material", "life_factor", "Z_L", "Z_v", "Z_R", "Z_W",
                        "Z_X", "S_Hmin"}
        root_keys = {"K_A", "K_v", "K_Fbeta", "K_Falpha", "material", "life_factor", "Y_ST", "Y_deltarelT", "Y_RrelT",
                     "Y_X", "S_Fmin", "rim_backup_ratio", "accuracy_grade"}

        def build():
            pair, g = self._pair(mesh), self._driving_gear(mesh)
            torque = self._datum(f"torque_Nm[{mesh}]@{lc.name}", lc.mesh_torque_Nm(mesh), "N*m")
            if self.parametric:
                opts["material"] = self._rating_materials(mesh, opts.get("material", "20MnCr5"))
            return {"contact": contact_stress_iso6336(pair, torque, driving_gear=g,
                                                      **{k: v for k, v in opts.items() if k in contact_keys}),
                    "root": root_stress_iso6336(pair, torque, driving_gear=g,
                                                **{k: v for k, v in opts.items() if k in root_keys})}

        return self._model(f"iso6336:{mesh}@{lc.name}", build, f"ISO 6336-2/-3 method B at {lc.name}")

    def _rating(self, mesh: str, lc: LoadCase):
        """ISO 6336 rating with computed factors (``rate_iso6336``; its keywords from ``iso6336_options``)."""
        import inspect

        from ..rating import rate_iso6336

        if lc.speed_rpm is None:
            raise GearoptInputError(f"load case {lc.name!r} needs speed_rpm for the ISO 6336 rating of {mesh!r}")
        allowed = set(inspect.signature(rate_iso6336).parameters) - {"pair", "torque_Nm", "speed_rpm", "driving_gear"}
        opts = {k: v for k, v in self.scene.iso6336_options.items() if k in allowed}

        def build():
            torque = self._datum(f"torque_Nm[{mesh}]@{lc.name}", lc.mesh_torque_Nm(mesh), "N*m")
            speed = self._datum(f"speed_rpm[{mesh}]@{lc.name}", self._driver_speed_rpm(mesh, lc.speed_rpm), "rpm")
            if self.parametric:
                opts["materials"] = self._rating_materials(mesh, opts.get("materials", "20MnCr5"))
            return rate_iso6336(self._pair(mesh), torque, speed, driving_gear=self._driving_gear(mesh), **opts)

        return self._model(f"iso6336_rating:{mesh}@{lc.name}", build,
                           f"ISO 6336 rating (computed factors) at {lc.name}")

    def _rating_materials(self, mesh: str, materials):
        """Both gears' materials with their endurance limits sigma_Hlim, sigma_Flim as data (parametric build)."""
        from ..rating.materials import material_pair

        out = []
        for name, m in zip(self._meshes[mesh].names, material_pair(materials)):
            limits = {key: self._datum(f"{key}[{name}]", getattr(m, key), "MPa")
                      for key in ("sigma_Hlim_MPa", "sigma_Flim_MPa") if getattr(m, key) is not None}
            out.append(replace(m, **limits))
        return tuple(out)

    # -- data as parameters, quantity expressions (hooks of gearopt.studies) --------------------------------------

    def parametric_twin(self, **options: Any) -> "BuiltScene":
        """The same NLP (same mesh positions and option overrides, e.g. after a refinement) built with its data as
        parameters (``Scene.build(parametric=True)``); ``options``: further ``ltca_options`` overrides (e.g.
        ``approach="nested"`` where the quantities must follow perturbed inputs at fixed variables)."""
        return BuiltScene(self.scene, positions=self._position_sets or None,
                          options={**self._options_override, **options} or None, parametric=True)

    def _datum(self, name: str, value: float, unit: str):
        """A datum a quantity uses: the number itself, or (``parametric`` build) a :class:`Problem` parameter of
        that value, declared once per name and listed in ``data_parameters`` (name -> value, unit)."""
        if not self.parametric or not nm.is_numeric(value):
            return value
        if name not in self.data_parameters:
            symbol = self.problem.parameter(name, float(value), unit=unit)
            self.data_parameters[name] = {"value": float(value), "unit": unit, "symbol": symbol}
        return self.data_parameters[name]["symbol"]

    def expressions(self, quantity: str, target: str, load_cases: Sequence[str] | None = None
                    ) -> list[tuple[str, str, Any]]:
        """``(label, load case, expression)`` of a quantity of the vocabulary at each load case (one entry with
        load case ``""`` for a quantity not evaluated per load case): the elements as the NLP sees them (the TE
        column of ``ppte_um``, the squared stresses of a ``squared`` quantity), for studies that add their own
        constraints or objectives to ``problem``."""
        kind = quantity_kind(quantity)
        if kind.shape == "named":
            raise GearoptInputError(f"{quantity!r} is a set of limits, not one quantity")
        if kind.target_kind == "mesh" and target not in self._meshes:
            raise GearoptInputError(f"quantity {quantity!r}: target={target!r} is not a mesh of the scene "
                                    f"({sorted(self._meshes)})")
        return [(self._label(quantity, target, lc), lc.name if lc is not None else "",
                 self._elements(kind, target, lc, {})) for lc in self._cases(kind, load_cases)]

    @property
    def records(self) -> list[dict[str, Any]]:
        """Every objective and limit quantity as declared, in the order of the quantity table: ``label``,
        ``quantity``, ``target``, ``load_case``, ``kind`` (:class:`QuantityKind`), ``expr`` (its elements),
        ``lower``, ``upper``, ``role``."""
        return list(self._records)

    def quantity_table(self, solved: ProblemResult) -> pd.DataFrame:
        """The quantity table (as ``SceneResult.quantities``) at any solve of ``problem``."""
        return self._quantity_table(solved)

    def _joint(self, joint: str, lc: LoadCase | None):
        from ..joints import joint_capacity

        overrides = {variable_kind(name).key or name: x for name, x in self._free(joint, "joint").items()}
        if self.parametric:
            entry = self._data_values()["joints"][joint]
            for key, unit in JOINT_DATA.get(entry["joint_type"], ()):
                if key not in overrides and key in entry:
                    overrides[key] = self._datum(f"{key}[{joint}]", entry[key], unit)
        speed = lc.speed_rpm if (lc is not None and lc.speed_rpm is not None) else 0.0
        return self._model(f"joint:{joint}@{speed:g}rpm",
                           lambda: joint_capacity(self._data(), joint, speed_rpm=speed, overrides=overrides),
                           f"capacity at {speed:g} rpm, free {sorted(overrides)}")

    def _blank(self, gear: str, symbolic: bool = True):
        from ..blank import blank_from_data

        blank, _ = blank_from_data(self._data(), self.scene.train, gear)
        if not symbolic:
            return blank
        free = self._free(gear, "blank")
        return self._model(f"blank:{gear}", lambda: replace(blank, **free), f"free {sorted(free)}")

    # -- solve -------------------------------------------------------------------------------------------------

    def solve(self, *, starts: int = 1, seed: int = 0, verbose: bool = False, check: bool = True,
              refine: bool | None = None, **ipopt) -> "SceneResult":
        """Solve the scene's NLP (Ipopt). Raises a :class:`~gearopt.errors.SolveError` subclass naming the violated
        constraints on failure.

        ``starts`` > 1: the declared start plus ``starts - 1`` Latin-hypercube points of the design variables inside
        their bounds (:func:`gearopt.nlp.multistart.multistart`, ``seed``); the best optimum is returned and
        ``SceneResult.starts`` tables every start with the success rate. ``check``: re-evaluate the optimum of every
        mesh with LTCA quantities by the exact LTCA at ``check_positions`` (``SceneResult.exact_check``: exact and
        smooth values side by side). ``refine`` (default: whenever a PPTE objective or limit is declared and
        ``check``): the semi-infinite refinement of :func:`gearopt.design.scene_refine.solve_refined` -- add the exact
        TE's peak and trough positions and re-solve warm until the smooth and exact PPTE agree within
        ``ltca_options["refine_tolerance"]`` (``SceneResult.refinement``)."""
        from .scene_refine import solve_refined

        if refine is None:
            refine = check and any(q.quantity == "ppte_um" for q in (*self.scene.objectives, *self.scene.limits))
        if refine:
            return solve_refined(self, starts=starts, seed=seed, verbose=verbose, **ipopt)
        return self.solve_once(starts=starts, seed=seed, verbose=verbose, check=check, **ipopt)

    def solve_once(self, *, starts: int = 1, seed: int = 0, verbose: bool = False, check: bool = True,
                   **ipopt) -> "SceneResult":
        """One solve of this NLP on its present position sets (no refinement); see :meth:`solve`."""
        starts_table = None
        if starts > 1:
            names = [f"{t}.{name}" for (t, name) in self._variables]
            ms = self.problem.multistart(starts - 1, seed=seed, variables=names, include_initial=True,
                                         verbose=verbose, **ipopt)
            solved, starts_table = ms.best, ms.table
        else:
            solved = self.problem.solve(verbose=verbose, **ipopt)
        values = {}
        for (t, name) in self._variables:
            entry = self.problem._variables[f"{t}.{name}"]
            v = float(np.asarray(solved.values[f"{t}.{name}"]).ravel()[0])
            values[f"{t}.{name}"] = float(np.clip(v, entry.lower[0], entry.upper[0]))
        table = self._quantity_table(solved)
        exact = self._exact_check(values, solved.value) if check else pd.DataFrame()
        return SceneResult(scene=self.scene.name, values=values, solve=solved, quantities=table, exact_check=exact,
                           microgeometry={m: self.microgeometry_at(values, m) for m in self._ltca_meshes()},
                           built=self.build_table, starts=starts_table, source=self,
                           positions={m: np.asarray(self._positions_of(m)) for m in self._ltca_meshes()})

    def _positions_of(self, mesh: str) -> np.ndarray:
        from ..contact.layout import position_fractions
        return position_fractions(self._positions(mesh))

@dataclass
class SceneResult:
    """The solved scene: ``values`` (``"target.variable"`` -> value in the variable's unit), ``quantities`` (every
    objective and limit quantity at the optimum: value, bounds, margin, unit -- the true maximum/PPTE, not the
    epigraph bound), ``exact_check`` (exact LTCA of the optimum), ``microgeometry`` per LTCA mesh, ``solve``
    (:class:`ProblemResult`: constraint and variable tables, multipliers), ``built`` (the build table) and
    ``starts`` (the multi-start table, when ``solve(starts=n)``), ``refinement`` (one row per solve of the
    semi-infinite refinement: positions, worst smooth-vs-exact PPTE error, Ipopt iterations and times) and
    ``positions`` (per LTCA mesh, the final mesh positions as fractions of a base pitch), ``source`` (the
    :class:`BuiltScene` solved; the studies of :mod:`gearopt.studies` start from it)."""

    scene: str
    values: dict[str, float]
    solve: ProblemResult
    quantities: pd.DataFrame
    exact_check: pd.DataFrame
    microgeometry: dict[str, Microgeometry]
    built: pd.DataFrame
    starts: pd.DataFrame | None = None
    refinement: pd.DataFrame | None = None
    positions: dict[str, np.ndarray] = field(default_factory=dict)
    source: Any = field(default=None, repr=False, compare=False)

    @property
    def refinements(self) -> int:
        """Re-solves the semi-infinite refinement needed (0: the first solve agreed with the exact model)."""
        return 0 if self.refinement is None else int(len(self.refinement) - 1)

    @property
    def success_rate(self) -> float:
        """Fraction of the multi-start solves that converged (1.0 for a single successful solve)."""
        return 1.0 if self.starts is None else float(self.starts["success"].mean())


__all__ = ["Scene", "BuiltScene", "SceneResult", "LoadCase", "DesignVariable", "Objective", "Limit",
           "DEFAULT_LTCA_OPTIONS"]
