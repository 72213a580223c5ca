"""The packaged default timing-system model: crankshaft chain with viscous damper, six throws and speed-controlled
flywheel; camshaft chain; fuel pump, air compressor and lube pump drives; the five gear meshes of the default train
(docs/source-study.md sec. 1; thesis sec. 3.6, Fig. 3.10), as a :class:`~gearopt.dynamics.network.TorsionalNetwork`.

Data (``default_train.toml``, provenance there): ``engine.crankshaft`` (10-node chain, damper ring coupled by
``damper_viscous_damping_Nms_per_rad``, throw absolute damping, shaft loss factor), ``engine.camshaft`` (cam gear
``gears.cam`` plus six stations), ``engine.fuel_pump``/``air_compressor``/``lube_pump`` (inertias and couplings),
``gears.*.inertia_kgm2`` (the crank gear is lumped in the crank-gear node), ``dynamics.mesh_damping_ratio``.

Modelling choices (all stated, [E] where no source fixes them):

* Boundary: the flywheel turns at the prescribed speed (the thesis' speed-controlled dynamometer behind a 2.075
  kg m^2 flywheel is close to this); its reaction torque is an output.
* Shaft damping: hysteretic loss factor ``eta`` (0.035, [V] Mendes via openTorsion, ``c = eta k / omega``) made
  viscous at a reference frequency: the crankshaft's first damped mode (``engine.crankshaft.mode_1_frequency_Hz``)
  for the crank chain; for the camshaft and accessory couplings [E] the coupling's own two-inertia frequency
  ``sqrt(k (1/J_a + 1/J_b))`` (modal damping ratio about eta/2 there). Throw damping acts on the vibratory speed.
* Meshes: ISO 6336-1 mean mesh stiffness ``c_gamma_alpha b`` of each pair of the train (web factor C_R for the
  webbed cam and FP gears), variation over the mesh phase proportional to the contact-line length
  (:meth:`~gearopt.dynamics.mesh.MeshStiffnessShape.from_contact_ratios`, ``stiffness_harmonics``), damping
  ``2 zeta sqrt(k m_eq)`` with the two gear inertias (thesis Eqs. 3.26-3.27, zeta 0.08), backlash along the
  transverse line of action = the pair's mean normal backlash (allowances and centre-distance tolerance) / cos
  beta_b, mesh phases 0 at crank angle 0 [E]. Helical meshes report the axial force F_bt tan beta_b.
* Excitation (:mod:`gearopt.engine`): gas + reciprocating-inertia torque per throw at the throw's own angle and
  speed (general form with its acceleration), firing order 1-5-3-6-2-4 (crank angle 0 = cylinder 1 firing TDC); the
  measured Mendes pressure trace (or the double Wiebe model) scaled to the speed-load peak-pressure map through the
  torque parameter ``cylinders.pressure_scale`` (set per speed by :meth:`TimingModel.parameters_at`, so one
  integrator serves every speed). Accessory loads over their own angles: valve train split equally over the six
  cam stations [E] (the engine model gives the camshaft total), common-rail pump on the pump shaft, air compressor
  on its crank, lube pump on its rotor.
* Excitation angle (default ``"nominal"``): the cylinder pressure and the accessory load maps are evaluated along
  the nominal (constant-speed) motion -- the usual assumption of torsional analysis, which lets all of them share one
  Fourier basis of the cam-phase angle -- while the slider-crank kinematics, the reciprocating inertia torque and
  its angle-dependent inertia use each throw's actual angle, speed and acceleration. The error is the vibratory
  angle times the slope of the pressure trace; ``excitation_angle="actual"`` evaluates everything at the vibrating
  angles (slower; the run times are in ``benchmarks/results/dynamics.json``). Measured
  (benchmarks/bench_dynamics.py, spur, no lash, 2500 rpm, third cycle): peak crank-cam force 8096 vs 8132 N (-0.4 %), RMS 2550 vs 2512 N (+1.5 %), largest trace difference 4.9 % of the peak.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import pandas as pd

from ...rating.stiffness import mesh_stiffness_table
from ...data import System, load_system, system_of, train_from_data, values
from ... import compile_cache
from ...errors import GearoptInputError
from ...validation import check_range
from ...dynamics.mesh import (
    DEFAULT_CONTACT_WIDTH_M,
    DEFAULT_DAMPING_WIDTH_M,
    DEFAULT_HARMONICS,
    MeshStiffnessShape,
)
from ...dynamics.network import TorsionalNetwork
from ...dynamics.train_model import add_gear_mesh, mean_backlash_line_of_action_mm
from ...dynamics.simulate import Simulation, simulate, simulator

KINDS = ("spur", "helical")
PRESSURE_SCALE = "cylinders.pressure_scale"


@dataclass
class TimingModel:
    """The default timing-system network with its system, gear train and per-mesh table (see module docstring).

    ``system`` the :class:`~gearopt.data.System` the model was built from (its ``[engine]`` sets the pressure map
    of :meth:`parameters_at`; its ``[joints]``/``[materials]`` give the joint capacities).

    ``mesh_table`` (index mesh): gears, base radii [mm], teeth, contact ratios, base helix angle [deg], mean mesh
    stiffness [N/m], damping [N s/m], backlash along the line of action [mm], ISO validity note. ``gear_nodes``:
    gear name -> network node that carries it (the crank gear is lumped in ``crank_gear_node``; every other gear is
    its own node).
    """

    kind: str
    network: TorsionalNetwork
    train: object
    mesh_table: pd.DataFrame
    system: System
    load: float
    pressure: str
    raw_peak_pressure_bar: float
    notes: list = field(default_factory=list)
    gear_nodes: dict = field(default_factory=dict)

    @property
    def factory(self) -> tuple[str, dict]:
        """How a spawned worker rebuilds this model from its system: (``"module:function"``, keyword arguments
        besides ``system``)."""
        return f"{__name__}:default_timing_model", {"kind": self.kind}

    @property
    def default_speeds_rpm(self) -> list[float]:
        """Crank speeds of a default speed sweep [rpm]: the engine's idle and overspeed-test speeds."""
        e = self.system.section("engine", "TimingModel.default_speeds_rpm")
        return [float(e["idle_speed_rpm"]), float(e["overspeed_test_speed_rpm"])]

    def parameters_at(self, speed_rpm: float, load: float | None = None) -> dict:
        """Parameter overrides for ``speed_rpm`` [rpm]: the cylinder-pressure scale that makes the trace's peak the
        speed-load map's peak pressure (:func:`gearopt.engine.peak_pressure_bar`)."""
        from ...engine import peak_pressure_bar
        load = self.load if load is None else load
        return {PRESSURE_SCALE: float(peak_pressure_bar(speed_rpm, load, self.system)) / self.raw_peak_pressure_bar}

    def simulate(self, speed_rpm: float = 2500.0, cycles: int = 10, backlash: bool = True, rtol: float = 1e-6,
                 *, parameters: dict | None = None, load: float | None = None, run_in_cycles: int = 0,
                 steady_state_tol: float | None = None, x0=None, jit: bool | None = None,
                 steady_state: str = "run-in", shooting_tol: float | None = None,
                 shooting_jacobian: str = "linear", shooting_max_iter: int = 20,
                 on_shooting_failure: str = "raise", reuse: bool = True, **options) -> Simulation:
        """Simulate ``cycles`` engine cycles (720 deg) at ``speed_rpm`` [rpm] (flywheel speed); ``backlash``
        selects the lash model (else linear meshes). ``parameters`` override network parameters (e.g.
        ``{"crank-cam.backlash_mm": 0.2}``); ``jit``: compile the equations with the system C compiler, once:
        the binaries are kept in the on-disk cache of :mod:`gearopt.compile_cache` (default ``None``: unless
        ``GEAROPT_JIT=0``; without a compiler the interpreted path with a notice; speed-ups measured in
        ``benchmarks/results/dynamics_speed.json``); the rest as
        :meth:`gearopt.dynamics.simulate.Simulator.run` and :class:`~gearopt.dynamics.simulate.Simulator` options
        (``method``, ``atol``, ``output_step_deg``, ``external_torques``; ``steady_state="shooting"`` solves the
        periodic state by shooting, see :meth:`~gearopt.dynamics.simulate.Simulator.periodic_state`; here the
        default ``shooting_jacobian="linear"``, the chord iteration: the exact forward-sensitivity Newton costs
        about 20 s per iteration on this 46-state model). ``reuse``: an identical run of this model is computed once
        per session and shared (:func:`gearopt.dynamics.simulate.simulate`).
        """
        p = self.parameters_at(speed_rpm, load)
        p.update(parameters or {})
        return simulate(self.network, speed_rpm, cycles, backlash=backlash, rtol=rtol, parameters=p,
                        run_in_cycles=run_in_cycles, steady_state_tol=steady_state_tol, x0=x0,
                        steady_state=steady_state, shooting_tol=shooting_tol, shooting_jacobian=shooting_jacobian,
                        shooting_max_iter=shooting_max_iter, on_shooting_failure=on_shooting_failure,
                        jit=_auto_jit(jit), reuse=reuse, **options)

    def simulator(self, backlash: bool = True, rtol: float = 1e-6, jit: bool | None = None, **options):
        """The cached :class:`~gearopt.dynamics.simulate.Simulator` of this model for these options (``jit`` as
        in :meth:`simulate`)."""
        return simulator(self.network, lash=backlash, rtol=rtol, jit=_auto_jit(jit), **options)

    def natural_frequencies_Hz(self, boundary: str = "network") -> np.ndarray:
        """Undamped natural frequencies [Hz] of the linearised model (mean mesh stiffness, no lash)."""
        return self.network.natural_frequencies_Hz(boundary=boundary)


_auto_jit = compile_cache.auto_jit


_PRESSURE_FUNCTIONS: dict = {}


def _nominal_pressures(exc) -> ca.Function:
    """SX Function: engine crank angle [rad] -> the cylinder pressures [bar] of ``exc`` (one shared harmonic basis),
    built once per pressure series and re-used by every model and lash option: calling it on a symbol copies the
    graph (C++) instead of rebuilding the Fourier basis in Python for each cylinder and equation set."""
    key = tuple((p.series.period, p.series.mean, p.series.cos_coefficients, p.series.sin_coefficients)
                for p in exc._cylinder_pressures)
    if key not in _PRESSURE_FUNCTIONS:
        angle = ca.SX.sym("crank_angle_rad")
        _PRESSURE_FUNCTIONS[key] = ca.Function("cylinder_pressures", [angle],
                                               [ca.vertcat(*exc.cylinder_pressures_bar(angle))])
    return _PRESSURE_FUNCTIONS[key]


def _shared_series(series):
    """``x -> series(x)``: on a CasADi SX symbol through an SX Function built once per series (the graph is copied
    in C++ instead of rebuilt in Python for every station, model and lash option); numbers as ``series`` itself."""
    key = (series.period, series.mean, series.cos_coefficients, series.sin_coefficients)
    if key not in _PRESSURE_FUNCTIONS:
        x = ca.SX.sym("x")
        _PRESSURE_FUNCTIONS[key] = ca.Function("fourier_series", [x], [series(x)])
    fun = _PRESSURE_FUNCTIONS[key]
    return lambda x: fun(x) if isinstance(x, ca.SX) else series(x)


def _check_kind(kind: str) -> None:
    if kind not in KINDS:
        raise GearoptInputError(f"kind={kind!r} must be one of {KINDS}")


def _gear_inertias(d: dict) -> dict:
    crank = d["engine"]["crankshaft"]
    node = crank["crank_gear_node"]
    j_crank = crank["inertias_kgm2"][crank["node_names"].index(node)]
    out = {"crank": float(j_crank)}
    for g in ("cam", "ac", "fp", "lpi", "lpg"):
        out[g] = float(d["gears"][g]["inertia_kgm2"])
    return out


def _local_damping(loss_factor: float, k: float, j_a: float, j_b: float) -> float:
    omega = math.sqrt(k * (1.0 / j_a + 1.0 / j_b))
    return loss_factor * k / omega


def default_timing_model(kind: str = "spur", *, system: System | None = None, load: float = 1.0,
                         pressure: str = "table", pressure_harmonics: int = 64,
                         stiffness_harmonics: int = DEFAULT_HARMONICS, stiffness_variation: float = 1.0,
                         contact_width_um: float = DEFAULT_CONTACT_WIDTH_M * 1e6,
                         damping_width_um: float = DEFAULT_DAMPING_WIDTH_M * 1e6,
                         air_compressor_loaded: bool = True, excitation_angle: str = "nominal",
                         mesh_stiffness: str = "iso6336", ltca_torques_Nm: dict | None = None,
                         ltca_options: dict | None = None) -> TimingModel:
    """The default engine timing-system model of ``kind`` ``"spur"`` (the redesign) or ``"helical"`` (the baseline).

    ``system``: the :class:`~gearopt.data.System` of a data file of the timing train's layout (an ``[engine]``
    section and the timing train's gears); default ``gearopt.load_system()``, the packaged timing train this case
    models; ``load`` engine load 0..1;
    ``pressure`` ``"table"`` (Mendes measured trace) or ``"wiebe"``; ``pressure_harmonics`` of its Fourier fit;
    ``stiffness_harmonics``/``stiffness_variation`` of the mesh-stiffness shape (0 variation: constant mean
    stiffness); ``contact_width_um`` of the smooth dead zone, ``damping_width_um`` over which the mesh dashpot
    engages; ``air_compressor_loaded``; ``excitation_angle``
    ``"nominal"`` (cylinder pressure and accessory maps evaluated along the nominal motion, one shared Fourier basis;
    run times of both in ``benchmarks/results/dynamics.json``, ``approximations.excitation_angle``) or ``"actual"``
    (at each node's vibrating angle). ``mesh_stiffness``: ``"iso6336"`` (ISO 6336-1 mean ``c_gamma_alpha b`` with the contact-line-length shape) or ``"ltca"`` (mean and shape over the mesh
    cycle from the exact LTCA of each pair, :func:`gearopt.dynamics.ltca_stiffness.ltca_mesh_stiffness`, at
    ``ltca_torques_Nm`` {mesh: torque on gear 1 [N m]}, default the data's ``[design_loads]``; ``ltca_options``
    go to it, e.g. ``{"stiffness": "iso6336"}``; damping rescaled to the same ratio ``zeta``). Measured on the
    default data (potential-energy tooth model): LTCA means 4-18 % above ISO (crank-cam +5.6 %, cam-AC +7.7 %,
    cam-FP +4.0 %, crank-LPI +11 %, LPI-LPG +17 % spur; +6 to +18 % helical). Module docstring: choices.
    """
    from ...engine import AccessoryTorque, EngineExcitation
    from ...engine.kinematics import slider_crank

    _check_kind(kind)
    check_range("load", load, 0.0, 1.0)
    system = load_system() if system is None else system_of(system, "default_timing_model")
    raw = system.data
    d = values(raw)
    train = train_from_data(raw, kind)
    crank = d["engine"]["crankshaft"]
    net = TorsionalNetwork(name=f"default {kind} timing system", cycle_deg=720.0)
    notes = []

    # --- crankshaft chain --------------------------------------------------------------------------------------
    names = list(crank["node_names"])
    throws = list(crank["throw_nodes"])
    omega_ref = 2.0 * math.pi * float(crank["mode_1_frequency_Hz"])
    eta = float(crank["shaft_loss_factor"])
    for name, j in zip(names, crank["inertias_kgm2"]):
        c_abs = float(crank["throw_absolute_damping_Nms_per_rad"]) if name in throws else 0.0
        net.add_inertia(name, float(j), damping_to_frame_Nms_per_rad=c_abs)
    for i, k in enumerate(crank["connection_stiffnesses_Nm_per_rad"]):
        a, b = names[i], names[i + 1]
        if float(k) == 0.0:
            if i != 0:
                raise GearoptInputError(f"engine.crankshaft connection {i} ({a}-{b}) has zero stiffness; only the "
                                        f"damper ring (connection 0) may be a pure viscous coupling")
            net.add_damper(a, b, float(crank["damper_viscous_damping_Nms_per_rad"]), name="damper")
        else:
            net.add_shaft(a, b, float(k), eta * float(k) / omega_ref)
    net.set_speed_boundary(names[-1])
    gear_node = {"crank": crank["crank_gear_node"]}

    # --- camshaft and accessories ------------------------------------------------------------------------------
    cam = d["engine"]["camshaft"]
    j_gear = _gear_inertias(d)
    net.add_inertia("cam", j_gear["cam"])
    stations = [f"cam_station_{i + 1}" for i in range(int(cam["stations"]))]
    for s, j in zip(stations, cam["station_inertias_kgm2"]):
        net.add_inertia(s, float(j))
    chain = ["cam"] + stations
    stiff = [float(cam["gear_to_station_1_stiffness_Nm_per_rad"])] + [float(k) for k in
                                                                      cam["station_stiffnesses_Nm_per_rad"]]
    for a, b, k in zip(chain[:-1], chain[1:], stiff):
        net.add_shaft(a, b, k, _local_damping(eta, k, net.inertias[a].inertia_kgm2, net.inertias[b].inertia_kgm2))
    fp, ac, lp = d["engine"]["fuel_pump"], d["engine"]["air_compressor"], d["engine"]["lube_pump"]
    for gear, load_node, j_load, k in (("fp", "fp_pump", fp["pump_inertia_kgm2"], fp["coupling_stiffness_Nm_per_rad"]),
                                       ("ac", "ac_crank", ac["crank_inertia_kgm2"], ac["coupling_stiffness_Nm_per_rad"]),
                                       ("lpg", "lpg_rotor", lp["rotor_inertia_kgm2"],
                                        lp["coupling_stiffness_Nm_per_rad"])):
        net.add_inertia(gear, j_gear[gear])
        net.add_inertia(load_node, float(j_load))
        net.add_shaft(gear, load_node, float(k), _local_damping(eta, float(k), j_gear[gear], float(j_load)))
    net.add_inertia("lpi", j_gear["lpi"])
    for g in ("cam", "fp", "ac", "lpi", "lpg"):
        gear_node[g] = g

    # --- meshes ------------------------------------------------------------------------------------------------
    blanks = {g: {"rim_thickness_mm": float(spec["rim_thickness_mm"]), "web_thickness_mm": float(spec["web_thickness_mm"])}
              for g, spec in d["gears"].items() if "web_thickness_mm" in spec and "rim_thickness_mm" in spec}
    zeta = float(d["dynamics"]["mesh_damping_ratio"])
    if mesh_stiffness not in ("iso6336", "ltca"):
        raise GearoptInputError(f"mesh_stiffness={mesh_stiffness!r} must be 'iso6336' or 'ltca'")
    if mesh_stiffness == "ltca":
        from ...dynamics.ltca_stiffness import ltca_mesh_stiffness
        torques = dict(ltca_torques_Nm or {})
        design = system.design_torques_Nm()
        for name in train.pairs:
            if name not in torques:
                if name not in design:
                    raise GearoptInputError(f"mesh_stiffness='ltca': no torque for mesh {name!r} (ltca_torques_Nm or "
                                            f"[meshes.{name}] design_torque_Nm)")
                torques[name] = design[name]
    table = mesh_stiffness_table(train, inertias_kgm2=j_gear, blanks=blanks, damping_ratio=zeta, validity="ignore")
    rows = []
    for _, row in table.iterrows():
        name = row["mesh"]
        pair = train.pairs[name]
        g = pair.geometry()
        backlash = mean_backlash_line_of_action_mm(g)
        k_iso = float(row["mean_mesh_stiffness_N_per_um"]) * 1e6
        c = float(row["damping_N_s_per_m"])
        if mesh_stiffness == "ltca":
            lt = ltca_mesh_stiffness(pair, torques[name], harmonics=stiffness_harmonics, **(ltca_options or {}))
            shape, k = lt["shape"], lt["mean_stiffness_N_per_m"]
            c = c * math.sqrt(k / k_iso)  # same damping ratio: c = 2 zeta sqrt(k m_eq)
        else:
            shape = MeshStiffnessShape.from_contact_ratios(float(g["transverse_contact_ratio"]),
                                                           float(g["overlap_contact_ratio"]), stiffness_harmonics)
            k = k_iso
        rows.append(add_gear_mesh(net, name, pair, (gear_node[pair.names[0]], gear_node[pair.names[1]]),
                                  stiffness_N_per_m=k, damping_N_s_per_m=c, backlash_mm=backlash,
                                  stiffness_shape=shape, iso6336_stiffness_N_per_m=k_iso,
                                  stiffness_source=mesh_stiffness, damping_ratio=zeta,
                                  iso6336_validity=row["iso6336_validity"], stiffness_variation=stiffness_variation,
                                  contact_width_um=contact_width_um, damping_width_um=damping_width_um))
        if row["iso6336_validity"] != "ok":
            notes.append(f"{name}: ISO 6336-1 stiffness outside its validity: {row['iso6336_validity']}")
    mesh_df = pd.DataFrame(rows).set_index("mesh")

    # --- excitation ---------------------------------------------------------------------------------------------
    if excitation_angle not in ("nominal", "actual"):
        raise GearoptInputError(f"excitation_angle={excitation_angle!r} must be 'nominal' or 'actual'")
    exc = EngineExcitation.from_data(system, speed_rpm=float(d["engine"]["rated_speed_rpm"]), load=load,
                                     pressure=pressure, harmonics=pressure_harmonics, scale_to_map=False)
    p_cc = float(exc.crankcase_pressure_bar)
    area_mm2, mass = exc.piston_area_mm2, exc.reciprocating_mass_kg
    for i, throw in enumerate(throws):
        cylinder = i + 1
        tdc = math.radians(exc.firing_tdc_deg(cylinder))

        def cylinder_torque(t_s, angle_rad, speed_rad_s, accel_rad_s2, pressure_scale, nominal_angle_rad,
                            _cyl=cylinder, _tdc=tdc):
            # gas (f p - p_cc) A s' and reciprocating inertia -m s' (s'' w^2 + s' a) at the throw's own angle,
            # speed and acceleration (gearopt.engine kinematics and pressure; engine.excitation's formulas)
            k = slider_crank(angle_rad - _tdc, exc.crank_radius_mm, exc.rod_length_mm)
            ds, d2s = k["ds_dtheta_mm"] * 1e-3, k["d2s_dtheta2_mm"] * 1e-3
            if excitation_angle == "nominal" and isinstance(nominal_angle_rad, ca.SX):
                p = _nominal_pressures(exc)(nominal_angle_rad)[_cyl - 1]  # one shared SX graph (see there)
            else:
                p = exc.cylinder_pressure_bar(_cyl, nominal_angle_rad if excitation_angle == "nominal" else angle_rad)
            gas = (pressure_scale * p - p_cc) * 0.1 * area_mm2 * ds
            return gas - mass * ds * (d2s * speed_rad_s * speed_rad_s + ds * accel_rad_s2)

        net.add_torque(throw, cylinder_torque, name=f"cylinder_{cylinder}", parameters={"pressure_scale": 1.0},
                       parameter_prefix="cylinders", acceleration_dependent=True,
                       description=f"cylinder {cylinder}: gas + reciprocating inertia (gearopt.engine)")

    def load_torque(series, share=1.0):
        shared = _shared_series(series.series)  # the Fourier graph built once per series, copied per use
        if excitation_angle == "nominal":
            return lambda t_s, a, w, nominal_angle_rad: -share * shared(nominal_angle_rad)
        return lambda t_s, a, w: -share * shared(a)

    valve = AccessoryTorque.camshaft(system)
    for s in stations:
        net.add_torque(s, load_torque(valve, 1.0 / len(stations)), name=f"valve_train@{s}",
                       description="valve train / stations (gearopt.engine camshaft map, [E] equal split)")
    net.add_torque("fp_pump", load_torque(AccessoryTorque.fuel_pump(system)), name="fuel_pump",
                   description="common-rail pump (gearopt.engine)")
    net.add_torque("ac_crank", load_torque(AccessoryTorque.air_compressor(system, loaded=air_compressor_loaded)),
                   name="air_compressor", description="single-cylinder air compressor (gearopt.engine)")
    net.add_torque("lpg_rotor", load_torque(AccessoryTorque.lube_pump(system)), name="lube_pump",
                   description="lube pump (gearopt.engine)")

    return TimingModel(kind=kind, network=net, train=train, mesh_table=mesh_df, system=system, load=float(load),
                       pressure=pressure, raw_peak_pressure_bar=float(exc.pressure.peak_bar), notes=notes,
                       gear_nodes=dict(gear_node))


__all__ = ["default_timing_model", "TimingModel", "KINDS", "PRESSURE_SCALE"]
