"""Operating envelope of cam-gear walk-off: the friction joints of the default timing model over speed, damper state
and fit, helical against spur (:mod:`gearopt.dynamics.joint_friction`).

Assumptions (every one stated where it is used, [E] = engineering estimate, [V] = public source):

* Speeds: rated 2500 rpm and high idle 2850 rpm ([V] Cummins ISBe manual, the governor's no-load maximum), the
  overspeed test speed 3000 rpm of the data, and 3300 rpm [E]: the governor only cuts fuel, so a vehicle pushing
  the engine downhill (or a wrong down-shift) can overrun high idle; 3300 rpm is taken as the motoring overspeed
  the engine may reach before the driver or the exhaust brake reacts (the thesis: walk-off "during the overspeed
  testing at higher than the rated rpm", sec. 1, without a figure).
* Damper states (the thesis' root cause: the damper is ineffective at overspeed, sec. 1): ``nominal`` the data's
  viscous coefficient (80 N m s/rad, the optimum of this chain), ``degraded`` 10 % of it [E] (silicone fluid
  degraded / partly lost: the coefficient falls with fluid loss and shear thinning), ``seized`` 100x [E] (gelled
  fluid: the ring is practically locked to the housing, the chain's mode then has only the shaft's own damping).
* Joint data (:data:`JOINT_FRICTION_DATA`): key side clearance, key stiffness, shoulder stiffness, and the friction
  coefficient range; the fit from ``[joints.*]`` (ISO 286 interference range, DIN 7190 smoothing).
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..data import System, joint_record, material_record, require_section, system_of
from ..errors import GearoptInputError
from ..validation import check_range
from .joint_friction import FrictionJoint, joint_simulator

#: Friction-joint data not in the packaged data file, with provenance.
JOINT_FRICTION_DATA = {
    "key_clearance_um": 10.0,
    "key_clearance_um_source": "[E] half the side clearance of a parallel key in its keyways (DIN 6885 key h9 in a "
                               "shaft keyway N9 and hub keyway JS9: total clearance about 0..60 um, 20 um typical), "
                               "as arc at the fit surface",
    "key_stiffness_N_per_m": 1.0e9,
    "key_stiffness_N_per_m_source": "[E] shear of a 12 x 8 x 25 mm key (G A / b = 80 GPa x 300 mm^2 / 12 mm = "
                                    "2e9 N/m) in series with the bearing compliance of both keyway flanks",
    "shoulder_stiffness_N_per_m": 5.0e9,
    "shoulder_stiffness_N_per_m_source": "[E] axial contact of the hub face on the shaft shoulder (annulus ~ 40 "
                                         "cm^2 at 200 GPa over a few mm of effective length)",
    "interface_stiffness_N_per_m": 1.0e9,
    "interface_stiffness_N_per_m_source": "[E] axial (tangential) stiffness of the fit interface before gross slip: "
                                          "a few um of elastic micro-slip at the capacity (Mindlin-type tangential "
                                          "compliance of a 25-30 mm long, 42-65 mm fit); creep is a plastic slip and "
                                          "does not depend on it in the quasi-static limit",
    "interface_damping_ratio": 1.0,
    "interface_damping_ratio_source": "[E] critical damping of the gear's axial oscillation on the stuck interface "
                                      "(micro-slip hysteresis); carries no force in steady slip",
    "gear_mass_source": "[E] solid-disc equivalent of the gear's own inertia at its base radius, m = 2 J_gear / "
                        "r_b^2 (gears.<gear>.inertia_kgm2 or solid_disc_inertia_kgm2): 2.6 kg crank, 5.2 kg cam",
    "slip_speed_m_s": 10.0,
    "slip_speed_m_s_source": "regularisation (not a material property): slip speed at 100 % overstress (V -> inf: "
                             "rate-independent Coulomb slip). Measured on the default helical model (copies with V = "
                             "10 and 100 m/s on one trajectory, crank joint, 2 cycles after 1): slip path per cycle "
                             "within 2 % (0.1-0.2 % on most lash trajectories, 8 % on one with a harder impact: "
                             "the lash model is chaotic); creep per cycle at the nominal fit 0.29/0.29 (2500 rpm, nominal damper), "
                             "0.51/0.71 (2500, seized), 0.22/0.23 um (3300, seized); at the weakest fit 14.5/15.7 um "
                             "(2500, seized). The gear's axial inertia is modelled; its circumferential slip is "
                             "massless and bounded by the key",
    "friction_coefficient_min": 0.08,
    "friction_coefficient_max": 0.16,
    "friction_coefficient_range_source": "[V]/[E] DIN 7190-1 sec. 5.2/5.3 adhesion coefficients steel-steel "
                                         "(via FVA Workbench help, attribute 200241): 0.12 (pressure-oil fits, "
                                         "mineral oil) to 0.20 (degreased shrink fit); longitudinal (pressed, "
                                         "oiled) fits lower; 0.08-0.16 around the data's 0.12 [E]",
}

#: Damper states: multiplier of the data's viscous coefficient (module docstring).
DAMPER_STATES = {"nominal": 1.0, "degraded": 0.1, "seized": 100.0}
DAMPER_STATES_SOURCE = ("[E] nominal = data (optimum c = 80 N m s/rad); degraded 10 % (fluid degraded or partly "
                        "lost); seized 100x (gelled fluid, ring locked); thesis sec. 1: damper ineffective at "
                        "overspeed")
DAMPER_PARAMETER = "damper.damping_Nms_per_rad"
ENVELOPE_EXTRA_SPEED_RPM = 3300.0
ENVELOPE_EXTRA_SPEED_SOURCE = ("[E] motoring overspeed above the 3000 rpm overspeed test (the governor limits fuel, "
                               "not a vehicle pushing the engine downhill)")


def thrust_signs(train, gear: str, root_rotation: str = "cw") -> tuple:
    """((mesh, sign), ...) of the meshes of ``gear``: +1 when a positive mesh force (mesh torque on its first gear
    driving) pushes ``gear`` off its shaft nose, -1 towards the shoulder, 0 for a spur mesh
    (:func:`gearopt.joints.walk_off` conventions: hands, rotation senses)."""
    from ..joints import walk_off
    out = []
    for name, mesh in train.meshes.items():
        if gear not in mesh.gears:
            continue
        f = float(walk_off(train, {name: 1.0}, root_rotation=root_rotation).axial_force_N[gear])
        out.append((name, 0.0 if f == 0.0 else math.copysign(1.0, f)))
    return tuple(out)


def fit_capacity_N(system: System, joint: str, *, interference_um: float | None = None,
                   friction_coefficient: float | None = None, smoothing_loss_um: float = 0.0,
                   speed_rpm: float = 0.0) -> float:
    """Friction capacity mu p pi d l [N] of the joint ``joint`` of ``system`` (``system.joints[joint]``, a press
    fit, with its ``system.materials``) for a given diametral interference [um] (default the fit's mean), friction
    coefficient (default the data's) and smoothing loss [um], at ``speed_rpm`` (centrifugal loss):
    :func:`gearopt.joints.press_fit`. ``system``: the :class:`~gearopt.data.System` of the data file."""
    from ..joints import press_fit
    system = system_of(system, "fit_capacity_N")
    j = joint_record(system, joint, "fit_capacity_N").entries
    if j["joint_type"] != "press_fit":
        raise GearoptInputError(f"joint {joint!r} is a {j['joint_type']}, not a press fit")
    mu = float(j["friction_coefficient"]) if friction_coefficient is None else float(friction_coefficient)
    if mu <= 0.0:
        raise GearoptInputError(f"friction_coefficient={mu!r} must be > 0")
    delta = float(j["diametral_interference_um"]) if interference_um is None else float(interference_um)
    check_range("smoothing_loss_um", smoothing_loss_um, 0.0, None, unit="um")
    hub = material_record(system, j["hub_material"], "fit_capacity_N", f"joints.{joint}.hub_material")
    shaft = material_record(system, j["shaft_material"], "fit_capacity_N", f"joints.{joint}.shaft_material")
    r = press_fit(j["shaft_diameter_mm"], j["shaft_bore_diameter_mm"], j["hub_outer_diameter_mm"], j["fit_length_mm"],
                  max(delta, 0.0), shaft["E_MPa"], shaft["poisson_ratio"], hub["E_MPa"], hub["poisson_ratio"], mu,
                  smoothing_loss_um=smoothing_loss_um, speed_rpm=speed_rpm,
                  shaft_density_kg_m3=shaft["density_kg_m3"], hub_density_kg_m3=hub["density_kg_m3"])
    return float(r.axial_capacity_N)


def fit_cases(system: System, joint: str, speed_rpm: float) -> dict:
    """Capacities [N] at ``speed_rpm`` of the fit's extremes: ``weakest`` (minimum ISO 286 interference, DIN 7190
    smoothing 0.8 sum Rz, lowest friction coefficient), ``nominal`` (mean interference, no smoothing, data's mu)
    and ``strongest`` (maximum interference, 0.4 sum Rz, highest mu). ``system``: as :func:`fit_capacity_N`."""
    system = system_of(system, "fit_cases")
    j = joint_record(system, joint, "fit_cases").entries
    rz = float(j["shaft_roughness_Rz_um"]) + float(j["hub_roughness_Rz_um"])
    f = JOINT_FRICTION_DATA
    return {"weakest": fit_capacity_N(system, joint, interference_um=j["diametral_interference_min_um"],
                                      friction_coefficient=f["friction_coefficient_min"],
                                      smoothing_loss_um=0.8 * rz, speed_rpm=speed_rpm),
            "nominal": fit_capacity_N(system, joint, speed_rpm=speed_rpm),
            "strongest": fit_capacity_N(system, joint, interference_um=j["diametral_interference_max_um"],
                                        friction_coefficient=f["friction_coefficient_max"],
                                        smoothing_loss_um=0.4 * rz, speed_rpm=speed_rpm)}


def model_joints(model, joint: str, levels: int = 1, *, thrust_scale: float = 1.0,
                 key_clearance_um: float | None = None, root_rotation: str = "cw",
                 label: str | None = None) -> list[FrictionJoint]:
    """``levels`` copies ``<label>#<i>`` (label default ``joint``) of the friction element of ``[joints.<joint>]``
    on ``model`` (a :class:`~gearopt.cases.timing_train.TimingModel`; its joints from ``model.system``), to be
    given different capacities per run (the copies do not interact). Gear inertia: the whole node for a gear that
    is its own node (cam), else the data's gear inertia (crank: ``gears.crank.inertia_kgm2`` or its solid-disc
    estimate), as :func:`~gearopt.dynamics.sweep.walk_off_history`."""
    from .sweep import _model_gear_inertia_kgm2
    system = system_of(model.system, "model_joints")
    spec = joint_record(system, joint, "model_joints").entries
    check_range("levels", levels, 1, None)
    gear = spec["gear"]
    node = model.gear_nodes.get(gear, gear)
    j_g = model.network.inertias[node].inertia_kgm2 if node == gear else _model_gear_inertia_kgm2(model, gear)[0]
    f = JOINT_FRICTION_DATA
    cap = fit_capacity_N(system, joint)
    clearance = f["key_clearance_um"] if key_clearance_um is None else key_clearance_um
    return [FrictionJoint(f"{label or joint}#{i}", node, float(spec["shaft_diameter_mm"]), cap,
                          thrust_signs(model.train, gear, root_rotation), float(j_g), key_clearance_um=clearance,
                          key_stiffness_N_per_m=f["key_stiffness_N_per_m"],
                          shoulder_stiffness_N_per_m=f["shoulder_stiffness_N_per_m"],
                          slip_speed_m_s=f["slip_speed_m_s"], thrust_scale=thrust_scale,
                          gear_mass_kg=gear_mass_kg(model, gear),
                          interface_stiffness_N_per_m=f["interface_stiffness_N_per_m"],
                          interface_damping_ratio=f["interface_damping_ratio"])
            for i in range(levels)]


def gear_mass_kg(model, gear: str) -> float:
    """Axial mass of ``gear`` [kg]: the solid-disc equivalent ``2 J_gear / r_b^2`` of its own inertia at its base
    radius (:data:`JOINT_FRICTION_DATA` ``gear_mass_source``)."""
    from .sweep import _model_gear_inertia_kgm2
    j_gear = _model_gear_inertia_kgm2(model, gear)[0]
    node = model.gear_nodes.get(gear, gear)
    radii = [m.base_radii_mm[0] if m.gear_1 == node else m.base_radii_mm[1]
             for m in model.network.meshes.values() if node in (m.gear_1, m.gear_2)]
    if not radii:
        raise GearoptInputError(f"gear {gear!r} (node {node!r}) has no mesh in the model")
    return 2.0 * j_gear / (1e-3 * max(radii)) ** 2


def damper_coefficient(system: System, state) -> float:
    """Viscous coefficient [N m s/rad] of the crankshaft damper in ``state``: a name of :data:`DAMPER_STATES` (times
    ``[engine.crankshaft] damper_viscous_damping_Nms_per_rad`` of ``system``) or a coefficient [N m s/rad] (>= 0;
    e.g. from the fluid's viscosity at its temperature). ``system``: as :func:`fit_capacity_N`."""
    if isinstance(state, (int, float)) and not isinstance(state, bool):
        check_range("damper coefficient", state, 0.0, None, unit="N m s/rad")
        return float(state)
    if state not in DAMPER_STATES:
        raise GearoptInputError(f"damper state={state!r} must be one of {sorted(DAMPER_STATES)} or a coefficient "
                                f"[N m s/rad] >= 0")
    e = system_of(system, "damper_coefficient").section("engine", "damper_coefficient")
    return float(e["crankshaft"]["damper_viscous_damping_Nms_per_rad"]) * DAMPER_STATES[state]


def envelope_speeds_rpm(system: System) -> dict:
    """Speeds of the envelope [rpm] with their sources (module docstring): the rated, high-idle and overspeed-test
    speeds of ``[engine]`` of ``system`` (as :func:`fit_capacity_N`) with their provenance strings, and
    :data:`ENVELOPE_EXTRA_SPEED_RPM`."""
    system = system_of(system, "envelope_speeds_rpm")
    e, raw = system.section("engine", "envelope_speeds_rpm"), require_section(system, "engine", "envelope_speeds_rpm")
    return {"rated": (float(e["rated_speed_rpm"]), raw.get("rated_speed_rpm_source", "")),
            "high_idle": (float(e["high_idle_speed_rpm"]), raw.get("high_idle_speed_rpm_source", "")),
            "overspeed_test": (float(e["overspeed_test_speed_rpm"]), raw.get("overspeed_test_speed_rpm_source", "")),
            "motoring_overspeed": (ENVELOPE_EXTRA_SPEED_RPM, ENVELOPE_EXTRA_SPEED_SOURCE)}


def capacity_levels_N(system: System, joint: str, speed_rpm: float, levels: int) -> np.ndarray:
    """``levels`` capacities [N] spread geometrically from the weakest to the strongest fit case at the speed
    (the grid over which the Monte Carlo interpolates the creep). ``system``: as :func:`fit_capacity_N`."""
    cases = fit_cases(system_of(system, "capacity_levels_N"), joint, speed_rpm)
    lo, hi = max(cases["weakest"], 1.0), max(cases["strongest"], 2.0)
    return np.geomspace(lo, hi, levels) if levels > 1 else np.array([cases["nominal"]])


#: Capacities below the weakest toleranced fit added to the envelope (fractions of the weakest case): where the
#: fit would have to be to slip and creep (fretting wear, a wrong fit) -- "what data would change the verdict".
BELOW_TOLERANCE_FRACTIONS = (0.5, 0.75)


def joint_envelope(model, joints=("cam", "crank"), speeds_rpm=None, damper_states=None, levels: int = 5,
                   cycles: int = 2, run_in_cycles: int = 1, lash: bool = True, rtol: float = 1e-6,
                   thrust_scale: float = 1.0, jit: bool | None = None, parameters: dict | None = None,
                   executor_map=map, variants: dict | None = None) -> pd.DataFrame:
    """Slip utilisation and axial creep of the friction joints of ``model`` over speeds x damper states x fit
    capacities.

    ``speeds_rpm`` (default :func:`envelope_speeds_rpm`), ``damper_states`` (names of :data:`DAMPER_STATES` or
    coefficients [N m s/rad]; default all names), ``levels`` capacities per joint from the weakest to the strongest fit case
    (:func:`capacity_levels_N`; with ``levels`` >= 3 the nominal case replaces the nearest interior level) plus
    :data:`BELOW_TOLERANCE_FRACTIONS` of the weakest (``fit_case`` ``"0.5x_weakest"`` ...), ``cycles`` recorded
    after ``run_in_cycles``,
    ``lash`` (backlash model), ``thrust_scale`` (e.g. tan of a lower helix angle over the present one),
    ``variants`` {label: (joint, thrust_scale)}: further copies of a joint riding on the same integration (the same
    network trajectory -- which matters where the lash model rattles chaotically), reported as joint ``label``; ``jit``
    (default: if a C compiler is found), ``executor_map`` a ``map``-like callable over the (speed, damper) runs
    (default the builtin; e.g. :meth:`gearopt.studies.Executor.map` with processes: the worker is a module-level
    function, forked workers inherit the simulator built here, spawned ones rebuild it from the compile cache). The
    integrator's step limit is the network's contact limit at the lowest swept speed.

    Returns one row per (speed, damper state, joint, capacity level): ``train``, ``speed_rpm``, ``damper_state``,
    ``damper_Nms_per_rad``, ``joint``, ``level``, ``capacity_N``, ``fit_case`` (``weakest``/``nominal``/
    ``strongest`` where the level is one, else ``""``), ``max_rigid_utilisation``, ``max_utilisation``,
    ``slip_um_per_cycle``, ``axial_creep_um_per_cycle``, ``axial_position_um``, ``max_key_force_N``,
    ``max_off_nose_thrust_N``, ``run_time_s``.
    """
    from ..compile_cache import auto_jit
    system = system_of(model.system, "joint_envelope")
    speeds = [v for v, _ in envelope_speeds_rpm(system).values()] if speeds_rpm is None else \
        [float(s) for s in np.atleast_1d(speeds_rpm)]
    states = list(DAMPER_STATES) if damper_states is None else list(damper_states)
    for s in states:
        damper_coefficient(system, s)
    check_range("levels", levels, 1, None)
    elements = []
    labels = {joint: (joint, thrust_scale) for joint in joints}
    labels.update(variants or {})
    for label, (joint, scale) in labels.items():
        elements += model_joints(model, joint, levels + len(BELOW_TOLERANCE_FRACTIONS), thrust_scale=scale,
                                 label=label)
    spec = {"kind": model.kind, "labels": labels, "levels": int(levels), "cycles": int(cycles),
            "run_in_cycles": int(run_in_cycles), "lash": bool(lash), "rtol": float(rtol), "jit": auto_jit(jit),
            "parameters": dict(parameters or {}), "min_speed_rpm": min(speeds), "factory": model.factory}
    key = repr((id(model), sorted((k, repr(v)) for k, v in spec.items())))
    sim = joint_simulator(model.network, elements, lash=lash, rtol=rtol, jit=spec["jit"],
                          min_speed_rpm=spec["min_speed_rpm"])
    _REGISTRY[key] = (model, sim)  # forked workers inherit it; spawned ones rebuild from the spec
    points = [(s, st) for s in speeds for st in states]
    try:
        rows = list(executor_map(_envelope_point, [(key, spec, system, pt) for pt in points]))
    finally:
        _REGISTRY.pop(key, None)  # the simulator lives as long as its envelope (no growth over repeated calls)
    return pd.DataFrame([row for r in rows for row in r])


#: Built (model, simulator) pairs of :func:`joint_envelope` by key, for the worker function (module level so that
#: an executor's processes can run it).
_REGISTRY: dict = {}


def _envelope_point(task) -> list[dict]:
    """Rows of one (speed, damper state) point of :func:`joint_envelope`: ``task = (key, spec, system, point)``
    (``system`` the model's :class:`~gearopt.data.System`)."""
    key, spec, system, (speed, state) = task
    if key not in _REGISTRY:  # a spawned worker: rebuild the model and simulator from the spec
        import importlib
        where, kwargs = spec["factory"]
        module, function = where.split(":")
        model = getattr(importlib.import_module(module), function)(system=system, **kwargs)
        elements = []
        for label, (joint, scale) in spec["labels"].items():
            elements += model_joints(model, joint, spec["levels"] + len(BELOW_TOLERANCE_FRACTIONS),
                                     thrust_scale=scale, label=label)
        _REGISTRY[key] = (model, joint_simulator(model.network, elements, lash=spec["lash"], rtol=spec["rtol"],
                                                 jit=spec["jit"], min_speed_rpm=spec["min_speed_rpm"]))
    model, sim = _REGISTRY[key]
    system = system_of(system, "joint_envelope")
    levels = spec["levels"]
    p = model.parameters_at(speed)
    p.update(spec["parameters"])
    p[DAMPER_PARAMETER] = damper_coefficient(system, state)
    caps, case_of = {}, {}
    for label, (joint, _) in spec["labels"].items():
        cases = fit_cases(system, joint, speed)
        grid = capacity_levels_N(system, joint, speed, levels)
        below = len(BELOW_TOLERANCE_FRACTIONS)
        if levels >= 3:
            mid = 1 + int(np.argmin(np.abs(np.log(grid[1:-1] / cases["nominal"]))))
            grid[mid] = cases["nominal"]
            case_of[label] = {below: "weakest", below + mid: "nominal", below + levels - 1: "strongest"}
        else:
            case_of[label] = {below: "nominal"} if levels == 1 else {below: "weakest", below + 1: "strongest"}
        case_of[label].update({i: f"{f:g}x_weakest" for i, f in enumerate(BELOW_TOLERANCE_FRACTIONS)})
        grid = np.concatenate([np.array(BELOW_TOLERANCE_FRACTIONS) * max(cases["weakest"], 1.0), grid])
        for i, c in enumerate(grid):
            caps[f"{label}#{i}.capacity_N"] = float(c)
    p.update(caps)
    res = sim.run(speed, spec["cycles"], parameters=p, run_in_cycles=spec["run_in_cycles"])
    rows = []
    for name, r in res.summary.iterrows():
        joint, level = name.split("#")
        rows.append({"train": model.kind, "speed_rpm": speed, "damper_state": state,
                     "damper_Nms_per_rad": p[DAMPER_PARAMETER], "joint": joint, "level": int(level),
                     "capacity_N": caps[f"{name}.capacity_N"],
                     "fit_case": case_of.get(joint, {}).get(int(level), ""), **r.to_dict(),
                     "run_time_s": res.stats["integration_time_s"]})
    return rows


__all__ = [
    "BELOW_TOLERANCE_FRACTIONS",
    "DAMPER_PARAMETER",
    "DAMPER_STATES",
    "DAMPER_STATES_SOURCE",
    "JOINT_FRICTION_DATA",
    "capacity_levels_N",
    "damper_coefficient",
    "envelope_speeds_rpm",
    "fit_capacity_N",
    "fit_cases",
    "gear_mass_kg",
    "joint_envelope",
    "model_joints",
    "thrust_signs",
]
