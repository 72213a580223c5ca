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

    system = go.load_system(path)      # e.g. gearopt/data/minimal_train.toml, or your own file
    MESH = "pinion-wheel"
    scene = Scene("pinion-wheel micro", train=system.train("spur"), data=system,
                  load_cases=[LoadCase("low", 60.0), LoadCase("design", 120.0), LoadCase("high", 180.0)],
                  variables=[DesignVariable(v, MESH) for v in ("tip_relief_1_um", "tip_relief_2_um",
                             "tip_relief_1_start_roll_deg", "tip_relief_2_start_roll_deg")],
                  objectives=[Objective("ppte_um", MESH, aggregate="max")],
                  limits=[Limit("max_contact_stress_MPa", MESH, upper=1100.0),
                          Limit("loaded_contact_ratio", MESH, lower=1.2)])
    built = scene.build()
    built.built          # ['geometry:pinion-wheel', 'ltca_smooth:pinion-wheel', 'ltca_evaluation:pinion-wheel']
    result = built.solve()
    result.values, result.quantities, result.exact_check

A built scene is composed of parts with public interfaces, each in its own module (none imports a part above it):

- declaration: :class:`Scene` and the records of :mod:`gearopt.design.scene_spec` in the vocabulary of
  :mod:`gearopt.design.scene_terms`;
- options: :class:`~gearopt.design.scene_options.LTCAOptions` -- the LTCA options as typed records per concern
  (smooth model, contact temperature, exact check, refinement), from the scene's flat ``ltca_options``;
- inputs: :class:`~gearopt.design.scene_inputs.SceneInputs` -- every read of the data set, the dynamic load cases,
  the data as NLP parameters of a parametric build;
- model graph: :class:`~gearopt.design.scene_models.SceneModels` (geometry, ISO 6336, joints, blanks, walk-off) and
  :class:`~gearopt.design.scene_contact.ContactModels` (smooth and macro LTCA, microgeometry, exact check), each model
  built once per target into one :class:`~gearopt.design.scene_cache.ModelCache`;
- transcription: :class:`~gearopt.design.scene_transcription.SceneTranscription` -- variables, objectives and
  limits into one :class:`~gearopt.nlp.problem.Problem`, the quantity table;
- refinement: :class:`~gearopt.design.scene_refine.SceneRefinement` (semi-infinite PPTE refinement);
- result: :class:`~gearopt.design.scene_result.SceneResult`.

:class:`BuiltScene` holds the parts (``inputs``, ``graph``, ``contact``, ``transcription``) and delegates to them.

Co-design (macro and micro geometry in one NLP): train-level variables (``DesignVariable("root_profile_shift",
"train", ...)``, ``DesignVariable("helix_angle_deg", "train", ...)``) make every mesh of the train symbolic at its
fixed centre distance, and a mesh with LTCA quantities then uses the macro-symbolic smooth LTCA
(:mod:`gearopt.design.scene_contact`); micro variables may target a gear flank (``"cam:driving"``) shared by every
mesh that loads it; joint margins take their axial demand from the mesh forces and the helix angle
(:mod:`gearopt.design.scene_models`).

PPTE over the mesh cycle is a minimax over a continuum of positions: :meth:`BuiltScene.solve` solves on a coarse set
of positions, re-evaluates the optimum by the exact LTCA and adds the exact TE's peak and trough positions until the
smooth and exact PPTE agree within ``refine_tolerance`` (:mod:`gearopt.design.scene_refine`;
``SceneResult.refinement`` tables the iterations). Contact temperature needs one speed for all load cases of a mesh
(the LTCA model is built for one speed).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pandas as pd

from ..contact.microgeometry import Microgeometry
from ..data import System, system_of
from ..errors import GearoptInputError
from ..geometry.pair import GearPair
from ..geometry.train import GearTrain
from ..nlp.problem import Problem, WarmStartPoint
from ..nlp.result import ProblemResult
from ..nlp.solver_options import WARM_START_IPOPT
from .scene_cache import ModelCache
from .scene_contact import ContactModels
from .scene_inputs import JOINT_DATA, SceneInputs
from .scene_models import TRAIN_TARGET, SceneModels
from .scene_options import DEFAULT_LTCA_OPTIONS, LTCAOptions
from .scene_refine import SceneRefinement, exact_best_start
from .scene_result import SceneResult
from .scene_search import exact_screen, screened_starts, search_scope
from .scene_spec import DesignVariable, Limit, LoadCase, Objective
from .scene_terms import quantity_kind, variable_kind
from .scene_transcription import SceneTranscription

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
        data: the scene's data set: a :class:`~gearopt.data.System` (``gearopt.load_system(path)``; a validated
            dict converts with ``gearopt.data.system_from_data(d)``) or None; joint, blank and rating-material
            quantities need it (an error names a missing one), and its ``[lubrication]`` sets the oil temperature
            and friction coefficient of contact temperatures unless ``ltca_options`` give them.
        ltca_options: flat overrides of the LTCA options (:class:`~gearopt.design.scene_options.LTCAOptions`,
            defaults :data:`DEFAULT_LTCA_OPTIONS`), e.g. ``{"positions": 24, "max_refinements": 0}``; an unknown
            key or a bad value raises naming it; iso6336_options: keyword arguments of
            :func:`~gearopt.rating.contact_stress_iso6336` / :func:`~gearopt.rating.root_stress_iso6336` (K_A, ...).
        objective_aggregate: how several objectives combine: ``"sum"`` (their weighted, scaled sum) or ``"max"``
            (the largest of them, by an epigraph variable ``objectives.max``: e.g. the largest PPTE of several
            meshes, each objective divided by its scale and multiplied by its weight). A pure minimax: the
            objectives below the largest are left wherever its optimum puts them.
        dynamics_model: ``kind -> torsional model`` of the scene's train (``"spur"``/``"helical"``), for load cases
            whose loads come from a simulation (:meth:`LoadCase.from_dynamics`); built once per kind.
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
    data: System | None = None
    ltca_options: Mapping[str, Any] = field(default_factory=dict)
    iso6336_options: Mapping[str, Any] = field(default_factory=dict)
    objective_aggregate: str = "sum"
    dynamics_model: Callable[[str], Any] | None = None

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
        :class:`Problem` parameters named like ``torque_Nm[pinion-wheel]@design`` (for parametric sensitivities and
        sampling, :mod:`gearopt.studies`)."""
        return BuiltScene(self, positions=positions, initial=initial, parametric=parametric)


def _lubrication_options(system: System | None) -> dict[str, float]:
    """The LTCA options the ``[lubrication]`` of the :class:`~gearopt.data.System` ``system`` sets: the oil (bulk)
    temperature [degC] and the mean friction coefficient of the contact temperatures (none without a system or the
    section)."""
    if system is None:
        return {}
    lub = system_of(system, "Scene(data=...)").lubrication
    if lub is None:
        return {}
    return {"bulk_temperature_C": float(lub.oil_temperature_C),
            "friction_coefficient": float(lub.mean_friction_coefficient)}


class BuiltScene:
    """A built scene: its models (``models``, in build order ``built``), its :class:`Problem` and :meth:`solve`.

    ``positions``: mesh -> fractions of a base pitch at which the smooth LTCA samples that mesh (default: the uniform
    ``ltca_options["positions"]``); ``initial``: ``"target.variable"`` -> start value (a warm start); ``reuse``:
    models of an earlier build that do not depend on these (data, dynamics), taken over unbuilt; ``options``:
    flat overrides of the scene's ``ltca_options`` for this build (the refinement's smoothing continuation).
    ``built.options`` is the build's :class:`~gearopt.design.scene_options.LTCAOptions`: the defaults, the data's
    ``[lubrication]``, the scene's ``ltca_options`` and these overrides, in that order.

    Parts (module docstring): ``cache`` (:class:`ModelCache`), ``inputs`` (:class:`SceneInputs`), ``graph``
    (:class:`SceneModels`), ``contact`` (:class:`ContactModels`), ``transcription`` (:class:`SceneTranscription`);
    the methods below delegate to them.
    """

    def __init__(self, scene: Scene, *, positions: Mapping[str, Any] | None = None,
                 initial: Mapping[str, float] | None = None, reuse: Mapping[str, Any] | None = None,
                 options: Mapping[str, Any] | None = None, parametric: bool = False):
        self.scene = scene
        self.parametric = bool(parametric)
        self._options_override = dict(options or {})
        self.options: LTCAOptions = LTCAOptions.from_mapping(
            scene.ltca_options, base=LTCAOptions().replace(**_lubrication_options(scene.data))
        ).replace(**self._options_override)
        if scene.objective_aggregate not in ("sum", "max"):
            raise GearoptInputError(f"objective_aggregate={scene.objective_aggregate!r} must be 'sum' or 'max'")
        if scene.objective_aggregate == "max" and any(o.sense != "min" for o in scene.objectives):
            raise GearoptInputError("objective_aggregate='max' takes objectives to be minimised (sense='min'): the "
                                    "largest of them is minimised")
        self.problem = Problem(name=scene.name)
        self.cache = ModelCache(reuse)
        self.inputs = SceneInputs(scene, self.cache, self.problem, parametric=self.parametric)
        self.graph = SceneModels(scene, self.options, self.inputs, self.cache, {}, self.problem)
        self.contact = ContactModels(self.graph, positions)
        self.transcription = SceneTranscription(self.graph, self.contact, initial)
        self.transcription.check_targets()
        self.graph.resolve_load_cases()
        self.transcription.transcribe()

    # -- what was built ----------------------------------------------------------------------------------------

    @property
    def models(self) -> dict[str, Any]:
        """The models of this build by key (``family:target``), those taken over by ``reuse`` included."""
        return self.cache.models

    @property
    def built(self) -> list[str]:
        """Keys of the models built, in build order (``family:target``)."""
        return self.cache.built

    @property
    def build_table(self) -> pd.DataFrame:
        """One row per built model: ``model``, ``detail`` (settings), ``build_time_s``."""
        return self.cache.build_table

    @property
    def load_cases(self) -> list[LoadCase]:
        """The scene's load cases, a dynamic one resolved into mesh torques and joint demands."""
        return self.graph.load_cases

    @property
    def data_parameters(self) -> dict[str, dict[str, Any]]:
        """Parametric build: the data declared as :class:`Problem` parameters (name -> value, unit, symbol)."""
        return self.inputs.data_parameters

    @property
    def variable_names(self) -> list[str]:
        """The design variables as ``"target.variable"``, in declaration order."""
        return self.transcription.variable_names

    @property
    def initial_overrides(self) -> dict[str, float]:
        """The warm-start values this build was given (``initial``)."""
        return self.transcription.initial_overrides

    def initial_values(self) -> dict[str, float]:
        """The start of every design variable (``"target.variable"`` keys)."""
        return self.graph.initial_values()

    # -- the model graph ---------------------------------------------------------------------------------------

    def train_at(self, values: Mapping[str, float]) -> GearTrain:
        """The scene's train with the train-level variables at ``values`` (``"train.variable"`` keys)."""
        return self.graph.train_at(values)

    def numeric_pair(self, mesh: str, values: Mapping[str, float]) -> GearPair:
        """The mesh's pair at the design ``values`` (numbers)."""
        return self.graph.numeric_pair(mesh, values)

    def joint_axial_force_N(self, joint: str, lc: LoadCase):
        """Axial force on ``joint``'s gear at ``lc`` [N] (:meth:`SceneModels.joint_axial_force_N`)."""
        return self.graph.joint_axial_force_N(joint, lc)

    def joint_torque_Nm(self, joint: str, lc: LoadCase):
        """Torque through ``joint`` at ``lc`` [N m] (:meth:`SceneModels.joint_torque_Nm`)."""
        return self.graph.joint_torque_Nm(joint, lc)

    def loaded_flanks(self, mesh: str) -> tuple[str, str]:
        """The flank targets (``"gear:flank"``) mesh ``mesh`` loads, gear 1 then gear 2."""
        return self.contact.loaded_flanks(mesh)

    def flank_meshes(self, flank: str) -> list[str]:
        """Meshes of the scene that load ``flank`` (``"gear:flank"``)."""
        return self.contact.flank_meshes(flank)

    def micro_bounds(self, target: str, name: str, kind) -> tuple[float | None, float | None, float | None]:
        """Default bounds and start of a micro variable of a mesh or a flank."""
        return self.contact.micro_bounds(target, name, kind)

    def microgeometry_at(self, values: Mapping[str, float], mesh: str) -> Microgeometry:
        """The mesh's microgeometry with the free amounts set to ``values`` (``"target.variable"`` keys)."""
        return self.contact.microgeometry_at(values, mesh)

    def ltca_meshes(self) -> list[str]:
        """Meshes with LTCA quantities."""
        return self.contact.ltca_meshes()

    def positions_of(self, mesh: str) -> np.ndarray:
        """The mesh positions of the mesh's smooth LTCA, as fractions of a base pitch."""
        return self.contact.positions_of(mesh)

    def exact_check(self, values: Mapping[str, float], evaluate: Callable | None = None, *,
                    train=None, positions: int | None = None, toleranced: bool | Sequence[str] = True,
                    fractions: bool = True, table: bool = True) -> pd.DataFrame | dict[str, np.ndarray]:
        """Exact LTCA of every LTCA mesh at a design, beside the smooth model's values when ``evaluate``
        (:meth:`ContactModels.exact_check`); ``train``: another numeric train's pairs instead of the scene's (e.g.
        another root profile shift: :func:`gearopt.design.scene_presolve.scan_train_variable`); ``positions``: a
        one-slice mesh's positions instead of ``check_positions`` (the exact screen's ``screen_positions``);
        ``toleranced``: the ``ppte_um_toleranced`` column where a quantity asks for it (False: leave out its relief
        variants, as the exact screen and the polish's steps do; a list of meshes: for those); ``fractions=False``:
        without the positions of the exact extremes (the refinement's, not the search's); ``table=False``: the
        columns as numpy arrays instead of a DataFrame (cheaper where only a few columns are read)."""
        return self.contact.exact_check(values, evaluate, train=train, positions=positions, toleranced=toleranced,
                                        fractions=fractions, table=table)

    # -- the NLP and its quantities (hooks of gearopt.studies) -------------------------------------------------

    def expressions(self, quantity: str, target: str, load_cases: Sequence[str] | None = None
                    ) -> list[tuple[str, str, Any]]:
        """``(label, load case, expression)`` of a quantity at each load case
        (:meth:`SceneTranscription.expressions`)."""
        return self.transcription.expressions(quantity, target, load_cases)

    @property
    def records(self) -> list[dict[str, Any]]:
        """Every objective and limit quantity as declared, in the order of the quantity table: ``label``,
        ``quantity``, ``target``, ``load_case``, ``kind`` (:class:`QuantityKind`), ``expr`` (its elements),
        ``lower``, ``upper``, ``role``."""
        return self.transcription.records

    def quantity_table(self, solved: ProblemResult) -> pd.DataFrame:
        """The quantity table (as ``SceneResult.quantities``) at any solve of ``problem``."""
        return self.transcription.quantity_table(solved)

    def quantities_at(self, values: Mapping[str, float]) -> pd.DataFrame:
        """Every objective and limit quantity of the smooth models at a design (``"target.variable"`` values; the
        table of :attr:`SceneResult.quantities`): e.g. two designs compared on one model."""
        return self.transcription.quantities_at(values)

    def evaluator_at(self, values: Mapping[str, float]) -> Callable:
        """``expr -> value`` of expressions of the design variables at ``values`` (``"target.variable"`` keys)."""
        return self.transcription.evaluator_at(values)

    # -- related builds ----------------------------------------------------------------------------------------

    def parametric_twin(self, **options: Any) -> "BuiltScene":
        """The same NLP (same mesh positions and option overrides, e.g. after a refinement) built with its data as
        parameters (``Scene.build(parametric=True)``); ``options``: further ``ltca_options`` overrides (e.g.
        ``approach="nested"`` where the quantities must follow perturbed inputs at fixed variables)."""
        return BuiltScene(self.scene, positions=self.contact.position_sets or None,
                          options={**self._options_override, **options} or None, parametric=True)

    def rebuild(self, *, positions: Mapping[str, Any], initial: Mapping[str, float] | None = None,
                reuse: Mapping[str, Any] | None = None, options: Mapping[str, Any] | None = None) -> "BuiltScene":
        """The next build of the refinement: the same scene (and parametric setting) at other mesh ``positions``,
        warm-started at ``initial``, with ``reuse`` taken over and ``options`` added to this build's overrides."""
        return BuiltScene(self.scene, positions=positions, initial=initial, reuse=reuse, parametric=self.parametric,
                          options={**self._options_override, **dict(options or {})})

    # -- solve -------------------------------------------------------------------------------------------------

    def solve(self, *, starts: int | None = None, seed: int = 0, verbose: bool = False, check: bool = True,
              refine: bool | None = None, warm_start: WarmStartPoint | None = None, **ipopt) -> "SceneResult":
        """Solve the scene's NLP (Ipopt). Raises a :class:`~gearopt.errors.SolveError` subclass naming the violated
        constraints on failure.

        Starts: where the exact search applies (:func:`gearopt.design.scene_search.search_scope`: PPTE objectives,
        limits on exact-LTCA and closed-form geometry quantities, few bounded variables), the ``starts`` (default
        :meth:`default_starts`: 1, or ``macro_starts`` with free macro variables) best designs of an exact screen
        (scrambled Sobol, ``seed``; ``SceneResult.screen``; not for a build warm-started with ``initial``, whose
        start the caller chose) and the optimum is polished on the exact model
        (``SceneResult.refinement.attrs["polish"]``); otherwise ``starts`` > 1 solves from the declared start plus
        ``starts - 1`` Latin-hypercube points of the design variables inside their bounds
        (:func:`gearopt.nlp.multistart.multistart`, ``seed``). Either way the exact LTCA ranks the optima of a
        scene with a PPTE objective and ``SceneResult.starts`` tables every start with the success rate. ``check``:
        re-evaluate the optimum of every mesh with LTCA quantities by the exact LTCA at ``check_positions``
        (``SceneResult.exact_check``: exact and smooth values side by side). ``refine`` (default: whenever a PPTE objective or limit is declared and
        ``check``): the semi-infinite refinement of :class:`gearopt.design.scene_refine.SceneRefinement` -- add the exact
        TE's peak and trough positions and re-solve warm until the smooth and exact PPTE agree within
        ``ltca_options["refine_tolerance"]`` (``SceneResult.refinement``). ``warm_start``: a
        :class:`~gearopt.nlp.WarmStartPoint` for the first solve from the declared start (one start; e.g. the
        multipliers of a related scene's result, :meth:`SceneResult.warm_start_point`), with
        :data:`~gearopt.nlp.WARM_START_IPOPT` under the caller's Ipopt options; refused with ``starts`` > 1 or
        where the exact screen picks the starts, which would not use it."""
        if starts is None:
            starts = self.default_starts(check)
        self._check_warm_start(warm_start, starts, check)
        if refine is None:
            refine = check and any(q.quantity == "ppte_um" for q in (*self.scene.objectives, *self.scene.limits))
        if refine:
            return SceneRefinement(self).solve(starts=starts, seed=seed, verbose=verbose, warm_start=warm_start,
                                               **ipopt)
        return self.solve_once(starts=starts, seed=seed, verbose=verbose, check=check, warm_start=warm_start, **ipopt)

    def default_starts(self, check: bool = True) -> int:
        """The starts of :meth:`solve` without ``starts``: ``ltca_options["macro_starts"]`` (4) of the exact screen's
        best designs where the screen applies (not warm-started, ``check``, in :func:`search_scope`) and a macro
        variable other than the train's root profile shift is free (a helix angle, a mesh's shift, tip diameters or
        face width: the exact PPTE has neighbouring optima across the overlap and contact ratios that one local
        solve does not reach), else 1. The root shift alone moves the contact ratios smoothly: on the packaged
        spur train's first mesh with two reliefs, 1 and 4 starts end at the same design, 0.5707 um, in 4.2 and 10.5
        CPU-s; with the helix angle free too, 0.2346 against 0.1239 um."""
        macro = any(variable_kind(v.name).group in ("train", "macro") and v.name != "root_profile_shift"
                    for v in self.scene.variables)
        return self.options.search.macro_starts if macro and self.screened(check) else 1

    def values_of(self, solved) -> dict[str, float]:
        """The design variables of a solve (``"target.variable"`` -> value, clipped to their bounds)."""
        values = {}
        for name in self.variable_names:
            entry = self.problem._variables[name]
            v = float(np.asarray(solved.values[name]).ravel()[0])
            values[name] = float(np.clip(v, entry.lower[0], entry.upper[0]))
        return values

    def screened(self, check: bool = True) -> bool:
        """Whether a solve of this build starts from the exact screen: ``check``, ``screen_samples`` > 0, in
        :func:`search_scope`, and not warm-started (a build with ``initial`` for a design variable: the caller chose
        the start)."""
        warm = bool(set(self.variable_names) & set(self.initial_overrides))
        return bool(check and not warm and self.options.search.screen_samples and search_scope(self) is None)

    def solve_once(self, *, starts: int = 1, seed: int = 0, verbose: bool = False, check: bool = True,
                   screened: bool = True, warm_start: WarmStartPoint | None = None, **ipopt) -> "SceneResult":
        """One solve of this NLP on its present position sets (no refinement); see :meth:`solve`. ``screened``
        (default): where the exact screen applies and the build is not warm-started, the starts are its best
        designs; ``False`` (a warm re-solve): the declared start. ``warm_start``: a
        :class:`~gearopt.nlp.WarmStartPoint` of a solve from the declared start (one start, not screened), with
        :data:`~gearopt.nlp.WARM_START_IPOPT` under ``ipopt``."""
        starts_table, screen = None, None
        names = self.variable_names
        self._check_warm_start(warm_start, starts, check and screened)
        if screened and self.screened(check):
            screen = exact_screen(self, seed=seed)       # the global phase: the exact model picks the starts
            points = screened_starts(screen, names, starts)
            ms = self.problem.multistart(len(points), variables=names, points=points, origin="exact screen",
                                         verbose=verbose, **ipopt)
            solved, starts_table = exact_best_start(self, ms)
        elif starts > 1:
            ms = self.problem.multistart(starts - 1, seed=seed, variables=names, include_initial=True,
                                         verbose=verbose, **ipopt)
            solved, starts_table = ms.best, ms.table
            if check and self.ltca_meshes() and any(o.quantity == "ppte_um" for o in self.scene.objectives):
                solved, starts_table = exact_best_start(self, ms)     # the exact model ranks the starts
        elif warm_start is not None:
            solved = self.problem.solve(verbose=verbose, warm_start=warm_start, **{**WARM_START_IPOPT, **ipopt})
        else:
            solved = self.problem.solve(verbose=verbose, **ipopt)
        return self._result(solved, check, starts_table, screen)

    def _check_warm_start(self, warm_start, starts: int, check: bool) -> None:
        """A warm start is for one solve from the declared start: refused (named) with several starts or where the
        exact screen picks the starts (:meth:`screened` of ``check``), where it would not be used."""
        if warm_start is None:
            return
        if not isinstance(warm_start, WarmStartPoint):
            raise GearoptInputError(f"warm_start={warm_start!r} must be a gearopt.nlp.WarmStartPoint or None")
        if starts > 1 or self.screened(check):
            raise GearoptInputError(
                f"warm_start: a warm start is for one solve from the declared start, but this solve starts from "
                f"{'starts=' + str(starts) + ' points' if starts > 1 else 'the exact screen'}; build the scene at "
                f"the design (build(initial=values)) and solve with starts=1")

    def solve_starts(self, *, starts: int, seed: int = 0, verbose: bool = False,
                     **ipopt) -> tuple[list["SceneResult | None"], pd.DataFrame, pd.DataFrame | None]:
        """Every start of a multistart solved once and checked (the refinement then finishes each;
        :meth:`solve`): ``(results, table, screen)`` -- per start its :class:`SceneResult` (``None`` where Ipopt
        failed), the starts table (:meth:`gearopt.nlp.problem.Problem.multistart`) and the exact screen (``None``
        where it does not apply: the declared start and ``starts - 1`` Latin-hypercube points, ``seed``). Raises the
        multistart's :class:`~gearopt.errors.SolveError` when every start fails."""
        names, screen = self.variable_names, None
        if self.screened(True):
            screen = exact_screen(self, seed=seed)
            ms = self.problem.multistart(max(1, int(starts)), variables=names, origin="exact screen",
                                         points=screened_starts(screen, names, starts), verbose=verbose, **ipopt)
        else:
            ms = self.problem.multistart(max(1, int(starts) - 1), seed=seed, variables=names, include_initial=True,
                                         verbose=verbose, **ipopt)
        results = [None if s is None else self._result(s, True, None, screen) for s in ms.results]
        return results, ms.table.copy(), screen

    def _result(self, solved, check: bool, starts_table, screen) -> "SceneResult":
        values = self.values_of(solved)
        table = self.transcription.quantity_table(solved)
        exact = self.exact_check(values, solved.value) if check else pd.DataFrame()
        return SceneResult(scene=self.scene.name, values=values, solve=solved, quantities=table, exact_check=exact,
                           microgeometry={m: self.microgeometry_at(values, m) for m in self.ltca_meshes()},
                           built=self.build_table, starts=starts_table, screen=screen, source=self,
                           positions={m: np.asarray(self.positions_of(m)) for m in self.ltca_meshes()})


__all__ = ["Scene", "BuiltScene", "SceneResult", "LoadCase", "DesignVariable", "Objective", "Limit",
           "DEFAULT_LTCA_OPTIONS", "JOINT_DATA", "TRAIN_TARGET"]
