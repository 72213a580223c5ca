"""A torsional model of any gear system with a generic driving torque (``[excitation]``): one node per gear, the
meshes of the system's train, the driving torque on the excitation gear and a load on every terminal gear, as a
:class:`~gearopt.dynamics.network.TorsionalNetwork` (issue 26: every entry point works on any train).

:func:`train_model` returns a :class:`TrainModel` with the API of the engine's
:class:`~gearopt.cases.timing_train.TimingModel` (``simulate``, ``simulator``, ``natural_frequencies_Hz``,
``network``, ``train``, ``mesh_table``, ``kind``, ``data``, ``gear_nodes``), so :func:`~gearopt.dynamics.speed_sweep`,
:func:`~gearopt.dynamics.walk_off_history` and :func:`~gearopt.dynamics.simulation_statistics` run on it. Gear and
mesh names come only from the system. :func:`gearopt.cases.torsional_model` picks the model of a system: the packaged engine's
timing model for ``[engine]`` data, this one for ``[excitation]`` data.

Modelling choices (all stated; [E] = an assumption no source fixes):

* Topology: the train of ``[trains.<kind>]`` -- a connected tree of external meshes (the geometry layer's
  :class:`~gearopt.geometry.GearTrain` admits nothing else: a pair, an idler train A-B-C, a gear driving several
  others). One node per gear, named by the gear. The data have no shaft concept joining two gears (a two-stage
  reducer with two gears on one shaft is not a connected mesh tree and cannot be stated), so every gear is its own
  node [E]; its shaft's own inertia may be added to the node (``shaft_inertias_kgm2``: e.g. the motor rotor on
  the driving gear, the load on a terminal gear), which then moves rigidly with the gear [E].
* Inertia of a gear: ``[gears.<g>] inertia_kgm2`` when stated; else the closed-form blank of
  :class:`gearopt.blank.GearBlank` (teeth at half fill, body or rim/web/hub; :func:`gearopt.blank.blank_from_data`)
  with the bore of the gear's joint and the density of its material (``[materials]``, else the packaged catalogue,
  else steel 7850 kg/m^3 [E]); a gear without a joint is a solid blank without a bore [E]. The source of every
  inertia is in :attr:`TrainModel.gear_table`.
* Meshes (as the timing-train case's model, :mod:`gearopt.cases.timing_train.model`): ISO 6336-1 mean mesh stiffness ``c_gamma_alpha b``
  (:func:`gearopt.rating.stiffness.mesh_stiffness_table`, web factor C_R for webbed gears that state rim and web
  thickness), variation over the mesh cycle proportional to the contact-line length
  (:meth:`~gearopt.dynamics.mesh.MeshStiffnessShape.from_contact_ratios`), damping ``2 zeta sqrt(k m_eq)`` with the
  two gear nodes' inertias and ``zeta`` = ``[dynamics] mesh_damping_ratio``, default 0.08 [E] (the thesis' value,
  :data:`gearopt.rating.stiffness.THESIS_DAMPING_RATIO`; noted in :attr:`TrainModel.notes` when used), mesh phases 0
  at t = 0 [E]. Backlash along the transverse line of action: the mean of the mesh's stated
  ``backlash_min_mm``/``backlash_max_mm``, read as circumferential backlash on the working pitch circle (as the
  packaged data state theirs) times ``cos alpha_wt = (d_b1 + d_b2) / (2 a)``; without a stated backlash the pair's
  computed mean normal backlash / cos beta_b (allowances and centre-distance tolerance), as the timing model.
  Each mesh keeps the data's orientation (driving gear first): where the power flows the other way, the mesh force
  is negative (back flanks loaded).
* Driving torque on ``[excitation] gear`` (the reference node, speed ratio +1): ``T = mean_torque_Nm + sum_k A_k
  cos(n_k theta + phi_k)``, theta the gear's angle from 0 at t = 0. Mean torque, amplitudes and phases are network
  parameters (``excitation.mean_torque_Nm``, ``excitation.harmonic_<k>_amplitude_Nm``,
  ``excitation.harmonic_<k>_phase_deg``, k from 1); zero amplitudes are allowed. ``excitation_angle="nominal"``
  (default, the usual assumption of torsional analysis and the timing model's default): theta is the nominal
  (constant-speed) angle, so the harmonics have zero mean and the train runs at the requested mean speed.
  ``"actual"``: theta is the vibrating angle; where the harmonics swing the speed by a sizeable fraction (light
  gears without ``shaft_inertias_kgm2``: -16 % to +24 % on the minimal example) the gear dwells longer where the
  torque brakes it, the harmonics then rectify into a mean braking torque, the mean speed settles below the
  nominal one (-1.8 % there) and the response is no longer periodic over the nominal cycle.
* Loads: every gear that is a leaf of the mesh tree seen from the driving gear (a terminal gear, no further driven
  mesh) carries a load; idlers carry none (bearing and churning losses neglected [E]). Load of terminal gear i,
  in its own sense: ``-(T_i + c_i phi_dot_i)`` with ``T_i = s_i T_mean / |r_i|`` (``r_i`` its speed ratio to the
  driving gear, ``s_i`` its share of the mean power: the shares of the terminal meshes' design powers when every one
  states ``design_torque_Nm``, else equal shares [E], or ``load_shares``) and ``c_i = |T_i| / omega_i`` at the
  model's rated speed ``speed_rpm`` (``[excitation] speed_rpm``, else ``[design_loads] speed_rpm``). At the rated
  speed this *is* a viscous load ``c_i omega`` that absorbs the mean power exactly at the requested speed (the load
  is linear in speed, so mean + slope is the whole of it); at other speeds the mean torque balances the drive
  exactly, so the train runs at whatever speed is requested, and the slope ``c_i`` keeps damping the rigid-body
  mode. The slope acts as the node's damping to the rotating frame (so the linear analysis's damping matrix has
  it); the mean as an external torque sharing the parameter ``excitation.mean_torque_Nm`` (an override moves drive
  and loads together). With zero mean torque the slopes are set so the rigid-body speed deviation decays by 1/e
  per revolution of the driving gear [E].
* No speed boundary: the network is free (its angle has one neutral rigid-body direction). The run starts from the
  static deflection under the mean torques (:meth:`~gearopt.dynamics.simulate.Simulator.static_state`) and reaches
  the periodic state by run-in (``steady_state="shooting"`` is refused for a free network: the neutral rigid-body
  angle leaves the periodic state undetermined).
* Cycle: the smallest whole number of driving-gear revolutions over which every harmonic order repeats (the mesh
  frequencies are z_drive per revolution for any tree of external meshes); ``cycles`` and the simulation's
  ``crank_angle_deg`` count in driving-gear degrees.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field, replace
from fractions import Fraction

import numpy as np
import pandas as pd

from .. import numerics as nm
from ..data import System, system_of
from ..errors import GearoptInputError
from ..rating.stiffness import THESIS_DAMPING_RATIO, mesh_stiffness_table
from ..validation import check_range
from .mesh import DEFAULT_CONTACT_WIDTH_M, DEFAULT_DAMPING_WIDTH_M, DEFAULT_HARMONICS, MeshStiffnessShape
from .network import TorsionalNetwork
from .simulate import Simulation, simulate, simulator

KINDS = ("spur", "helical")
#: Parameter prefix of the driving torque and of the loads (they share ``excitation.mean_torque_Nm``).
EXCITATION_PREFIX = "excitation"
#: Largest excitation cycle in driving-gear revolutions (harmonic orders with larger common periods are refused).
MAX_CYCLE_REVOLUTIONS = 64
#: Default density [kg/m^3] of a gear whose material has none [E] (steel).
STEEL_DENSITY_KG_M3 = 7850.0


@dataclass
class TrainModel:
    """The torsional model of a system with a generic driving torque (module docstring).

    ``kind`` the train variant; ``system`` the :class:`~gearopt.data.system.System`; ``network`` its
    :class:`~gearopt.dynamics.network.TorsionalNetwork`; ``train`` the :class:`~gearopt.geometry.GearTrain`;
    ``mesh_table`` (index mesh): gears, teeth, base radii [mm], contact ratios, base helix angle [deg], mean mesh
    stiffness [N/m], damping [N s/m] and ratio, backlash along the line of action [mm] and its source, ISO validity;
    ``gear_table`` (index gear): node, role (``"drive"``/``"load"``/``"idler"``), speed ratio to the driving gear,
    the gear's own inertia [kg m^2] and its source, the shaft inertia added to its node, the node inertia, the
    load's mean torque [N m] and slope [N m s/rad]; ``gear_nodes`` gear -> node (every gear its own node);
    ``drive_gear``; ``speed_rpm`` the rated speed of the driving gear [rpm] (default of :meth:`simulate`);
    ``min_speed_rpm`` the lowest speed the default simulator is built for (lower speeds get their own; the joint
    capacities read ``[joints]``/``[materials]`` of ``system``); ``notes``.
    """

    kind: str
    system: System
    network: TorsionalNetwork
    train: object
    mesh_table: pd.DataFrame
    gear_table: pd.DataFrame
    drive_gear: str
    speed_rpm: float
    min_speed_rpm: float
    notes: list = field(default_factory=list)
    gear_nodes: dict = field(default_factory=dict)

    # -- the API of TimingModel --------------------------------------------------------------------------------

    def parameters_at(self, speed_rpm: float, load: float | None = None) -> dict:
        """Parameter overrides for ``speed_rpm`` [rpm]: none (the loads balance the mean torque at every speed); the
        counterpart of :meth:`gearopt.cases.timing_train.TimingModel.parameters_at`."""
        _check_speed("speed_rpm", speed_rpm)
        return {}

    def simulate(self, speed_rpm: float | None = None, cycles: int = 10, backlash: bool = True, rtol: float = 1e-6,
                 *, parameters: dict | None = None, run_in_cycles: int = 0, steady_state_tol: float | None = None,
                 x0=None, jit: bool | None = None, steady_state: str = "run-in", shooting_tol: float | None = None,
                 shooting_jacobian: str = "sensitivity", shooting_max_iter: int = 20,
                 on_shooting_failure: str = "raise", reuse: bool = True, **options) -> Simulation:
        """Simulate ``cycles`` excitation cycles (:attr:`cycle_revolutions` revolutions of the driving gear) at
        ``speed_rpm`` [rpm] of the driving gear (default :attr:`speed_rpm`); the arguments as
        :meth:`TimingModel.simulate <gearopt.cases.timing_train.TimingModel.simulate>` (``backlash`` the lash
        model, ``parameters`` network overrides such as ``{"excitation.harmonic_1_amplitude_Nm": 0.0}``, ``jit``,
        ``reuse``, simulator ``options``). Speeds below :attr:`min_speed_rpm` get a simulator built for them (the
        lash model's impact step limit depends on the lowest speed)."""
        from ..compile_cache import auto_jit as _auto_jit
        speed = self.speed_rpm if speed_rpm is None else speed_rpm
        _check_speed("speed_rpm", speed)
        options.setdefault("min_speed_rpm", min(self.min_speed_rpm, float(speed)))
        return simulate(self.network, float(speed), cycles, backlash=backlash, rtol=rtol, parameters=parameters,
                        run_in_cycles=run_in_cycles, steady_state_tol=steady_state_tol, x0=x0,
                        steady_state=steady_state, shooting_tol=shooting_tol, shooting_jacobian=shooting_jacobian,
                        shooting_max_iter=shooting_max_iter, on_shooting_failure=on_shooting_failure,
                        jit=_auto_jit(jit), reuse=reuse, **options)

    def simulator(self, backlash: bool = True, rtol: float = 1e-6, jit: bool | None = None, **options):
        """The cached :class:`~gearopt.dynamics.simulate.Simulator` of this model for these options."""
        from ..compile_cache import auto_jit as _auto_jit
        options.setdefault("min_speed_rpm", self.min_speed_rpm)
        return simulator(self.network, lash=backlash, rtol=rtol, jit=_auto_jit(jit), **options)

    def natural_frequencies_Hz(self, boundary: str = "network", rigid_body: bool = False) -> np.ndarray:
        """Undamped natural frequencies [Hz] of the linearised model (mean mesh stiffness, no lash), ascending.
        The network is free (no speed boundary): its first frequency is the rigid-body mode's 0, left out unless
        ``rigid_body``."""
        f = self.network.natural_frequencies_Hz(boundary=boundary)
        free = boundary == "free" or not self.network.boundary_nodes
        return f if rigid_body or not free else f[1:]

    # -- what the sweep and the walk-off tools ask of a model ----------------------------------------------------

    def gear_inertia_kgm2(self, gear: str) -> tuple[float, str]:
        """The gear's own polar inertia [kg m^2] and its source (module docstring)."""
        if gear not in self.gear_table.index:
            raise GearoptInputError(f"gear={gear!r} is not a gear of the model ({list(self.gear_table.index)})")
        row = self.gear_table.loc[gear]
        return float(row["inertia_kgm2"]), str(row["inertia_source"])

    @property
    def cycle_revolutions(self) -> int:
        """Driving-gear revolutions per excitation cycle."""
        return int(round(self.network.cycle_deg / 360.0))

    @property
    def load_gears(self) -> tuple[str, ...]:
        return tuple(self.gear_table.index[self.gear_table["role"] == "load"])

    @property
    def default_speeds_rpm(self) -> list[float]:
        """Speeds of the driving gear of a default speed sweep [rpm]: the rated speed and, where the data state
        ``[design_loads] overspeed_rpm``, the overspeed at the same ratio to the rated speed."""
        loads = self.system.design_loads
        if loads is not None and loads.speed_rpm and loads.overspeed_rpm:
            return [self.speed_rpm, self.speed_rpm * loads.overspeed_rpm / loads.speed_rpm]
        return [self.speed_rpm]

    @property
    def sweep_shafts(self) -> tuple:
        """Shaft elements :func:`~gearopt.dynamics.speed_sweep` reports by default: none (the model has none)."""
        return ()

    @property
    def sweep_joints(self) -> tuple:
        """Joints :func:`~gearopt.dynamics.speed_sweep` reports by default: every ``[joints.*]`` of the system."""
        return tuple(self.system.joints)


def _check_speed(name: str, speed) -> None:
    check_range(name, speed, 0.0, None, low_inclusive=False, unit="rpm")


def _cycle_revolutions(orders, source: str) -> int:
    """The smallest whole number of revolutions over which every order (per revolution) repeats."""
    revs = 1
    for n in orders:
        frac = Fraction(float(n)).limit_denominator(1000)
        if abs(float(frac) - float(n)) > 1e-9 * max(1.0, abs(float(n))):
            raise GearoptInputError(f"{source}: [excitation] harmonic_orders has order {n!r}, which is no ratio of "
                                    f"integers up to 1000: the excitation has no common period")
        revs = math.lcm(revs, frac.denominator)
    if revs > MAX_CYCLE_REVOLUTIONS:
        raise GearoptInputError(f"{source}: [excitation] harmonic_orders {list(orders)} repeat only every {revs} "
                                f"revolutions of the driving gear (limit {MAX_CYCLE_REVOLUTIONS})")
    return revs


def _density(system, gear) -> tuple[float, str]:
    mat = gear.material
    if mat and mat in system.materials and "density_kg_m3" in system.materials[mat]:
        return float(system.materials[mat]["density_kg_m3"]), f"materials.{mat}.density_kg_m3"
    if mat:
        from ..rating.materials import material, material_names
        if mat in material_names():
            return float(material(mat).density_kg_m3), f"catalogue {mat}"
    return STEEL_DENSITY_KG_M3, "steel 7850 kg/m^3 [E]"


def _gear_inertia(system, train, name: str) -> tuple[float, str]:
    """The gear's own inertia [kg m^2] and its source (module docstring)."""
    from ..blank import GearBlank, blank_from_data

    gear = system.gear(name)
    if gear.inertia_kgm2 is not None:
        return float(gear.inertia_kgm2), f"gears.{name}.inertia_kgm2"
    rho, rho_source = _density(system, gear)
    table = train.gear_table()
    d_a, d_f = float(table.loc[name, "tip_diameter_mm"]), float(table.loc[name, "root_diameter_mm"])
    if system.joint_of(name) is not None:
        blank, assumed = blank_from_data(system, train, name)
        blank = replace(blank, density_kg_m3=rho)
        extra = f"; assumed {', '.join(assumed)}" if assumed else ""
        return float(blank.inertia_kgm2()), (f"[E] {blank.kind} GearBlank, bore of joint "
                                             f"{system.joint_of(name).name!r}, {rho_source}{extra}")
    blank = GearBlank(d_a, d_f, gear.face_width_mm, 0.0, density_kg_m3=rho)
    note = "" if (gear.blank or "solid") == "solid" else f" (blank {gear.blank!r} without a joint: taken solid)"
    return float(blank.inertia_kgm2()), f"[E] solid GearBlank without bore, {rho_source}{note}"


def _tree(train, root: str) -> tuple[dict, dict]:
    """BFS of the mesh tree from ``root``: {gear: parent mesh (None for root)} and {gear: child gears}."""
    neighbours: dict = {g: [] for g in train.gears}
    for name, m in train.meshes.items():
        a, b = m.gears
        neighbours[a].append((b, name))
        neighbours[b].append((a, name))
    parent, children = {root: None}, {g: [] for g in train.gears}
    queue = deque([root])
    while queue:
        g = queue.popleft()
        for other, mesh in neighbours[g]:
            if other not in parent:
                parent[other] = mesh
                children[g].append(other)
                queue.append(other)
    return parent, children


def _load_shares(system, train, ratios, leaves, parent, shares) -> tuple[dict, str]:
    if shares is not None:
        unknown = set(shares) - set(leaves)
        if unknown or set(leaves) - set(shares):
            raise GearoptInputError(f"load_shares={dict(shares)!r} must name exactly the terminal gears {list(leaves)}")
        for g, s in shares.items():
            check_range(f"load_shares[{g!r}]", s, 0.0, None)
        total = sum(float(s) for s in shares.values())
        if total <= 0.0:
            raise GearoptInputError(f"load_shares={dict(shares)!r} must not all be zero")
        return {g: float(shares[g]) / total for g in leaves}, "load_shares"
    powers = {}
    for g in leaves:
        m = system.meshes[parent[g]]
        if m.design_torque_Nm is None:
            powers = None
            break
        powers[g] = abs(m.design_torque_Nm * ratios[m.driving_gear])
    if powers and sum(powers.values()) > 0.0:
        total = sum(powers.values())
        return {g: p / total for g, p in powers.items()}, "design powers of the terminal meshes"
    return {g: 1.0 / len(leaves) for g in leaves}, "equal shares [E]"


def mean_backlash_line_of_action_mm(geometry) -> float:
    """Mean backlash of a pair along the transverse line of action [mm]: the mean normal backlash of its
    allowances and centre-distance tolerance (``normal_backlash_min_mm``/``_max_mm``) over cos beta_b."""
    beta_b = float(geometry["base_helix_angle_deg"])
    return 0.5 * (float(geometry["normal_backlash_min_mm"]) + float(geometry["normal_backlash_max_mm"])) / \
        math.cos(math.radians(beta_b))


def add_gear_mesh(net: TorsionalNetwork, name: str, pair, nodes: tuple[str, str], *, stiffness_N_per_m: float,
                  damping_N_s_per_m: float, backlash_mm: float, stiffness_shape, iso6336_stiffness_N_per_m: float,
                  stiffness_source: str, damping_ratio: float, iso6336_validity: str, **mesh_options) -> dict:
    """Add the mesh ``name`` of ``pair`` between ``nodes`` to ``net`` (base radii, teeth and base helix angle from
    the pair's geometry; ``mesh_options``: ``stiffness_variation``, ``contact_width_um``, ``damping_width_um``) and
    return its row of a model's ``mesh_table``."""
    g = pair.geometry()
    rb = tuple(0.5 * float(v) for v in g["base_diameter_mm"])
    beta_b = float(g["base_helix_angle_deg"])
    net.add_mesh(nodes[0], nodes[1], base_radii_mm=rb, teeth=pair.teeth, stiffness_N_per_m=stiffness_N_per_m,
                 damping_N_s_per_m=damping_N_s_per_m, backlash_mm=backlash_mm, stiffness_shape=stiffness_shape,
                 base_helix_angle_deg=beta_b, name=name, **mesh_options)
    return {"mesh": name, "gear_1": pair.names[0], "gear_2": pair.names[1], "teeth_1": pair.teeth[0],
            "teeth_2": pair.teeth[1], "base_radius_1_mm": rb[0], "base_radius_2_mm": rb[1],
            "transverse_contact_ratio": float(g["transverse_contact_ratio"]),
            "overlap_contact_ratio": float(g["overlap_contact_ratio"]), "base_helix_angle_deg": beta_b,
            "mean_stiffness_N_per_m": stiffness_N_per_m, "iso6336_mean_stiffness_N_per_m": iso6336_stiffness_N_per_m,
            "stiffness_source": stiffness_source, "damping_N_s_per_m": damping_N_s_per_m,
            "damping_ratio": damping_ratio, "backlash_line_of_action_mm": backlash_mm,
            "iso6336_validity": iso6336_validity}


def train_model(system: System, kind: str = "spur", *, speed_rpm: float | None = None,
                min_speed_rpm: float | None = None, damping_ratio: float | None = None,
                shaft_inertias_kgm2: dict | None = None, load_shares: dict | None = None, backlash: str = "data",
                stiffness_harmonics: int = DEFAULT_HARMONICS, stiffness_variation: float = 1.0,
                contact_width_um: float = DEFAULT_CONTACT_WIDTH_M * 1e6,
                damping_width_um: float = DEFAULT_DAMPING_WIDTH_M * 1e6,
                excitation_angle: str = "nominal") -> TrainModel:
    """The torsional model of ``system`` (a :class:`~gearopt.data.system.System` with a generic ``[excitation]``)
    for its ``[trains.<kind>]`` (module docstring: the modelling choices).

    ``speed_rpm`` the rated speed of the driving gear [rpm] (default ``[excitation] speed_rpm``, else
    ``[design_loads] speed_rpm``): the load slopes are set there and it is :meth:`TrainModel.simulate`'s default;
    ``min_speed_rpm`` the lowest speed of the default simulator (default half the rated speed); ``damping_ratio``
    of the meshes (default ``[dynamics] mesh_damping_ratio``, else 0.08 [E]); ``shaft_inertias_kgm2`` {gear: J}
    added to the gear's node (its shaft, motor rotor or load; default none); ``load_shares`` {terminal gear: share
    of the mean power} (default: module docstring); ``backlash`` ``"data"`` (the mesh's stated backlash where
    given, else the geometry's) or ``"geometry"``; ``stiffness_harmonics``/``stiffness_variation`` of the
    mesh-stiffness shape (0 variation: constant mean stiffness); ``contact_width_um``/``damping_width_um`` of the
    lash model; ``excitation_angle`` ``"nominal"`` (the harmonics over the driving gear's nominal angle) or
    ``"actual"`` (over its vibrating angle; module docstring).

    A system without ``[excitation]`` raises :class:`~gearopt.errors.MissingSectionError` naming the file (the
    engine's data: use :func:`gearopt.cases.torsional_model` or :func:`gearopt.cases.timing_train.timing_model`).
    """
    from ..data.system import DrivingTorque

    system = system_of(system, "train_model")
    if kind not in KINDS:
        raise GearoptInputError(f"kind={kind!r} must be one of {KINDS}")
    if excitation_angle not in ("nominal", "actual"):
        raise GearoptInputError(f"excitation_angle={excitation_angle!r} must be 'nominal' or 'actual'")
    if backlash not in ("data", "geometry"):
        raise GearoptInputError(f"backlash={backlash!r} must be 'data' or 'geometry'")
    system.require("excitation", "the torsional model of a gear train (gearopt.dynamics.train_model)")
    exc = system.excitation
    if not isinstance(exc, DrivingTorque):  # pragma: no cover - the System record makes [excitation] a DrivingTorque
        raise GearoptInputError(f"{system.source}: [excitation] is not a driving torque ({exc!r})")
    source = system.source
    drive = exc.gear
    system.gear(drive)
    n_h = len(exc.harmonic_orders)
    if len(exc.harmonic_amplitudes_Nm) != n_h or len(exc.harmonic_phases_deg) not in (0, n_h):
        raise GearoptInputError(f"{source}: [excitation] harmonic_orders ({n_h}), harmonic_amplitudes_Nm "
                                f"({len(exc.harmonic_amplitudes_Nm)}) and harmonic_phases_deg "
                                f"({len(exc.harmonic_phases_deg)}) must have equal lengths")
    phases = exc.harmonic_phases_deg or (0.0,) * n_h
    rated = speed_rpm if speed_rpm is not None else exc.speed_rpm if exc.speed_rpm is not None else \
        system.design_loads.speed_rpm if system.design_loads is not None else None
    if rated is None:
        raise GearoptInputError(f"{source}: no operating speed: give [excitation] speed_rpm (or [design_loads] "
                                f"speed_rpm, or speed_rpm=...)")
    _check_speed("speed_rpm", rated)
    rated = float(rated)
    min_speed = 0.5 * rated if min_speed_rpm is None else min_speed_rpm
    _check_speed("min_speed_rpm", min_speed)
    notes = []
    if damping_ratio is None:
        if system.has("dynamics") and "mesh_damping_ratio" in system.section("dynamics"):
            zeta = float(system.section("dynamics")["mesh_damping_ratio"])
        else:
            zeta = THESIS_DAMPING_RATIO
            notes.append(f"mesh damping ratio {zeta:g} [E] (no [dynamics] mesh_damping_ratio in {source})")
    else:
        zeta = float(damping_ratio)
    check_range("damping_ratio", zeta, 0.0, None)
    extra_j = dict(shaft_inertias_kgm2 or {})
    for g, j in extra_j.items():
        system.gear(g)
        check_range(f"shaft_inertias_kgm2[{g!r}]", j, 0.0, None, unit="kg m^2")

    train = system.train(kind)
    revs = _cycle_revolutions(exc.harmonic_orders, source)
    net = TorsionalNetwork(name=f"{system.title or source}: {kind} train", cycle_deg=360.0 * revs)

    # --- nodes: the driving gear first (the reference node), then the tree -------------------------------------
    parent, children = _tree(train, drive)
    order = list(parent)  # BFS order from the driving gear
    ratios = {g: float(train.speed_ratios[g]) / float(train.speed_ratios[drive]) for g in order}
    leaves = [g for g in order if g != drive and not children[g]]
    shares, share_source = _load_shares(system, train, ratios, leaves, parent, load_shares)
    inertia, inertia_source = {}, {}
    for g in order:
        inertia[g], inertia_source[g] = _gear_inertia(system, train, g)
    node_j = {g: inertia[g] + float(extra_j.get(g, 0.0)) for g in order}
    omega = rated * math.pi / 30.0
    t_mean = float(exc.mean_torque_Nm)
    load_torque = {g: shares[g] * t_mean / abs(ratios[g]) for g in leaves}
    if t_mean != 0.0:
        slope = {g: abs(load_torque[g]) / (abs(ratios[g]) * omega) for g in leaves}
    else:  # rigid-body speed deviation decays by 1/e per revolution of the driving gear [E]
        j_red = sum(node_j[g] * ratios[g] ** 2 for g in order)
        slope = {g: shares[g] * j_red * omega / (2.0 * math.pi) / ratios[g] ** 2 for g in leaves}
        notes.append("zero mean torque: load slopes set to damp the rigid-body mode in one revolution [E]")
    for g in order:
        net.add_inertia(g, node_j[g], damping_to_frame_Nms_per_rad=slope.get(g, 0.0))

    # --- meshes ------------------------------------------------------------------------------------------------
    blanks = {}
    for name, gear in system.gears.items():
        e = gear.entries
        if gear.blank in ("webbed", "recessed") and "web_thickness_mm" in e and "rim_thickness_mm" in e:
            blanks[name] = {"rim_thickness_mm": float(e["rim_thickness_mm"]),
                            "web_thickness_mm": float(e["web_thickness_mm"])}
    table = mesh_stiffness_table(train, inertias_kgm2=node_j, blanks=blanks, damping_ratio=zeta, validity="ignore")
    rows = []
    for _, row in table.iterrows():
        name = row["mesh"]
        pair = train.pairs[name]
        g = pair.geometry()
        rb = tuple(0.5 * float(v) for v in g["base_diameter_mm"])
        beta_b = float(g["base_helix_angle_deg"])
        stated = system.meshes[name].backlash_mm
        if backlash == "data" and stated is not None:
            a = float(g["centre_distance_mm"])
            j_bt = 0.5 * (stated[0] + stated[1]) * (2.0 * (rb[0] + rb[1])) / (2.0 * a)
            j_source = f"meshes.{name}.backlash_min_mm/backlash_max_mm (mean, circumferential) x cos alpha_wt"
        else:
            j_bt = mean_backlash_line_of_action_mm(g)
            j_source = "pair geometry (mean normal backlash / cos beta_b)"
        if j_bt < 0.0:
            raise GearoptInputError(f"{source}: mesh {name!r} has negative backlash {j_bt:.4g} mm (the teeth jam)")
        k = float(row["mean_mesh_stiffness_N_per_um"]) * 1e6
        c = float(row["damping_N_s_per_m"])
        shape = MeshStiffnessShape.from_contact_ratios(float(g["transverse_contact_ratio"]),
                                                       float(g["overlap_contact_ratio"]), stiffness_harmonics)
        rows.append({**add_gear_mesh(net, name, pair, pair.names, stiffness_N_per_m=k, damping_N_s_per_m=c,
                                     backlash_mm=j_bt, stiffness_shape=shape, iso6336_stiffness_N_per_m=k,
                                     stiffness_source="iso6336", damping_ratio=zeta,
                                     iso6336_validity=row["iso6336_validity"], stiffness_variation=stiffness_variation,
                                     contact_width_um=contact_width_um, damping_width_um=damping_width_um),
                     "backlash_source": j_source})
        if row["iso6336_validity"] != "ok":
            notes.append(f"{name}: ISO 6336-1 stiffness outside its validity: {row['iso6336_validity']}")
    mesh_df = pd.DataFrame(rows).set_index("mesh")

    # --- driving torque and loads --------------------------------------------------------------------------------
    orders = tuple(float(n) for n in exc.harmonic_orders)
    params = {"mean_torque_Nm": t_mean}
    for i, (a, p) in enumerate(zip(exc.harmonic_amplitudes_Nm, phases), start=1):
        params[f"harmonic_{i}_amplitude_Nm"] = float(a)
        params[f"harmonic_{i}_phase_deg"] = float(p)

    def harmonic_torque(angle_rad, p):
        total = p["mean_torque_Nm"]
        for i, n in enumerate(orders, start=1):
            total = total + p[f"harmonic_{i}_amplitude_Nm"] * nm.cos(
                n * angle_rad + p[f"harmonic_{i}_phase_deg"] * (math.pi / 180.0))
        return total

    if excitation_angle == "nominal":
        def driving_torque(t_s, angle_rad, speed_rad_s, nominal_angle_rad, **p):
            return harmonic_torque(nominal_angle_rad, p)
    else:
        def driving_torque(t_s, angle_rad, speed_rad_s, **p):
            return harmonic_torque(angle_rad, p)

    net.add_torque(drive, driving_torque, name=f"excitation@{drive}", parameters=params,
                   parameter_prefix=EXCITATION_PREFIX,
                   description=f"driving torque on {drive!r}: mean + harmonics of its angle ([excitation])")
    for g in leaves:
        factor = shares[g] / abs(ratios[g])  # T_i = s_i T_mean / |r_i|, following any override of the mean

        def load(t_s, angle_rad, speed_rad_s, mean_torque_Nm, _f=factor):
            return -_f * mean_torque_Nm

        net.add_torque(g, load, name=f"load@{g}", parameters={"mean_torque_Nm": t_mean},
                       parameter_prefix=EXCITATION_PREFIX,
                       description=f"mean load on {g!r} (share {shares[g]:.4g} of the mean power; its slope "
                                   f"{slope[g]:.4g} N m s/rad is the node's damping to the frame)")
    roles = {g: "drive" if g == drive else "load" if g in leaves else "idler" for g in order}
    gear_df = pd.DataFrame([{"gear": g, "node": g, "role": roles[g], "speed_ratio": ratios[g],
                             "inertia_kgm2": inertia[g], "inertia_source": inertia_source[g],
                             "shaft_inertia_kgm2": float(extra_j.get(g, 0.0)), "node_inertia_kgm2": node_j[g],
                             "load_share": shares.get(g, 0.0), "load_torque_Nm": load_torque.get(g, 0.0),
                             "load_slope_Nms_per_rad": slope.get(g, 0.0)} for g in order]).set_index("gear")
    if leaves:
        notes.append(f"load shares: {share_source}")
    return TrainModel(kind=kind, system=system, network=net, train=train, mesh_table=mesh_df, gear_table=gear_df,
                      drive_gear=drive, speed_rpm=rated, min_speed_rpm=float(min_speed),
                      notes=notes, gear_nodes={g: g for g in order})


__all__ = ["TrainModel", "train_model", "add_gear_mesh", "mean_backlash_line_of_action_mm", "EXCITATION_PREFIX", "KINDS"]
