"""The contact models of a built scene (:class:`ContactModels`, part of its model graph on top of
:class:`~gearopt.design.scene_models.SceneModels`): LTCA models per mesh, the microgeometry each mesh sees (per mesh
or per gear flank), LTCA quantities, and the exact-LTCA check of an optimum.

Two smooth models serve a scene:

- a mesh whose macro geometry is fixed uses :class:`~gearopt.contact.ltca_smooth.LTCAModel` (its numeric layout
  keeps only the springs on the path);
- a mesh whose macro geometry is free (train variables ``root_profile_shift``/``helix_angle_deg``, or mesh macro
  variables) uses :class:`~gearopt.contact.ltca_macro.MacroLTCAModel`, whose graph is the same for every macro value
  (normalised positions and slices, a fixed range of tooth pairs, smooth engagement).

Both are evaluated at the mesh's set of mesh positions (fractions of a base pitch): a uniform grid at first, grown
by the semi-infinite refinement of :mod:`gearopt.design.scene_refine`.

Gear flanks: in forward operation a mesh loads the ``driving`` flank of its driving gear and the ``driven`` flank of
the other (:data:`gearopt.design.scene_terms.FLANKS`). A micro variable targeting ``"gear:flank"`` is one design
quantity that every mesh loading that flank sees -- a gear has one tooth form per flank.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Mapping, Sequence

import numpy as np
import pandas as pd

from .. import numerics as nm
from ..contact.layout import default_positions, default_slices, position_fractions
from ..contact.ltca import ltca_torques
from ..contact.ltca_macro import MacroLTCAModel, macro_vector, micro_vector
from ..contact.ltca_smooth import LTCAModel
from ..contact.microgeometry import Microgeometry
from ..contact.relief_tolerances import relief_variants
from ..errors import GearoptInputError
from ..rating.stiffness import iso6336_stiffness
from .positions import corner_values, extreme_fractions, min_tip_relief_design, peak_fractions, start_bounds
from .scene_models import SceneModels
from .scene_spec import LoadCase
from .scene_terms import FLANKS, quantity_kind

UNMODIFIED = Microgeometry()
"""The microgeometry of a mesh the scene gives none (made once: a record's checks run when it is made)."""
MICRO_FIELDS = ("tip_relief_um", "tip_relief_start_roll_deg", "profile_crown_um", "lead_crown_um")
START_WIDENING_DEG = 3.0
APPROACH_SCALE_UM = 10.0
"""Scale of the lifted form's approach variables [um] (a mesh's static TE is some microns to tens of microns)."""
"""With free macro geometry the start bounds of a tip relief are widened by this much around the initial
geometry's pitch point .. tip, and constraints on the symbolic geometry keep the start inside the profile."""


def mesh_variable_name(field: str, gear_index: int) -> str:
    """The mesh-targeted variable of a microgeometry field and gear: ``tip_relief_um``, 0 -> ``tip_relief_1_um``."""
    stem = field.replace("_start_roll_deg", "").replace("_um", "")
    return f"{stem}_{gear_index + 1}{field[len(stem):]}"


def parse_flank(target: str) -> tuple[str, str]:
    gear, sep, flank = target.partition(":")
    if not sep or flank not in FLANKS:
        raise GearoptInputError(f"flank target {target!r} must be 'gear:flank' with flank in {FLANKS}")
    return gear, flank


SMOOTH_COMPARED = ("ppte_um", "max_contact_stress_MPa", "max_root_stress_MPa", "max_contact_temperature_C")
"""The exact check's quantities compared with the smooth model's (``smooth_<q>``, ``<q>_error``)."""


class ContactModels:
    """The contact models of a build (module docstring), on its model graph ``graph``
    (:class:`~gearopt.design.scene_models.SceneModels`: pairs, driving gears, the model cache, the design variables,
    the data as parameters); ``positions``: mesh -> mesh positions of its smooth LTCA (fractions of a base pitch;
    default the uniform ``options.model.positions``).

    Public interface: flanks (:meth:`loaded_flanks`, :meth:`flank_meshes`, :meth:`check_flank_target`), the
    microgeometry each mesh sees (:meth:`base_microgeometry`, :meth:`free_micro`, :meth:`microgeometry`,
    :meth:`microgeometry_at`, :meth:`minimum_relief`, :meth:`micro_bounds`), the LTCA models (:meth:`ltca_meshes`,
    :meth:`mesh_cases`, :meth:`positions`, :meth:`positions_of`, :meth:`ltca_model`, :meth:`ltca`), the LTCA
    quantities (:meth:`elements`) and the exact check of a design (:meth:`exact_check`). The lifted form
    (``approach="lifted"``) declares its approach variables and equilibrium constraints on the graph's problem and
    sets the problem's ``start_completion`` (:meth:`lifted_start`).
    """

    def __init__(self, graph: SceneModels, positions: Mapping[str, Any] | None = None):
        self.graph = graph
        self.scene = graph.scene
        self.options = graph.options
        self.meshes = graph.meshes
        self.needs = graph.needs
        self.inputs = graph.inputs
        self.position_sets: dict[str, Any] = dict(positions or {})
        self._lifted: dict[str, tuple] = {}

    # -- flanks --------------------------------------------------------------------------------------------------

    def loaded_flanks(self, mesh: str) -> tuple[str, str]:
        """The flank targets (``"gear:flank"``) mesh ``mesh`` loads, gear 1 then gear 2."""
        names = self.meshes[mesh].names
        d = self.graph.driving_gear(mesh) - 1
        return tuple(f"{names[i]}:{'driving' if i == d else 'driven'}" for i in (0, 1))

    def flank_meshes(self, flank: str) -> list[str]:
        """Meshes of the scene that load ``flank`` (``"gear:flank"``)."""
        return [m for m in self.meshes if flank in self.loaded_flanks(m)]

    def check_flank_target(self, what: str, name: str, target: str) -> None:
        gear, _ = parse_flank(target)
        gears = sorted({g for p in self.meshes.values() for g in p.names})
        if gear not in gears:
            raise GearoptInputError(f"{what} {name!r}: target={target!r} names gear {gear!r}, not a gear of the "
                                    f"scene ({gears})")
        if not self.flank_meshes(target):
            loaded = sorted({f for m in self.meshes for f in self.loaded_flanks(m)})
            raise GearoptInputError(f"{what} {name!r}: no mesh of the scene loads flank {target!r} (loaded flanks: "
                                    f"{loaded})")
        for mesh in self.flank_meshes(target):
            i = self.loaded_flanks(mesh).index(target)
            if (mesh, mesh_variable_name(name, i)) in {(v.target, v.name) for v in self.scene.variables}:
                raise GearoptInputError(f"design variable {name!r} of flank {target!r} and "
                                        f"{mesh_variable_name(name, i)!r} of mesh {mesh!r} set the same tooth form")

    # -- microgeometry -------------------------------------------------------------------------------------------

    def base_microgeometry(self, mesh: str) -> Microgeometry:
        return self.scene.microgeometry.get(mesh, UNMODIFIED)

    def mesh_cases(self, mesh: str) -> list[LoadCase]:
        """Load cases at which the mesh's LTCA is evaluated: those its LTCA objectives and limits name (all when
        any of them names none), in the scene's order."""
        cases = list(self.graph.load_cases)
        wanted: set[str] = set()
        for q in (*self.scene.objectives, *self.scene.limits):
            if q.target == mesh and "ltca" in quantity_kind(q.quantity).needs:
                if q.load_cases is None:
                    return cases
                wanted.update(q.load_cases)
        return [lc for lc in cases if lc.name in wanted] or cases

    def minimum_relief(self, mesh: str) -> Microgeometry:
        cases = self.mesh_cases(mesh)
        if not cases:
            raise GearoptInputError(f"mesh {mesh!r}: tip-relief variables start from the minimum tip relief at the "
                                    f"first load case; the scene has no load case")
        pair = self.meshes[mesh]
        if float(pair.geometry()["helix_angle_deg"]) == 0.0:
            return min_tip_relief_design(pair, cases[0].mesh_torque_Nm(mesh),
                                         driving_gear=self.graph.driving_gear(mesh))
        # the thesis' minimum relief is a spur model: for a helical mesh, a starting guess from the spur pair of the
        # same transverse data (amounts) with starts at the helical mesh's own single-contact boundaries
        spur = replace(pair, helix_angle_deg=0.0, helix_hands=None)
        amounts = min_tip_relief_design(spur, cases[0].mesh_torque_Nm(mesh),
                                        driving_gear=self.graph.driving_gear(mesh)).tip_relief_um
        g = pair.geometry()
        starts = tuple(max(float(g["lpstc_roll_deg"][i]), float(g["hpstc_roll_deg"][i])) for i in range(2))
        return Microgeometry(tip_relief_um=amounts, tip_relief_start_roll_deg=starts, relief_shape="linear")

    def free_micro(self, mesh: str, i: int, field: str, values: Mapping[str, float] | None):
        """The free variable (or its value) setting ``field`` of gear ``i`` in ``mesh``: mesh- or flank-targeted."""
        for target, name in ((mesh, mesh_variable_name(field, i)), (self.loaded_flanks(mesh)[i], field)):
            if (target, name) in self.graph.variables:
                return values[f"{target}.{name}"] if values is not None else self.graph.variables[(target, name)]
        return None

    def _default_start(self, mesh: str, i: int) -> float:
        """Start of a free tip relief whose start is neither free nor given: where the thesis minimum relief of the
        first mesh loading that flank starts (one start per flank)."""
        first = self.flank_meshes(self.loaded_flanks(mesh)[i])[0]
        j = self.loaded_flanks(first).index(self.loaded_flanks(mesh)[i])
        return self.minimum_relief(first).tip_relief_start_roll_deg[j]

    def microgeometry(self, mesh: str, values: Mapping[str, float] | None = None) -> Microgeometry:
        """The mesh's microgeometry: fixed fields from ``scene.microgeometry``, free ones (mesh or flank targets) as
        symbols or at ``values`` (``"target.variable"`` keys)."""
        base = self.base_microgeometry(mesh)
        kw: dict[str, Any] = {"relief_smoothing_deg": self.options.model.relief_smoothing_deg}
        for field in MICRO_FIELDS:
            vals = list(getattr(base, field))
            for i in (0, 1):
                v = self.free_micro(mesh, i, field, values)
                vals[i] = vals[i] if v is None else v
            kw[field] = tuple(vals)
        starts = list(kw["tip_relief_start_roll_deg"])
        for i in (0, 1):
            if starts[i] is None and self.free_micro(mesh, i, "tip_relief_um", None) is not None:
                starts[i] = self._default_start(mesh, i)
        kw["tip_relief_start_roll_deg"] = tuple(starts)
        return replace(base, **kw)

    def microgeometry_at(self, values: Mapping[str, float], mesh: str) -> Microgeometry:
        """The mesh's microgeometry with the free amounts set to ``values`` (``"target.variable"`` keys)."""
        return self.microgeometry(mesh, values)

    def micro_bounds(self, target: str, name: str, kind) -> tuple[float | None, float | None, float | None]:
        """Default bounds and start of a micro variable of a mesh or a flank."""
        lo, hi, init = kind.lower, kind.upper, None
        if kind.target_kind == "mesh":
            uses = [(target, int(name.split("_")[2]) - 1)]
            field = name.replace(f"_{uses[0][1] + 1}_", "_")
        else:
            field = name
            uses = [(m, self.loaded_flanks(m).index(target)) for m in self.flank_meshes(target)]
        if field == "tip_relief_start_roll_deg":
            spans = [start_bounds(self.meshes[m].geometry(), i, self.options.model.start_margin_deg) for m, i in uses]
            lo, hi = max(s[0] for s in spans), min(s[1] for s in spans)
            if hi <= lo:
                raise GearoptInputError(f"design variable {name!r} of {target!r}: the meshes {[m for m, _ in uses]} "
                                        f"leave no common room for a tip relief start ({lo:.3f}..{hi:.3f} deg)")
            if any(self.graph.macro_free(m) for m, _ in uses):
                lo, hi = lo - START_WIDENING_DEG, hi + START_WIDENING_DEG
        mesh, i = uses[0]
        base = self.base_microgeometry(mesh)
        init = getattr(base, field)[i]
        if field.startswith("tip_relief") and not any(nm.is_numeric(a) and nm.to_float(a) > 0
                                                      for a in base.tip_relief_um):
            first = self.flank_meshes(self.loaded_flanks(mesh)[i])[0] if kind.target_kind == "flank" else mesh
            j = i if first == mesh else self.loaded_flanks(first).index(self.loaded_flanks(mesh)[i])
            init = getattr(self.minimum_relief(first), field)[j]
        return lo, hi, init

    # -- models --------------------------------------------------------------------------------------------------

    def ltca_meshes(self) -> list[str]:
        """Meshes with LTCA quantities, in the order of the scene's targets."""
        return [m for m, needs in self.needs.items() if "ltca" in needs]

    def positions(self, mesh: str):
        """The mesh's positions setting of its smooth LTCA: a set of fractions, or the uniform count."""
        return self.position_sets.get(mesh, self.options.model.positions)

    def positions_of(self, mesh: str) -> np.ndarray:
        """The mesh's positions of its smooth LTCA as fractions of a base pitch."""
        return position_fractions(self.positions(mesh))

    def _lead(self, mesh: str) -> bool:
        return any(self.free_micro(mesh, i, "lead_crown_um", None) is not None for i in (0, 1)) \
            or self.base_microgeometry(mesh).has_lead_modification

    def _ltca_speed(self, mesh: str) -> float | None:
        if "ltca_temperature" not in self.needs[mesh]:
            return None
        speeds = {lc.speed_rpm for lc in self.mesh_cases(mesh)}
        if len(speeds) != 1 or None in speeds:
            raise GearoptInputError(f"mesh {mesh!r}: contact temperature needs one speed_rpm for all load cases "
                                    f"(got {sorted(speeds, key=str)})")
        return self.graph.driver_speed_rpm(mesh, speeds.pop())

    def ltca_model(self, mesh: str):
        needs, o = self.needs[mesh], self.options
        speed = self._ltca_speed(mesh)
        common = dict(driving_gear=self.graph.driving_gear(mesh), stiffness=o.model.stiffness,
                      positions=self.positions(mesh),
                      lead_modification=self._lead(mesh), smoothing_um=o.model.smoothing_um,
                      count_width_um=o.model.count_width_um,
                      root_stress="ltca_root_stress" in needs, speed_rpm=speed,
                      bulk_temperature_C=o.temperature.bulk_temperature_C,
                      friction_coefficient=o.temperature.friction_coefficient)
        pair = self.graph.pair(mesh)
        if not self.graph.macro_free(mesh):
            if float(pair.geometry()["helix_angle_deg"]) != 0.0:
                common["slices"] = o.model.helical_slices
            return self.graph.model(f"ltca_smooth:{mesh}", lambda: LTCAModel(pair, **common), lambda m: (
                f"positions={m.layout.positions}, slices={m.layout.slices}, root_stress={m.root_stress}, "
                f"flash_temperature={speed is not None}"))
        helical = self.graph.helix_free() or float(self.meshes[mesh].geometry()["helix_angle_deg"]) != 0.0

        def build():
            eps_a, eps_b = self.graph.contact_ratio_bounds(mesh)
            return MacroLTCAModel(self.meshes[mesh], **common, helical=helical,
                                  slices=o.model.helical_slices if helical else None,
                                  load_cases=len(self.mesh_cases(mesh)), max_contact_ratio=eps_a,
                                  max_overlap_ratio=eps_b, engagement_width_mm=o.model.engagement_width_mm,
                                  relief_shape=self.base_microgeometry(mesh).relief_shape,
                                  relief_smoothing_deg=o.model.relief_smoothing_deg,
                                  derivative_steps=o.model.macro_derivative_order)

        return self.graph.model(f"ltca_macro:{mesh}", build, lambda m: (
            f"positions={m.positions}, slices={m.slices}, pairs={len(m.pair_index)}, root_stress={m.root_stress}, "
            f"flash_temperature={speed is not None}, symbolic macro geometry"))

    def lifted_start(self, values: Mapping[str, Any]) -> dict[str, np.ndarray]:
        """The lifted approaches consistent with the design variables of a start (``Problem.start_completion``):
        a start from other design values (a multi-start point, a neighbour of a front) would otherwise begin far
        from the force balance."""
        out = {}
        for mesh in self._lifted:
            try:
                out[f"{mesh}.approach_um"] = self._approach_at(mesh, values)
            except GearoptInputError:     # a start outside the model's range: Ipopt restores the balance itself
                continue
        return out

    def _approach_at(self, mesh: str, values: Mapping[str, Any]) -> np.ndarray:
        """Numeric approaches of a lifted mesh at the scalar variables of ``values`` (variable units)."""
        model, numbers = self._lifted[mesh]
        scalars = {k: float(np.asarray(v).ravel()[0]) for k, v in values.items() if np.size(v) == 1}
        return model.approach_start(self.microgeometry(mesh, scalars), numbers)

    def ltca(self, mesh: str):
        model = self.ltca_model(mesh)
        numbers = [lc.mesh_torque_Nm(mesh) for lc in self.mesh_cases(mesh)]
        if not numbers:
            raise GearoptInputError(f"mesh {mesh!r}: LTCA quantities need at least one load case")
        torques = [self.inputs.datum(f"torque_Nm[{mesh}]@{lc.name}", t, "N*m")
                   for lc, t in zip(self.mesh_cases(mesh), numbers)]
        detail = f"{len(numbers)} load case(s) at {', '.join(f'{t:g}' for t in numbers)} N m"
        if isinstance(model, MacroLTCAModel):
            def evaluate():
                micro = micro_vector(self.microgeometry(mesh), self.meshes[mesh].geometry())
                return model.evaluate(macro_vector(self.graph.pair(mesh)), micro, torques)
            return self.graph.model(f"ltca_evaluation:{mesh}", evaluate, detail)
        if self.options.model.approach == "nested":
            return self.graph.model(f"ltca_evaluation:{mesh}", lambda: model.evaluate(
                self.microgeometry(mesh), torques, **self._ltca_data(mesh, model)), detail)
        return self.graph.model(f"ltca_evaluation:{mesh}", lambda: self._lifted_ltca(mesh, model, torques, numbers),
                           f"{detail}, lifted approach")

    def _lifted_ltca(self, mesh: str, model: LTCAModel, torques: list, numbers: list):
        """The smooth LTCA in lifted form (``ltca_options["approach"] = "lifted"``): the approach of every position
        and load case is an NLP variable ``{mesh}.approach_um`` (started at the numeric approaches of the start
        design) held by the equality constraint ``{mesh}.approach_equilibrium`` (the force balance of each
        position, scaled by the largest mesh force), instead of Newton's method inside the model. Same optimum as
        the nested form; the NLP's graph is a few operations per spring, so its derivatives are cheap (measured
        in benchmarks/bench_studies.py)."""
        if not self._lifted:
            self.graph.problem.start_completion = self.lifted_start
        self._lifted[mesh] = (model, numbers)
        start = self._approach_at(mesh, {name: entry.init for name, entry in self.graph.problem._variables.items()})
        force = max(max(numbers), 1e-6) * float(model.layout.force_per_torque_N_per_Nm)
        delta = self.graph.problem.variable(f"{mesh}.approach_um", init=start, n=start.size, scale=APPROACH_SCALE_UM,
                                      unit="um")
        res = model.evaluate(self.microgeometry(mesh), torques, approach_um=delta, **self._ltca_data(mesh, model))
        self.graph.problem.subject_to(f"{mesh}.approach_equilibrium", nm.column(res.approach_residual_N), lower=0.0,
                                upper=0.0, scale=force, unit="N")
        self.graph.problem.subject_to(f"{mesh}.approach_closes_a_gap", nm.column(res.approach_floor_um), lower=0.0,
                                unit="um")
        return res

    def relieved_gears(self, mesh: str) -> list[int]:
        """Gears of ``mesh`` (0, 1) whose tip relief is made: a free amount, or a fixed one > 0."""
        base = self.base_microgeometry(mesh)
        return [i for i in (0, 1) if self.free_micro(mesh, i, "tip_relief_um", None) is not None
                or (nm.is_numeric(base.tip_relief_um[i]) and nm.to_float(base.tip_relief_um[i]) > 0.0)]

    def toleranced_ppte(self, mesh: str, lc: LoadCase):
        """``ppte_um_toleranced`` of ``mesh`` at ``lc`` in the NLP: per blended variant of its reliefs
        (:func:`~gearopt.contact.relief_tolerances.relief_variants` over the gears of :meth:`relieved_gears`), the
        log-sum-exp maximum minus minimum of its smooth TE at the mesh positions -- an upper bound of the sampled
        PPTE, above it by at most ``2 w ln(positions)`` (``toleranced_ppte_width_um``). The variants' LTCAs share
        the mesh's model; each is one evaluation over the mesh's load cases."""
        model = self.ltca_model(mesh)
        cases = self.mesh_cases(mesh)
        results = self.graph.model(f"ltca_variants:{mesh}", lambda: self._variant_ltcas(mesh, model),
                                   lambda r: f"{len(r)} relief tolerance variant(s)")
        if not results:
            raise GearoptInputError(f"ppte_um_toleranced[{mesh}]: nothing varies (no relieved gear, or tolerances "
                                    f"of 0); limit ppte_um instead")
        w = self.options.tolerance.toleranced_ppte_width_um
        l_idx = cases.index(lc)
        bounds = []
        for res in results:
            te = _te_column(res, model, l_idx, len(cases))
            bounds.append(-nm.column_softmin(-te, w) - nm.column_softmin(te, w))
        return nm.vcat(bounds)

    def _variant_ltcas(self, mesh: str, model) -> list:
        """The smooth LTCA of every blended relief variant of ``mesh`` at its load cases (the nested approach)."""
        torques = [self.inputs.datum(f"torque_Nm[{mesh}]@{lc.name}", lc.mesh_torque_Nm(mesh), "N*m")
                   for lc in self.mesh_cases(mesh)]
        variants = relief_variants(self.microgeometry(mesh), self.graph.geometry(mesh),
                                   self.options.tolerance.tolerances, self.relieved_gears(mesh), sharp=False)
        if isinstance(model, MacroLTCAModel):
            macro, geometry = macro_vector(self.graph.pair(mesh)), self.meshes[mesh].geometry()
            return [model.evaluate(macro, micro_vector(v.microgeometry, geometry), torques) for v in variants]
        data = self._ltca_data(mesh, model)
        return [model.evaluate(v.microgeometry, torques, **data) for v in variants]

    def _toleranced_meshes(self) -> set[str]:
        return {q.target for q in (*self.scene.objectives, *self.scene.limits) if q.quantity == "ppte_um_toleranced"}

    def _exact_toleranced_ppte(self, pair, mods: Microgeometry, torques: list[float], ltca_kw: dict,
                               nominal_um: list[float]) -> list[float]:
        """Largest exact PPTE of a mesh at each of ``torques`` over every variant of its reliefs as designed (gears
        with a relief > 0; sharp starts with ``relief_sharp_start``), the verdict's judgement; ``nominal_um`` where
        nothing varies. Each variant's LTCA at every torque at once (:func:`~gearopt.contact.ltca.ltca_torques`)."""
        relieved = [i for i in (0, 1) if float(mods.tip_relief_um[i]) > 0.0]
        variants = relief_variants(mods, pair.geometry(), self.options.tolerance.tolerances, relieved)
        if not variants:
            return list(nominal_um)
        ppte = np.array([[float(r.ppte_um) for r in ltca_torques(pair, torques, microgeometry=v.microgeometry,
                                                                 **ltca_kw)] for v in variants])
        return [float(v) for v in ppte.max(axis=0)]

    def _ltca_data(self, mesh: str, model: LTCAModel) -> dict[str, Any]:
        """A parametric build's LTCA data as NLP parameters (:meth:`LTCAModel.evaluate`'s data keywords), each
        declared only where a quantity of the mesh depends on it: the single-pair stiffness c' (every LTCA
        quantity; with ``stiffness="iso6336"`` or a number), the contact face width (a spur mesh with one face
        slice), Young's modulus (contact stress and temperature), the driving gear's speed and both gears' thermal
        contact coefficients (contact temperature)."""
        if not self.graph.parametric:
            return {}
        used = {q.quantity for q in (*self.scene.objectives, *self.scene.limits) if q.target == mesh}
        stiffness, data = self.options.model.stiffness, {}
        if stiffness == "iso6336" or (isinstance(stiffness, (int, float)) and not isinstance(stiffness, bool)):
            if stiffness == "iso6336":
                c0 = float(iso6336_stiffness(self.graph.pair(mesh))["single_stiffness"])
            else:
                c0 = float(stiffness)
            data["stiffness_factor"] = self.inputs.datum(f"single_pair_stiffness_N_per_mm_um[{mesh}]", c0,
                                                   "N/(mm*um)") / c0
        if model.layout.slices == 1 and model.layout.base_helix_angle_rad == 0.0:   # the face width scales exactly
            data["face_width_mm"] = self.inputs.datum(f"face_width_mm[{mesh}]", float(model.layout.face_width_mm), "mm")
        if used & {"max_contact_stress_MPa", "max_contact_temperature_C"}:
            data["E_MPa"] = self.inputs.datum(f"youngs_modulus_MPa[{mesh}]", model.E_MPa, "MPa")
        if model.speed_rpm and "max_contact_temperature_C" in used:
            data["speed_rpm"] = self.inputs.datum(f"speed_rpm[{mesh}]", model.speed_rpm, "rpm")
            names = self.meshes[mesh].names
            data["thermal_contact_coefficients"] = tuple(
                self.inputs.datum(f"thermal_contact_coefficient_N_per_mm_sqrt_s_K[{names[i]}]", b, "N/(mm*s^0.5*K)")
                for i, b in enumerate(model.thermal_contact_coefficients))
        return data

    def _contact_temperature(self, mesh: str, bulk_C, flash_K):
        """Bulk + flash temperature; in a parametric build the oil temperature and the friction coefficient are
        parameters (Blok's flash temperature is proportional to the friction coefficient)."""
        bulk = self.inputs.datum(f"oil_temperature_C[{mesh}]", bulk_C, "C")
        mu = self.options.temperature.friction_coefficient
        if self.graph.parametric and mu > 0.0:
            flash_K = flash_K * (self.inputs.datum(f"friction_coefficient[{mesh}]", mu, "") / mu)
        return bulk + flash_K

    def elements(self, name: str, target: str, lc: LoadCase):
        """Expression of an LTCA quantity of ``target`` at ``lc`` (TE column, spring vector or scalar)."""
        if name == "ppte_um_toleranced":
            return self.toleranced_ppte(target, lc)
        res, model = self.ltca(target), self.ltca_model(target)
        l_idx = self.mesh_cases(target).index(lc)
        L = len(self.mesh_cases(target))
        if isinstance(model, MacroLTCAModel):
            P = model.positions
            cols = slice(l_idx * P, (l_idx + 1) * P)

            def block(m):
                return nm.reshape(m[:, cols], int(m.shape[0]) * P, 1)

            if name == "ppte_um":
                return _te_column(res, model, l_idx, L)
            if name == "loaded_contact_ratio":
                return nm.column_sum(nm.reshape(res.loaded_pairs[:, cols], P, 1)) / P
            if name == "max_contact_stress_MPa":
                return block(res.contact_stress_squared_MPa2)
            if name == "max_root_stress_MPa":
                return nm.vcat([block(r) for r in res.root_stress_MPa])
            if name == "max_contact_temperature_C":
                return self._contact_temperature(target, res.bulk_temperature_C, block(res.flash_temperature_rise_K))
        if name == "ppte_um":
            return _te_column(res, model, l_idx, L)
        if name == "loaded_contact_ratio":
            lcr = res.loaded_contact_ratio
            return lcr if L == 1 else lcr[l_idx]
        if name == "max_contact_stress_MPa":
            return _on_path(res.contact_stress_squared_MPa2, model, l_idx)
        if name == "max_root_stress_MPa":
            return nm.vcat([_on_path(r, model, l_idx) for r in res.root_stress_MPa])
        if name == "max_contact_temperature_C":
            return self._contact_temperature(target, res.bulk_temperature_C,
                                             _on_path(res.flash_temperature_rise_K, model, l_idx))
        raise GearoptInputError(f"quantity {name!r} is not an LTCA quantity")

    # -- exact check ---------------------------------------------------------------------------------------------

    def exact_check(self, values: Mapping[str, float], evaluate=None, *, train=None,
                    positions: int | None = None, toleranced: bool | Sequence[str] = True,
                    fractions: bool = True, table: bool = True) -> pd.DataFrame | dict[str, np.ndarray]:
        """Exact LTCA (``check_positions``, the default slices) of every LTCA mesh at the optimum, per load case,
        beside the smooth model's values at the same design (``smooth_*``) and their relative differences
        (``*_error``, relative to the exact value). ``worst_fractions`` lists the mesh positions (fractions of a
        base pitch) of the exact TE's peak and trough, ``stress_fractions`` those where the exact contact stress,
        root stress and contact temperature peak (each a maximum over the mesh cycle: a semi-infinite limit like
        PPTE, refined the same way). ``positions``: a one-slice mesh's positions instead of ``check_positions``
        (coarser: the exact screen ranks designs with it). ``ppte_um_toleranced``: the largest exact PPTE over the
        relief variants of a mesh that a ``ppte_um_toleranced`` quantity names (``toleranced=False``: left out; a
        list of meshes: those). ``fractions=False``: without ``worst_fractions`` and ``stress_fractions`` (only the
        refinement reads them; the exact screen and polish do not). ``table=False``: the columns as numpy arrays
        (``{column: array}``, NaN where a row lacks the column) instead of a DataFrame -- the screen's and the
        polish's thousands of evaluations read a few columns, and building a DataFrame cost about as much as one
        exact LTCA."""
        rows, smooth = [], []
        variant_meshes = self._toleranced_meshes() if toleranced is True else set(toleranced or ())
        for mesh in self.ltca_meshes():
            mods = self.microgeometry_at(values, mesh)
            pair = self.graph.numeric_pair(mesh, values) if train is None else train.pairs[mesh]
            model = self.ltca_model(mesh)
            slices = default_slices(pair, mods)
            mesh_positions = (max(self.options.check.check_positions, self._model_positions(model))
                              if positions is None else int(positions)) if slices == 1 else default_positions(slices)
            speed = model.speed_rpm
            kw = dict(driving_gear=self.graph.driving_gear(mesh), stiffness=self.options.model.stiffness,
                      positions=mesh_positions, slices=slices, speed_rpm=speed,
                      bulk_temperature_C=self.options.temperature.bulk_temperature_C,
                      friction_coefficient=self.options.temperature.friction_coefficient)
            cases = self.mesh_cases(mesh)
            # the layout, gaps and load curves once for every load case of the mesh (one design, several torques)
            torques = [lc.mesh_torque_Nm(mesh) for lc in cases]
            results = ltca_torques(pair, torques, microgeometry=mods, **kw) if cases else []
            toleranced = self._exact_toleranced_ppte(pair, mods, torques, kw, [r.ppte_um for r in results]) \
                if cases and mesh in variant_meshes else None
            for k, (lc, r) in enumerate(zip(cases, results)):
                row = {"mesh": mesh, "load_case": lc.name, "torque_Nm": lc.mesh_torque_Nm(mesh), "slices": slices,
                       "ppte_um": r.ppte_um, "max_contact_stress_MPa": r.max_contact_stress_MPa,
                       "loaded_contact_ratio": r.loaded_contact_ratio}
                peaks = [r.contact_stress_MPa]
                if model.root_stress:
                    row["max_root_stress_MPa"] = max(r.max_root_stress_MPa)
                    peaks += list(r.root_stress_MPa)
                if speed is not None:
                    row["max_contact_temperature_C"] = r.max_flash_temperature_C
                    peaks.append(r.flash_temperature_rise_K)
                if fractions:
                    at = np.arange(mesh_positions) / mesh_positions
                    neighbours = self.options.refinement.refine_neighbours
                    row["worst_fractions"] = extreme_fractions(r.transmission_error_um, at, neighbours=neighbours)
                    row["stress_fractions"] = peak_fractions(peaks, at, neighbours)
                if toleranced is not None:
                    row["ppte_um_toleranced"] = toleranced[k]
                if evaluate is not None:
                    row["smooth_dense_ppte_um"] = self._dense_smooth_ppte(mesh, values, lc, mesh_positions)
                    smooth += [(row, q, self.elements(q, mesh, lc)) for q in SMOOTH_COMPARED if q in row]
                rows.append(row)
        # the smooth model's values in one evaluation (each mesh's LTCA once, not once per quantity and load case)
        for (row, q, _), v in zip(smooth, nm.evaluate_stacked(evaluate, [e for _, _, e in smooth])):
            s = _smooth_value(q, v)
            row[f"smooth_{q}"] = s
            row[f"{q}_error"] = abs(s - row[q]) / max(abs(row[q]), 1e-12)
        return pd.DataFrame(rows) if table else _columns(rows)

    def _dense_smooth_ppte(self, mesh: str, values: Mapping[str, float], lc: LoadCase, positions: int) -> float:
        """PPTE of the smooth model at the optimum on the exact check's uniform grid: separates the error of the
        smoothing (dense smooth vs exact) from that of the NLP's sampling (NLP vs dense smooth)."""
        model = self.ltca_model(mesh)
        mods, torque = self.microgeometry_at(values, mesh), lc.mesh_torque_Nm(mesh)
        o = self.options
        if isinstance(model, MacroLTCAModel):
            key = f"ltca_macro_dense:{mesh}"
            dense = self.graph.cache.models.get(key) or MacroLTCAModel(
                self.meshes[mesh], driving_gear=model.driving_gear, stiffness=o.model.stiffness, positions=positions,
                slices=model.slices, helical=model.helical, max_contact_ratio=model.max_contact_ratio,
                max_overlap_ratio=model.max_overlap_ratio, smoothing_um=model.smoothing_um,
                engagement_width_mm=model.engagement_width_mm, relief_shape=model.relief_shape,
                relief_smoothing_deg=model.relief_smoothing_deg)
            self.graph.cache.models[key] = dense
            pair = self.graph.numeric_pair(mesh, values)
            r = dense.evaluate(macro_vector(pair), micro_vector(mods, self.meshes[mesh].geometry()), [torque])
            return float(r.ppte_um[0])
        dense = LTCAModel(self.meshes[mesh], driving_gear=model.layout.driving_gear, stiffness=o.model.stiffness,
                          positions=positions, slices=model.layout.slices, smoothing_um=model.smoothing_um)
        return float(dense.evaluate(mods, torque).ppte_um)

    def _model_positions(self, model) -> int:
        return model.positions if isinstance(model, MacroLTCAModel) else model.layout.positions


def _columns(rows: list[dict]) -> dict[str, np.ndarray]:
    """Rows (dicts) as columns of numpy arrays, in the order a DataFrame of them has its columns (NaN where a row
    lacks a column)."""
    names = list(dict.fromkeys(k for r in rows for k in r))
    return {k: _column([r.get(k, np.nan) for r in rows]) for k in names}


def _column(values: list) -> np.ndarray:
    """A 1-D array of ``values``: numbers or strings as such; an object array where they are sequences themselves
    (positions of extremes) or strings mixed with a missing value's NaN (as a DataFrame keeps them)."""
    sequences = any(isinstance(v, (list, tuple, np.ndarray)) for v in values)
    texts = [isinstance(v, str) for v in values]
    if not sequences and (all(texts) or not any(texts)):
        return np.asarray(values)
    out = np.empty(len(values), dtype=object)
    for i, v in enumerate(values):
        out[i] = v
    return out


def _smooth_value(q: str, v: np.ndarray) -> float:
    """The smooth model's ``q`` from the values of its elements (a TE column, squared stresses, ...)."""
    if q == "ppte_um":
        return float(np.ptp(v))
    return float(np.sqrt(max(v.max(), 0.0))) if q == "max_contact_stress_MPa" else float(v.max())


def _te_column(res, model, l_idx: int, cases: int):
    """The TE column [um] (one value per mesh position) of load case ``l_idx`` of an LTCA evaluation ``res`` of
    ``model`` over ``cases`` load cases."""
    if isinstance(model, MacroLTCAModel):
        return res.transmission_error_um[:, l_idx]
    return nm.reshape(res.transmission_error_um, model.layout.positions, cases)[:, l_idx]


def _on_path(matrix, model: LTCAModel, l_idx: int):
    """Elements of an (N, P*L) spring matrix at load case ``l_idx`` where the spring is on the path of contact."""
    P = model.layout.positions
    on = model.layout.on_path.reshape(P, -1).T                       # (N, P), pair-major springs
    idx = np.flatnonzero(on.reshape(-1, order="F")).tolist()
    block = matrix[:, l_idx * P:(l_idx + 1) * P]
    return nm.reshape(block, int(on.size), 1)[idx]


__all__ = ["ContactModels", "MICRO_FIELDS", "mesh_variable_name", "parse_flank", "corner_values", "peak_fractions"]
