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

Limits of the present form: the LTCA needs numeric macro geometry, so a scene cannot free macro variables (profile
shift, tip diameters, face width) of a mesh whose LTCA quantities it asks for -- solve the macro scene first and
pass its pair to the micro scene (a clear error says so). Contact temperature needs one speed for all load cases of
a mesh (the LTCA model is built for one speed).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field, replace
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pandas as pd

from .. import numerics as nm
from ..contact.layout import default_positions, default_slices
from ..contact.ltca import ltca
from ..contact.ltca_smooth import DEFAULT_SMOOTHING_UM, LTCAModel
from ..contact.microgeometry import Microgeometry
from ..errors import GearoptInputError, InfeasibleProblemError, ViolatedConstraint
from ..geometry.pair import GearPair
from ..geometry.train import GearTrain
from .microgeometry_nlp import _start_bounds, min_tip_relief_design
from ..nlp.problem import Problem
from ..nlp.result import ProblemResult
from .scene_spec import DesignVariable, Limit, LoadCase, Objective
from .scene_terms import QuantityKind, quantity_kind, variable_kind

DEFAULT_LTCA_OPTIONS: dict[str, Any] = {
    "positions": 40, "smoothing_um": DEFAULT_SMOOTHING_UM, "stiffness": "iso6336", "relief_smoothing_deg": 0.1,
    "bulk_temperature_C": 100.0, "friction_coefficient": 0.06, "check_positions": 1280, "start_margin_deg": 0.25}
"""LTCA settings of a scene (override per scene with ``ltca_options``): the NLP's sampled positions and contact
smoothing (:class:`LTCAModel`), the relief-start blend of the design, the oil temperature and friction of the flash
temperature, and the positions of the exact-LTCA check of the optimum (benchmarks/results/ltca.json)."""


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

    def build(self, *, parametric: bool = False) -> "BuiltScene":
        """Build the models the scene needs (each once) and its NLP; see :class:`BuiltScene`. ``parametric``: the
        data the quantities use (load-case torques and joint demands, the oil temperature and the friction
        coefficient of contact temperatures) enter the NLP as :class:`Problem` parameters named like
        ``torque_Nm[crank-cam]@design`` (for parametric sensitivities and sampling, :mod:`gearopt.studies`)."""
        return BuiltScene(self, parametric=parametric)


class BuiltScene:
    """A built scene: its models (``models``, in build order ``built``), its :class:`Problem` and :meth:`solve`."""

    def __init__(self, scene: Scene, *, parametric: bool = False):
        self.scene = scene
        self.parametric = bool(parametric)
        self.data_parameters: dict[str, dict[str, Any]] = {}
        self.models: dict[str, Any] = {}
        self._log: list[dict[str, Any]] = []
        self._opts = {**DEFAULT_LTCA_OPTIONS, **dict(scene.ltca_options)}
        unknown = set(scene.ltca_options) - set(DEFAULT_LTCA_OPTIONS)
        if unknown:
            raise GearoptInputError(f"ltca_options {sorted(unknown)} are unknown ({sorted(DEFAULT_LTCA_OPTIONS)})")
        self._meshes = scene.meshes()
        self._needs = scene.needs()
        self._check_targets()
        self.problem = Problem(name=scene.name)
        self._records: list[dict[str, Any]] = []
        self._objective_terms: list[Any] = []
        self.load_cases = [self._resolve_load_case(lc) for lc in scene.load_cases]
        self._variables = self._declare_variables()
        for obj in scene.objectives:
            self._add_objective(obj)
        for lim in scene.limits:
            self._add_limit(lim)
        if not self._objective_terms:
            raise GearoptInputError(f"scene {scene.name!r} has no objective")
        self.problem.minimize(sum(self._objective_terms[1:], self._objective_terms[0]))

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
        for mesh, needs in self._needs.items():
            macro = [v.name for v in self.scene.variables
                     if v.target == mesh and variable_kind(v.name).group == "macro"]
            if macro and "ltca" in needs:
                raise GearoptInputError(
                    f"mesh {mesh!r}: macro variables {macro} and LTCA quantities in one scene are not supported (the "
                    f"LTCA needs numeric macro geometry): solve the macro scene first and pass its pair")
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
            torques[mesh] = float(stat * sim.mesh_base_radii_mm[mesh][0] * 1e-3)
        joints = {t for t, needs in self._needs.items() if "joint" in needs}
        jt, ja = {}, {}
        for joint in sorted(joints):
            w = walk_off_history(model, sim, joint)
            jt[joint] = float(np.max(np.abs(w["joint_torque_Nm"])))
            ja[joint] = float(np.max(np.abs(w["axial_force_N"])))
        return LoadCase(name=lc.name, torque_Nm=torques, speed_rpm=lc.speed_rpm, joint_torque_Nm=jt,
                        joint_axial_force_N=ja)

    def _declare_variables(self) -> dict[tuple[str, str], Any]:
        out: dict[tuple[str, str], Any] = {}
        for v in self.scene.variables:
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
            init = float(np.clip(init if init is not None else 0.5 * (lo + hi), lo, hi))
            out[(v.target, v.name)] = self.problem.variable(
                f"{v.target}.{v.name}", init=init, lower=lo, upper=hi, scale=v.scale or kind.scale, unit=kind.unit)
        return out

    def _variable_defaults(self, v: DesignVariable, kind) -> tuple[float | None, float | None, float | None]:
        """Default bounds and start of a variable from the target's present design."""
        lo, hi, init = kind.lower, kind.upper, None
        if kind.target_kind == "mesh":
            pair = self._meshes[v.target]
            if kind.group == "macro":
                g = pair.geometry()
                i = 0 if v.name.endswith("1_mm") else 1
                init = {"profile_shift_1": pair.profile_shifts[0], "face_width_mm": pair.face_width_mm[0]}.get(
                    v.name, g["tip_diameter_mm"][i])
            else:
                gear = int(v.name.split("_")[2]) - 1
                base = self._base_microgeometry(v.target)
                field_name = v.name.replace(f"_{gear + 1}_", "_")
                if v.name.startswith("tip_relief") and "start" in v.name:
                    lo, hi = _start_bounds(pair.geometry(), gear, self._opts["start_margin_deg"])
                init = getattr(base, field_name)[gear]
                if v.name.startswith("tip_relief") and not _has_tip_relief(base):
                    init = getattr(self._minimum_relief(v.target), field_name)[gear]
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

    def _base_microgeometry(self, mesh: str) -> Microgeometry:
        return self.scene.microgeometry.get(mesh, Microgeometry())

    def _minimum_relief(self, mesh: str) -> Microgeometry:
        cases = self._mesh_cases(mesh)
        torque = cases[0].mesh_torque_Nm(mesh) if cases else None
        if torque is None:
            raise GearoptInputError(f"mesh {mesh!r}: tip-relief variables start from the minimum tip relief at the "
                                    f"first load case; the scene has no load case")
        return min_tip_relief_design(self._meshes[mesh], torque, driving_gear=self._driving_gear(mesh))

    def _mesh_cases(self, mesh: str) -> list[LoadCase]:
        return [lc for lc in (getattr(self, "load_cases", None) or self.scene.load_cases)]

    # -- models ------------------------------------------------------------------------------------------------

    def _free(self, target: str, group: str) -> dict[str, Any]:
        return {name: x for (t, name), x in self._variables.items()
                if t == target and variable_kind(name).group == group}

    def _pair(self, mesh: str) -> GearPair:
        macro = self._free(mesh, "macro")

        def build():
            pair = self._meshes[mesh]
            if "profile_shift_1" in macro:
                x1 = macro["profile_shift_1"]
                pair = replace(pair, profile_shifts=(x1, pair.profile_shifts[0] + pair.profile_shifts[1] - x1),
                               tip_diameters_mm=None)
            if "face_width_mm" in macro:
                pair = replace(pair, face_width_mm=(macro["face_width_mm"], macro["face_width_mm"]))
            if "tip_diameter_1_mm" in macro or "tip_diameter_2_mm" in macro:
                d = pair.geometry()["tip_diameter_mm"]
                pair = replace(pair, tip_diameters_mm=(macro.get("tip_diameter_1_mm", d[0]),
                                                       macro.get("tip_diameter_2_mm", d[1])))
            return pair

        detail = f"symbolic in {sorted(macro)}" if macro else "numeric"
        return self._model(f"geometry:{mesh}", build, detail)

    def _geometry(self, mesh: str) -> dict:
        return self._pair(mesh).geometry()

    def _ltca_model(self, mesh: str) -> LTCAModel:
        needs, o = self._needs[mesh], self._opts
        pair = self._pair(mesh)
        lead = bool(self._free(mesh, "micro").keys() & {"lead_crown_1_um", "lead_crown_2_um"}) \
            or self._base_microgeometry(mesh).has_lead_modification
        speed = None
        if "ltca_temperature" in needs:
            speeds = {lc.speed_rpm for lc in self._mesh_cases(mesh)}
            if len(speeds) != 1 or None in speeds:
                raise GearoptInputError(f"mesh {mesh!r}: contact temperature needs one speed_rpm for all load cases "
                                        f"(got {sorted(speeds, key=str)})")
            speed = self._driver_speed_rpm(mesh, speeds.pop())

        def build():
            return LTCAModel(pair, driving_gear=self._driving_gear(mesh), stiffness=o["stiffness"],
                             positions=o["positions"], lead_modification=lead, smoothing_um=o["smoothing_um"],
                             root_stress="ltca_root_stress" in needs, speed_rpm=speed,
                             bulk_temperature_C=o["bulk_temperature_C"],
                             friction_coefficient=o["friction_coefficient"])

        return self._model(f"ltca_smooth:{mesh}", build, lambda m: (
            f"positions={m.layout.positions}, slices={m.layout.slices}, root_stress={m.root_stress}, "
            f"flash_temperature={speed is not None}"))

    def _driver_speed_rpm(self, mesh: str, crank_speed_rpm: float) -> float:
        name = self._meshes[mesh].names[self._driving_gear(mesh) - 1]
        train = self.scene.train
        return train.gear_speed_rpm(name, crank_speed_rpm) if train is not None else crank_speed_rpm

    def _microgeometry(self, mesh: str, values: Mapping[str, float] | None = None) -> Microgeometry:
        """The mesh's microgeometry: fixed fields from ``scene.microgeometry``, free ones as symbols (or at
        ``values``, keyed ``"mesh.variable"``). A free relief amount whose start is neither free nor given starts
        where the thesis minimum relief starts."""
        base, free = self._base_microgeometry(mesh), self._free(mesh, "micro")
        if values is not None:
            free = {name: values[f"{mesh}.{name}"] for name in free}
        kw: dict[str, Any] = {"relief_smoothing_deg": self._opts["relief_smoothing_deg"]}
        for fname in ("tip_relief_um", "tip_relief_start_roll_deg", "profile_crown_um", "lead_crown_um"):
            stem = fname.replace("_um", "").replace("_start_roll_deg", "")
            vals = list(getattr(base, fname))
            for i in (0, 1):
                vals[i] = free.get(f"{stem}_{i + 1}{fname[len(stem):]}", vals[i])
            kw[fname] = tuple(vals)
        starts = list(kw["tip_relief_start_roll_deg"])
        for i in (0, 1):
            if starts[i] is None and f"tip_relief_{i + 1}_um" in free:
                starts[i] = self._minimum_relief(mesh).tip_relief_start_roll_deg[i]
        kw["tip_relief_start_roll_deg"] = tuple(starts)
        return replace(base, **kw)

    def _ltca(self, mesh: str):
        model = self._ltca_model(mesh)
        numbers = [lc.mesh_torque_Nm(mesh) for lc in self._mesh_cases(mesh)]
        if not numbers:
            raise GearoptInputError(f"mesh {mesh!r}: LTCA quantities need at least one load case")
        torques = [self._datum(f"torque_Nm[{mesh}]@{lc.name}", t, "N*m")
                   for lc, t in zip(self._mesh_cases(mesh), numbers)]
        return self._model(f"ltca_evaluation:{mesh}", lambda: model.evaluate(self._microgeometry(mesh), torques),
                           f"{len(torques)} load case(s) at {', '.join(f'{t:g}' for t in numbers)} N m")

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
        return self._model(f"iso6336_rating:{mesh}@{lc.name}", lambda: rate_iso6336(
            self._pair(mesh), lc.mesh_torque_Nm(mesh), self._driver_speed_rpm(mesh, lc.speed_rpm),
            driving_gear=self._driving_gear(mesh), **opts), f"ISO 6336 rating (computed factors) at {lc.name}")

    def _joint(self, joint: str, lc: LoadCase | None) -> dict:
        from ..joints import joint_capacity

        overrides = {variable_kind(name).key or name: x for name, x in self._free(joint, "joint").items()}
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

    # -- quantities --------------------------------------------------------------------------------------------

    def _elements(self, kind: QuantityKind, target: str, lc: LoadCase | None, options: Mapping[str, Any]):
        """The quantity's expression: a scalar, a vector (shape max/min), the TE column (ppte) or a dict (named)."""
        name = kind.name
        if kind.target_kind == "mesh" and "ltca" in kind.needs:
            res, model = self._ltca(target), self._ltca_model(target)
            l_idx = self._mesh_cases(target).index(lc)
            P, L = model.layout.positions, len(self._mesh_cases(target))
            if name == "ppte_um":
                return nm.reshape(res.transmission_error_um, P, L)[:, l_idx]
            if name == "loaded_contact_ratio":
                lcr = res.loaded_contact_ratio
                return lcr if L == 1 else lcr[l_idx]
            if name == "max_contact_stress_MPa":
                return _on_path(res.contact_stress_squared_MPa2, model, l_idx)
            if name == "max_root_stress_MPa":
                return nm.vcat([_on_path(r, model, l_idx) for r in res.root_stress_MPa])
            if name == "max_contact_temperature_C":
                bulk = self._datum(f"oil_temperature_C[{target}]", res.bulk_temperature_C, "C")
                flash = _on_path(res.flash_temperature_rise_K, model, l_idx)
                mu = self._opts["friction_coefficient"]
                if self.parametric and mu > 0.0:     # Blok's flash temperature is proportional to the friction
                    flash = flash * (self._datum(f"friction_coefficient[{target}]", mu, "") / mu)
                return bulk + flash
        if kind.target_kind == "mesh" and "iso6336_rating" in kind.needs:
            sf = self._rating(target, lc).safety_factors
            if name in ("contact_safety_factor", "root_safety_factor"):
                return nm.vcat(list(sf["S_H" if name == "contact_safety_factor" else "S_F"]))
            return sf["S_B" if name == "scuffing_safety_factor_flash" else "S_intS"]
        if kind.target_kind == "mesh" and "iso6336" in kind.needs:
            iso = self._iso(target, lc)
            if name.startswith("root_"):
                key = "sigma_F_MPa" if name == "root_stress_iso6336_MPa" else "safety_factor"
                return nm.vcat([iso["root"][g][key] for g in ("gear1", "gear2")])
            key = "sigma_H_MPa" if name == "contact_stress_iso6336_MPa" else "safety_factor"
            return nm.vcat(list(iso["contact"][key]))
        if kind.target_kind == "mesh":
            g = self._geometry(target)
            if name == "geometry_limits":
                return self._pair(target).constraints(**dict(options))
            if name == "min_tip_thickness_mm":
                return nm.vcat(list(g["tip_thickness_mm"]))
            if name.startswith("tip_thickness_"):
                return g["tip_thickness_mm"][int(name[len("tip_thickness_")]) - 1]
            return g[name]
        if kind.target_kind == "joint":
            cap = self._joint(target, lc)
            if not kind.per_load_case:
                return cap[name]
            torque_Nm, axial_N = _demand(lc, target, "joint_torque_Nm"), _demand(lc, target, "joint_axial_force_N")

            def torque():   # a datum becomes a parameter only where a quantity uses it (Opti drops unused ones)
                return self._datum(f"joint_torque_Nm[{target}]@{lc.name}", torque_Nm, "N*m")

            def axial():
                return self._datum(f"joint_axial_force_N[{target}]@{lc.name}", axial_N, "N")
            if name == "torque_margin":
                return _margin(cap["torque_capacity_Nm"], torque(), target, "torque", torque_Nm)
            if name == "axial_margin":
                return _margin(cap["axial_capacity_N"], axial(), target, "axial force", axial_N)
            from ..joints.walk_off import joint_margins
            return joint_margins(cap["type"], torque(), axial(), cap["torque_capacity_Nm"],
                                 cap["axial_capacity_N"])["slip_utilisation"]
        blank = self._blank(target)
        return blank.backup_ratio if name == "rim_backup_ratio" else getattr(blank, name)()

    def _cases(self, kind: QuantityKind, only: Sequence[str] | None) -> list[LoadCase | None]:
        if not kind.per_load_case:
            return [None]
        cases = self.load_cases
        if only is not None:
            missing = set(only) - {lc.name for lc in cases}
            if missing:
                raise GearoptInputError(f"load_cases {sorted(missing)} are not load cases of the scene")
            cases = [lc for lc in cases if lc.name in only]
        if not cases:
            raise GearoptInputError(f"quantity {kind.name!r} is evaluated per load case; the scene has none")
        return cases

    def _initial(self, expr) -> np.ndarray:
        """Value of an expression at the problem's initial guess (starts of epigraph variables)."""
        if nm.is_numeric(expr):
            return np.atleast_1d(np.asarray(expr, dtype=float))
        opti = self.problem.opti
        return np.atleast_1d(np.asarray(opti.value(expr, opti.initial()), dtype=float)).ravel()

    def _label(self, quantity: str, target: str, lc: LoadCase | None) -> str:
        return f"{quantity}[{target}]" + (f"@{lc.name}" if lc is not None else "")

    def _ppte(self, te, label: str):
        """PPTE of a TE column by its epigraph: hi >= te >= lo, PPTE = hi - lo (exact at a minimum or an upper limit)."""
        start = self._initial(te)
        p, n = self.problem, int(np.size(start))
        hi = p.variable(f"{label}.te_max_um", init=float(start.max()), scale=5.0, unit="um")
        lo = p.variable(f"{label}.te_min_um", init=float(start.min()), scale=5.0, unit="um")
        p.subject_to(f"{label}.te_below_max", nm.repeat_rows(hi, n) - te, lower=0.0, unit="um")
        p.subject_to(f"{label}.te_above_min", te - nm.repeat_rows(lo, n), lower=0.0, unit="um")
        return hi - lo

    def _add_objective(self, obj: Objective) -> None:
        kind = quantity_kind(obj.quantity)
        if kind.shape == "named":
            raise GearoptInputError(f"{obj.quantity!r} is a set of limits, not an objective")
        minimise = obj.sense == "min"
        if (kind.shape in ("max", "ppte") and not minimise) or (kind.shape == "min" and minimise):
            raise GearoptInputError(f"objective {obj.quantity!r} with sense={obj.sense!r}: the {kind.shape} of a set "
                                    f"can only be {'minimised' if kind.shape != 'min' else 'maximised'} smoothly")
        per_case = []
        for lc in self._cases(kind, None):
            label = self._label(obj.quantity, obj.target, lc)
            expr = self._elements(kind, obj.target, lc, {})
            self._record(label, obj.quantity, obj.target, lc, kind, expr, None, None, "objective")
            if kind.shape == "ppte":
                f = self._ppte(expr, label)
            elif kind.shape in ("max", "min"):
                start = self._initial(expr)
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
            starts = [float(self._initial(x).max()) for x in per_case]
            z = self.problem.variable(label, init=max(starts) if minimise else min(starts), scale=kind.scale,
                                      unit=kind.unit)
            gap = nm.vcat([z - x if minimise else x - z for x in per_case])
            self.problem.subject_to(f"{label}.epigraph", gap, lower=0.0, unit=kind.unit)
            f = z
        scale = obj.scale or kind.scale
        self._objective_terms.append((obj.weight / scale) * (f if minimise else -f))

    def _add_limit(self, lim: Limit) -> None:
        kind = quantity_kind(lim.quantity)
        if kind.shape == "named":
            margins = self._elements(kind, lim.target, None, lim.options)
            for name, expr in margins.items():
                label = f"{lim.target}.{name}"
                self._record(label, name, lim.target, None, kind, expr, 0.0, None, "limit")
                self.problem.subject_to(label, expr, lower=0.0, unit="mm" if name.endswith("_mm") else "")
            return
        if kind.shape in ("max", "ppte") and lim.lower is not None:
            raise GearoptInputError(f"Limit {lim.quantity!r}: a lower limit on the largest value of a set is not a "
                                    f"smooth constraint; give an upper limit")
        if kind.shape == "min" and lim.upper is not None:
            raise GearoptInputError(f"Limit {lim.quantity!r}: an upper limit on the smallest value of a set is not a "
                                    f"smooth constraint; give a lower limit")
        for lc in self._cases(kind, lim.load_cases):
            label = self._label(lim.quantity, lim.target, lc)
            expr = self._elements(kind, lim.target, lc, lim.options)
            self._record(label, lim.quantity, lim.target, lc, kind, expr, lim.lower, lim.upper, "limit")
            if kind.shape == "ppte":
                expr = self._ppte(expr, label)
            lower, upper, scale, unit = lim.lower, lim.upper, kind.scale, kind.unit
            if kind.squared:
                upper, scale, unit = upper ** 2, upper ** 2 / 100.0, f"({unit})^2"
            if nm.is_numeric(expr):
                _check_constant(label, expr, lower, upper, unit)
                continue
            self.problem.subject_to(label, expr, lower=lower, upper=upper, scale=scale, unit=unit)

    def _record(self, label, quantity, target, lc, kind, expr, lower, upper, role) -> None:
        self._records.append({"label": label, "quantity": quantity, "target": target,
                              "load_case": lc.name if lc is not None else "", "kind": kind, "expr": expr,
                              "lower": lower, "upper": upper, "role": role})

    # -- data as parameters, quantity expressions (hooks of gearopt.studies) --------------------------------------

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

    # -- solve -------------------------------------------------------------------------------------------------

    def solve(self, *, starts: int = 1, seed: int = 0, verbose: bool = False, check: bool = True,
              **ipopt) -> "SceneResult":
        """Solve the scene's NLP (Ipopt). Raises a :class:`~gearopt.errors.SolveError` subclass naming the violated
        constraints on failure.

        ``starts`` > 1: the declared start plus ``starts - 1`` Latin-hypercube points of the design variables inside
        their bounds (:func:`gearopt.nlp.multistart.multistart`, ``seed``); the best optimum is returned and
        ``SceneResult.starts`` tables every start with the success rate. ``check``: re-evaluate the optimum of every
        mesh with LTCA quantities by the exact LTCA at ``check_positions`` (``SceneResult.exact_check``)."""
        starts_table = None
        if starts > 1:
            names = [f"{t}.{name}" for (t, name) in self._variables]
            ms = self.problem.multistart(starts - 1, seed=seed, variables=names, include_initial=True,
                                         verbose=verbose, **ipopt)
            solved, starts_table = ms.best, ms.table
        else:
            solved = self.problem.solve(verbose=verbose, **ipopt)
        values = {f"{t}.{name}": float(np.asarray(solved.values[f"{t}.{name}"]).ravel()[0])
                  for (t, name) in self._variables}
        table = self._quantity_table(solved)
        exact = self._exact_check(values) if check else pd.DataFrame()
        return SceneResult(scene=self.scene.name, values=values, solve=solved, quantities=table, exact_check=exact,
                           microgeometry={m: self.microgeometry_at(values, m) for m in self._ltca_meshes()},
                           built=self.build_table, starts=starts_table, source=self)

    def _ltca_meshes(self) -> list[str]:
        return [m for m, needs in self._needs.items() if "ltca" in needs]

    def microgeometry_at(self, values: Mapping[str, float], mesh: str) -> Microgeometry:
        """The mesh's microgeometry with the free amounts set to ``values`` (``"mesh.variable"`` keys)."""
        return self._microgeometry(mesh, values)

    def _quantity_table(self, solved: ProblemResult) -> pd.DataFrame:
        rows = []
        for r in self._records:
            kind, expr = r["kind"], r["expr"]
            v = np.atleast_1d(np.asarray(expr if nm.is_numeric(expr) else solved.value(expr), dtype=float))
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

    def _exact_check(self, values: Mapping[str, float]) -> pd.DataFrame:
        """Exact LTCA (``check_positions``, the default slices) of every LTCA mesh at the optimum, per load case."""
        rows = []
        for mesh in self._ltca_meshes():
            mods = self.microgeometry_at(values, mesh)
            pair, model = self._meshes[mesh], self._ltca_model(mesh)
            slices = default_slices(pair, mods)
            positions = max(int(self._opts["check_positions"]), model.layout.positions) if slices == 1 \
                else default_positions(slices)
            speed = model.speed_rpm if getattr(model, "speed_rpm", None) is not None else None
            for lc in self._mesh_cases(mesh):
                key = f"exact_ltca:{mesh}@{lc.name}"
                r = self._model(key, lambda: ltca(
                    pair, lc.mesh_torque_Nm(mesh), driving_gear=self._driving_gear(mesh), microgeometry=mods,
                    stiffness=model.layout.stiffness, positions=positions, slices=slices, speed_rpm=speed,
                    bulk_temperature_C=self._opts["bulk_temperature_C"],
                    friction_coefficient=self._opts["friction_coefficient"]),
                    f"positions={positions}, slices={slices}")
                row = {"mesh": mesh, "load_case": lc.name, "torque_Nm": lc.mesh_torque_Nm(mesh),
                       "ppte_um": r.ppte_um, "max_contact_stress_MPa": r.max_contact_stress_MPa,
                       "loaded_contact_ratio": r.loaded_contact_ratio}
                if model.root_stress:
                    row["max_root_stress_MPa"] = max(r.max_root_stress_MPa)
                if speed is not None:
                    row["max_contact_temperature_C"] = r.max_flash_temperature_C
                rows.append(row)
        return pd.DataFrame(rows)


@dataclass
class SceneResult:
    """The solved scene: ``values`` (``"target.variable"`` -> value in the variable's unit), ``quantities`` (every
    objective and limit quantity at the optimum: value, bounds, margin, unit -- the true maximum/PPTE, not the
    epigraph bound), ``exact_check`` (exact LTCA of the optimum), ``microgeometry`` per LTCA mesh, ``solve``
    (:class:`ProblemResult`: constraint and variable tables, multipliers), ``built`` (the build table) and
    ``starts`` (the multi-start table, when ``solve(starts=n)``), ``source`` (the :class:`BuiltScene` solved; the
    studies of :mod:`gearopt.studies` start from it)."""

    scene: str
    values: dict[str, float]
    solve: ProblemResult
    quantities: pd.DataFrame
    exact_check: pd.DataFrame
    microgeometry: dict[str, Microgeometry]
    built: pd.DataFrame
    starts: pd.DataFrame | None = None
    source: Any = field(default=None, repr=False, compare=False)

    @property
    def success_rate(self) -> float:
        """Fraction of the multi-start solves that converged (1.0 for a single successful solve)."""
        return 1.0 if self.starts is None else float(self.starts["success"].mean())


def _has_tip_relief(mods: Microgeometry) -> bool:
    return any(nm.is_numeric(a) and nm.to_float(a) > 0 for a in mods.tip_relief_um)


def _on_path(matrix, model: LTCAModel, l_idx: int):
    """Elements of an (N, P*L) spring matrix at load case ``l_idx`` where the spring is on the path of contact."""
    P = model.layout.positions
    on = model.layout.on_path.reshape(P, -1).T                       # (N, P), pair-major springs
    idx = np.flatnonzero(on.reshape(-1, order="F")).tolist()
    block = matrix[:, l_idx * P:(l_idx + 1) * P]
    return nm.reshape(block, int(on.size), 1)[idx]


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


def _demand(lc: LoadCase, joint: str, what: str) -> float:
    table = getattr(lc, what)
    if joint not in table:
        raise GearoptInputError(f"LoadCase {lc.name!r} gives no {what} for joint {joint!r} (joint margins need it)")
    return float(table[joint])


def _margin(capacity, demand, joint: str, what: str, nominal: float):
    """``capacity / |demand|``; ``nominal``: the demand's value (``demand`` may be its parameter)."""
    if nominal == 0.0:
        raise GearoptInputError(f"joint {joint!r}: the {what} demand is zero, its margin is infinite (drop the limit)")
    return capacity / abs(demand)


__all__ = ["Scene", "BuiltScene", "SceneResult", "LoadCase", "DesignVariable", "Objective", "Limit",
           "DEFAULT_LTCA_OPTIONS"]
