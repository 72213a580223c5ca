"""Shaft-hub joint as a friction element in the torsional dynamics: slip, key stop, shoulder stop and axial creep.

A gear press fitted on its shaft (with a key, thesis sec. 3.11/4.7.1) has two slip coordinates of the hub on the
seat: ``u_t`` [m], the circumferential slip at the fit surface (relative rotation ``u_t / r``), and ``u_a`` [m], the
axial position of the gear measured from the shaft shoulder, positive *off the shaft nose* (+z of
:mod:`gearopt.joints.walk_off`). Both are states of the integration.

Demand. The interface must transmit the friction-force vector ``D = (D_t, D_a)`` [N]:

* ``D_t = T_joint / r - F_key(u_t)``: the joint torque over the fit radius, minus what the key takes. ``T_joint``
  [N m] is the gear's rotational equilibrium ``sum of its mesh torques - J_g alpha`` (the net mesh torque on the
  gear minus its own inertia torque, alpha the acceleration of its network node), in the network's common sign
  convention;
* ``D_a = F_thrust + F_shoulder(u_a)``: the helical meshes' axial force on the gear (+ off the nose; the sign of
  each mesh from the train's hands and rotation senses) plus the shoulder's reaction.

Key: a stop on ``u_t`` with clearance ``c`` per side (arc at the fit radius) and stiffness ``k_key`` [N/m],
``F_key = k_key (max(u_t - c, 0) - max(-u_t - c, 0))``. Shoulder: a one-sided stop at ``u_a = 0``,
``F_shoulder = k_sh max(-u_a, 0)``, so only thrust off the nose can move the gear away from it. Both are exact
piecewise-linear springs (Lipschitz, like the slip law's ``<.>_+``; CVODES' error control finds the kinks): a
smoothed stop would leave a small force at rest that, with the hub slipping round, walks the gear by itself.

Friction (regularised Coulomb with a combined capacity, viscoplastic form)::

    du/dt = V <|D|/C - 1>_+ * D / |D|        (|D| = sqrt(D_t^2 + D_a^2))

``C`` [N] the friction capacity ``mu p pi d l`` (:func:`gearopt.joints.press_fit`), shared by torque and axial force
(the capacity circle). Inside the circle (stick) the slip rate is exactly zero -- no creep below capacity; outside
it the hub slips along the demand direction, with the relative overstress ``|D|/C - 1 = |v|/V`` that the slip
speed needs. As the regularisation speed ``V`` [m/s] grows this converges to rate-independent Coulomb slip (tested),
in which the
hub slips just fast enough to keep the demand on the circle. The axial creep accompanying a circumferential slip
``du_t`` is ``du_a = (D_a / |D_t|) |du_t|``: its sign follows the thrust's, whichever way the hub slips round. With
the key engaged, part of the torque goes into the key, the circumferential friction stays saturated and every
torque swing that slips the hub (forward against the key and back on the key's spring-back) lets the thrust drive
the gear along the shaft: ratcheting ("walk-out"). A spur mesh gives ``D_a = 0`` and no axial creep.

Axial inertia. The gear moves axially as a mass ``m`` on the interface: its position ``u_a`` is a state with its
velocity, and the interface carries the axial force ``D_a = k_c (u_a - z)`` through a stiff elastic layer ``k_c``
(the fit's tangential contact stiffness before gross slip) in series with the plastic slip ``z`` that the friction
law above drives (``D_a`` replaces ``F_thrust + F_shoulder`` in ``D``)::

    dz/dt = v_a(D_t, D_a)                          (the flow law above)
    m d2u_a/dt2 = F_thrust + F_shoulder(u_a) - D_a - c_c (du_a/dt - dz/dt),   c_c = 2 zeta_c sqrt(k_c m)

(the dashpot ``c_c`` damps the gear's oscillation on the stuck interface only: it fades out linearly up to a slip
speed of :data:`STICK_DAMPING_FADE_M_S`, so a slipping interface carries no more than its capacity).
Quasi-statically (slow thrust) ``D_a = F_thrust + F_shoulder`` and the element is the massless law above. When the
thrust alone exceeds the capacity the massless law has no bounded answer (it would slide at ``V (|F|/C - 1)``, a
speed set by the regularisation, not by physics); with the mass the gear accelerates at ``(F - C)/m`` as Coulomb
friction with inertia does, until ``V`` itself bounds it (terminal speed ``V (F/C - 1)`` after ``m V / C``; both
closed forms tested).

Definitions. *Slip utilisation* (``rigid_utilisation``, the headline): the combined friction demand the fit would
have to carry if the gear stuck on its seat with the key unloaded, ``|(T_joint/r, F_thrust)| / C``; above 1 the fit
slips and the key (circumferentially) and the gear's inertia (axially) carry the excess -- it says how far the fit
is from holding, not what the interface carries. The interface itself never carries more than its capacity:
``utilisation`` ``|(D_t, D_a)|/C`` exceeds 1 only by the regularisation's overstress ``|v|/V``. *Axial creep*: the
change of the plastic axial slip ``z`` over the recorded cycles per engine cycle (+ off the nose); the gear's elastic
axial deflection on the interface (``D_a/k_c``) and on the shoulder recovers and is not creep.

Coupling (approximation, stated): one-way. The slip states are driven by the network's mesh forces and node
accelerations but do not feed back into the torsional model (the gear stays lumped in its node): the relative
rotation is bounded by the key clearance (about 1 mrad) and the friction dissipated by slip would only damp the
vibration, so the one-way coupling over-estimates rather than hides the slip. The hub's circumferential inertia relative
to its shaft is replaced by the viscoplastic regularisation ``V`` (its slip speed follows the overstress; the slip
is bounded by the key's clearance and stiffness); its axial inertia is modelled (above). Under
slowly varying loads the result converges quickly in ``V`` (tested); under short impacts (a rattling mesh) the slip
of each impact grows with ``V`` towards the key-bounded limit of a massless hub, and the hub's inertia would hold it
back: there ``V`` is a stated modelling choice with a measured sensitivity
(:data:`gearopt.dynamics.walk_off_envelope.JOINT_FRICTION_DATA`).

Several joints, and several copies of one joint with different capacities, can ride on one network integration
(they do not interact): one run gives the creep of a whole range of fits.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import casadi as ca
import numpy as np
import pandas as pd

from .. import compile_cache
from .. import numerics as nm
from ..errors import GearoptInputError, SolveError
from ..geometry.forces import mesh_torque_Nm
from ..validation import check_range
from .buffered_call import BufferedFunction
from .implicit_steps import implicit_steps
from .joint_element import (  # noqa: F401 -- the element's names are part of this module's interface
    DEMAND_FLOOR_N,
    STICK_DAMPING_FADE_M_S,
    FrictionJoint,
    joint_rates,
    key_force_N,
    shoulder_force_N,
    slip_rates_m_s,
)
from .network import OFFSET_PARAMETER, SPEED_PARAMETER, TorsionalNetwork

#: Unit of the slip states [m] (millimetres: the integrator's absolute tolerance, 0.1 rtol in state units, is then
#: 1e-7 mm = 0.1 nm at rtol 1e-6, far below the 0.01 um creep per cycle resolved; outputs are in um).
SLIP_UNIT_M = 1e-3
#: Names of the per-joint integration parameters (prefixed ``<joint>.``).
JOINT_PARAMETERS = ("capacity_N", "key_clearance_um", "slip_speed_m_s", "thrust_scale")
#: Per-joint outputs (``joint_outputs`` frames).
JOINT_OUTPUTS = ("joint_torque_Nm", "thrust_N", "demand_tangential_N", "demand_axial_N", "rigid_utilisation",
                 "utilisation", "key_force_N", "shoulder_force_N", "slip_um", "axial_position_um",
                 "slip_speed_m_s", "axial_slip_um", "axial_velocity_m_s")
#: Slip states per joint: circumferential slip u_t, plastic axial slip z, the gear's axial position u_a (all in
#: SLIP_UNIT_M) and its axial velocity du_a/d(crank angle) [SLIP_UNIT_M/rad]. A joint on which no mesh can put a
#: thrust (a spur gear) carries u_t only: its axial states would stay exactly 0 (``THRUST_FREE_STATES``).
STATES_PER_JOINT = 4
THRUST_FREE_STATES = 1
#: Ways of integrating the slip states with the network (:class:`JointSimulator` ``integration``).
INTEGRATIONS = ("sequential", "simultaneous")
#: Most chunks of a cycle in which ``integration="sequential"`` integrates the slip states (each with its own
#: forcing table; the integrator restarts at each chunk's start).
SLIP_CHUNKS_PER_CYCLE = 16
#: Integrators of the slip states of a gear whose joints carry no thrust (:class:`JointSimulator`
#: ``thrust_free_integrator``).
THRUST_FREE_INTEGRATORS = ("bdf2", "cvodes")
#: Newton tolerance of the fixed-step integration, a fraction of the absolute tolerance ``atol`` (a step is accepted
#: when its largest residual entry is at most ``atol``).
BDF2_NEWTON_TOLERANCE = 1e-3
#: Fixed steps per interval of the forcing grid (the forcing linear in between, as CVODES reads it).
BDF2_STEPS_PER_FORCING_STEP = 2


class JointIntegrationError(SolveError):
    """The integration of a network with friction joints could not hold its tolerance through stick-slip (or ran
    out of its step budget); ``status`` holds the integrator's message."""

    def __init__(self, message: str, *, status: str = "", hint: str = ""):
        super().__init__(message, hint=hint)
        self.status = status


# ----------------------------------------------------------------------------------------------------------------
# augmented equations and integration
# ----------------------------------------------------------------------------------------------------------------

def _sign(v: float) -> float:
    return 1.0 if v >= 0.0 else -1.0


@dataclass
class JointEquations:
    """Network equations augmented by the slip states (after the network's states, per joint from
    ``state_offsets[i]``: u_t, and where a thrust can act z, u_a and the axial velocity; ``thrust_free[i]``: the
    joint carries u_t only).

    The coupling is one-way, so the joints see the network only through their *forcing*: per distinct gear (node,
    gear inertia, thrust signs) the joint torque [N m] and the unscaled thrust [N], ``forcing`` (expressions in
    ``tau``, the network's states ``x[:n_network]`` and ``p``; rows ``2 g`` and ``2 g + 1`` for the gear
    ``g = gear_of_joint[i]`` of joint ``i``). ``joint_rhs`` are the joints' rates in terms of ``forcing_symbols``
    instead (and of the slip states and ``p``), for integrating the joints after the network
    (:class:`JointSimulator` ``integration="sequential"``)."""

    x: ca.SX
    p: ca.SX
    tau: ca.SX
    rhs: ca.SX
    outputs: ca.SX
    parameter_names: list
    output_names: list
    n_network: int
    state_offsets: tuple = ()
    thrust_free: tuple = ()
    forcing: ca.SX | None = None
    forcing_symbols: ca.SX | None = None
    joint_rhs: ca.SX | None = None
    gear_of_joint: tuple = ()


def _joint_forcing(network: TorsionalNetwork, eq, joint: FrictionJoint):
    """(joint torque [N m], unscaled thrust [N]) of ``joint`` as expressions of the network equations ``eq``:
    the gear's net mesh torque minus its own inertia torque, and its meshes' axial forces with the joint's thrust
    signs (module docstring, "Demand")."""
    ratios = network.speed_ratios()
    free = eq.free_nodes
    omega = eq.p[eq.parameter_names.index(SPEED_PARAMETER)]
    out_index = {name: i for i, name in enumerate(eq.output_names)}
    if joint.gear_node not in network.inertias:
        raise GearoptInputError(f"joint {joint.name!r}: gear_node={joint.gear_node!r} is not a network node")
    if joint.gear_node in network.boundary_nodes:
        raise GearoptInputError(f"joint {joint.name!r}: gear_node={joint.gear_node!r} is a speed boundary")
    torque, thrust = 0.0, 0.0
    signs = dict(joint.thrust_signs)
    for m in network.meshes.values():
        if joint.gear_node not in (m.gear_1, m.gear_2):
            continue
        s1 = _sign(ratios[m.gear_1])
        r_gear_mm = m.base_radii_mm[0] if m.gear_1 == joint.gear_node else m.base_radii_mm[1]
        force = eq.outputs[out_index[("mesh_force_N", m.name)]]
        torque = torque - mesh_torque_Nm(force * s1, r_gear_mm)
        thrust = thrust + float(signs.get(m.name, 0.0)) * eq.outputs[out_index[("axial_force_N", m.name)]]
    unknown = set(signs) - {m.name for m in network.meshes.values() if joint.gear_node in (m.gear_1, m.gear_2)}
    if unknown:
        raise GearoptInputError(f"joint {joint.name!r}: thrust_signs name meshes {sorted(unknown)} that do not "
                                f"touch node {joint.gear_node!r}")
    n = len(free)
    torque = torque - joint.gear_inertia_kgm2 * eq.rhs[n + free.index(joint.gear_node)] * omega
    return ca.SX(torque), ca.SX(thrust)


def joint_equations(network: TorsionalNetwork, joints, lash: bool = True) -> JointEquations:
    """Build the augmented equations (cached on the network per joint set and lash option)."""
    joints = tuple(joints)
    key = ("joint_equations", bool(lash), joints)
    if key in network._cache:
        return network._cache[key]
    names = [j.name for j in joints]
    if len(set(names)) != len(names):
        raise GearoptInputError(f"joint names {names} must be unique")
    eq = network.equations(lash=lash)
    omega = eq.p[eq.parameter_names.index(SPEED_PARAMETER)]
    extra_names = [f"{j.name}.{k}" for j in joints for k in JOINT_PARAMETERS]
    p_joint = ca.SX.sym("p_joint", len(extra_names))
    forcing, forcing_row = [], {}       # per distinct gear: torque, unscaled thrust
    states, rates, outputs, out_names, offsets, thrust_free, symbols, gear_of = [], [], [], [], [], [], [], []
    for i, j in enumerate(joints):
        gear = (j.gear_node, j.gear_inertia_kgm2, tuple(sorted(dict(j.thrust_signs).items())))
        if gear not in forcing_row:
            forcing_row[gear] = len(forcing)
            forcing += list(_joint_forcing(network, eq, j))
            symbols += [ca.SX.sym(f"torque_{len(symbols) // 2}"), ca.SX.sym(f"thrust_{len(symbols) // 2}")]
        torque, unscaled = symbols[forcing_row[gear]], symbols[forcing_row[gear] + 1]
        gear_of.append(forcing_row[gear] // 2)
        capacity, clearance_um, v_reg, scale = (p_joint[4 * i + k] for k in range(4))
        free_of_thrust = forcing[forcing_row[gear] + 1].is_zero()     # no mesh of this gear has an axial force
        thrust = 0.0 if free_of_thrust else scale * unscaled
        offsets.append(sum(s.numel() for s in states))
        thrust_free.append(bool(free_of_thrust))
        u = ca.SX.sym(f"u_{i}", THRUST_FREE_STATES if free_of_thrust else STATES_PER_JOINT)
        states.append(u)
        slip = u[0] * SLIP_UNIT_M
        # without thrust z, u_a and their velocity stay exactly 0 (no axial demand, no shoulder contact)
        z, axial, w = (0.0, 0.0, 0.0) if free_of_thrust else (u[1] * SLIP_UNIT_M, u[2] * SLIP_UNIT_M,
                                                              u[3] * SLIP_UNIT_M * omega)
        jr = joint_rates(j, torque, thrust, slip, z, axial, w, capacity, clearance_um * 1e-6, v_reg)
        d_t, d_a, v_t, v_z = (jr["demand_tangential_N"], jr["demand_axial_N"], jr["slip_rate_m_s"],
                              jr["axial_slip_rate_m_s"])
        rates.append(v_t / SLIP_UNIT_M / omega)
        if not free_of_thrust:
            rates += [v_z / SLIP_UNIT_M / omega, u[3], jr["axial_acceleration_m_s2"] / SLIP_UNIT_M / omega ** 2]
        r = 0.5e-3 * j.fit_diameter_mm
        rigid = nm.sqrt((torque / r) ** 2 + thrust ** 2) / capacity
        util = nm.sqrt(d_t ** 2 + d_a ** 2) / capacity
        outputs += [torque, thrust, d_t, d_a, rigid, util, jr["key_force_N"], jr["shoulder_force_N"], slip * 1e6,
                    axial * 1e6, nm.sqrt(v_t ** 2 + v_z ** 2), z * 1e6, w]
        out_names += [(q, j.name) for q in JOINT_OUTPUTS]
    forcing, symbols = ca.vertcat(*forcing), ca.vertcat(*symbols)
    joint_rhs = ca.vertcat(*rates)
    # the network's own equations do not depend on the joint states (one-way coupling)
    coupled_rhs, coupled_outputs = ca.substitute([joint_rhs, ca.vertcat(*outputs)], [symbols], [forcing])
    result = JointEquations(x=ca.vertcat(eq.x, *states), p=ca.vertcat(eq.p, p_joint), tau=eq.tau,
                            rhs=ca.vertcat(eq.rhs, coupled_rhs), outputs=coupled_outputs,
                            parameter_names=list(eq.parameter_names) + extra_names, output_names=out_names,
                            n_network=int(eq.x.numel()), state_offsets=tuple(offsets), thrust_free=tuple(thrust_free),
                            forcing=forcing, forcing_symbols=symbols, joint_rhs=joint_rhs,
                            gear_of_joint=tuple(gear_of))
    network._cache[key] = result
    return result


@dataclass
class JointSimulation:
    """Result of :meth:`JointSimulator.run`: per joint (columns) the outputs of ``JOINT_OUTPUTS`` over the recorded
    cycles (``frames[quantity]``, index ``crank_angle_deg`` from the start of the recording), and per joint the
    summary ``summary`` (DataFrame): ``max_rigid_utilisation`` (peak combined demand with the gear stuck and the
    key unloaded, |(T/r, F_thrust)|/C), ``max_utilisation`` (peak |D|/C of the element), ``slip_um_per_cycle``
    (total circumferential slip path per cycle), ``axial_creep_um_per_cycle`` (change of the plastic axial slip over
    the recorded cycles per cycle, + off the nose), ``axial_creep_um_cycle_std`` (its standard deviation from cycle
    to cycle; 0 for one cycle), ``max_cycle_axial_creep_um`` (largest single cycle), ``axial_position_um`` (the
    gear's, at the end), ``max_key_force_N``,
    ``max_off_nose_thrust_N``; ``speed_rpm``, ``cycles``, ``run_in_cycles``, ``stats``."""

    speed_rpm: float
    cycles: int
    run_in_cycles: int
    crank_angle_deg: np.ndarray
    frames: dict
    summary: pd.DataFrame
    final_state: np.ndarray
    stats: dict


class JointSimulator:
    """One CasADi integrator (CVODES) over one excitation cycle for a network with friction joints.

    ``network`` (:class:`~gearopt.dynamics.network.TorsionalNetwork`), ``joints`` (:class:`FrictionJoint` s),
    ``lash``, ``rtol``/``atol`` (network states as in :class:`~gearopt.dynamics.simulate.Simulator`; the slip
    states in um), ``output_step_deg``, ``max_step_deg`` (default: the network simulator's contact step limit at
    ``min_speed_rpm``), ``max_num_steps`` per cycle (the step budget: beyond it a :class:`JointIntegrationError`),
    ``jit`` (compile the integrator and outputs with the C compiler, once: :mod:`gearopt.compile_cache` keeps the
    binaries on disk across runs).

    ``integration`` (the coupling is one-way, so the same model either way):

    * ``"sequential"`` (default): each cycle integrates the network alone, evaluates the joints' forcing (joint
      torque and thrust per gear) on its output grid of ``forcing_step_deg``, then integrates the slip states of
      each gear alone (in :data:`SLIP_CHUNKS_PER_CYCLE` chunks of the cycle), driven by that forcing interpolated
      linearly. The network keeps its own steps, and a gear whose joints stick does not take the steps of one whose
      joints slip. Approximation: the forcing between grid points is linear (a lash impact of the default train
      lasts about a degree; the default 0.025 deg puts some 40 points on it). Measured: on a ratcheting joint both
      integrations agree to 1e-5 and a 20x coarser grid moves slip and creep by less than 0.1 % (tested); on the
      default helical model with lash, on one network trajectory, halving the grid moved the creep of the fits
      from the weakest up by less than 0.1 %, that of half the weakest fit (a gear whose thrust exceeds its
      capacity) by 3 % at 3300 rpm and changed its sign at 2500 rpm, where it is below 1 um per cycle.
    * ``"simultaneous"``: network and slip states in one integration (every stick-slip transition also cuts the
      network's steps).

    ``thrust_free_integrator`` (``"sequential"`` only), for a gear on which no mesh puts a thrust (one slip state
    per joint): ``"bdf2"`` (default) fixed implicit steps, :data:`BDF2_STEPS_PER_FORCING_STEP` per forcing step,
    each joint copy its own Newton solve (:mod:`gearopt.dynamics.implicit_steps`), so that the copies do not share
    each other's stick-slip transitions as one adaptive integration does; a chunk whose steps leave a residual
    above ``atol`` is integrated by CVODES instead (counted in the run's ``stats["fallback_chunks"]``; the joint
    steps redone by backward-Euler substeps in ``stats["substep_steps"]``).
    Approximation, measured on the default spur model's joints: slip path within 0.6 %, key force within 1.5 %,
    utilisation within 1 % of CVODES; the default spur envelope 25.1 -> 15.4 CPU-s (its network integrations
    unchanged). ``"cvodes"``: CVODES as for the other gears.
    """

    def __init__(self, network: TorsionalNetwork, joints, *, lash: bool = True, rtol: float = 1e-6,
                 atol: float | None = None, output_step_deg: float = 0.5, max_step_deg: float | None = None,
                 min_speed_rpm: float = 700.0, max_num_steps: int = 2_000_000, jit: bool = False,
                 integration: str = "sequential", forcing_step_deg: float = 0.025,
                 thrust_free_integrator: str = "bdf2"):
        from .simulate import simulator
        if integration not in INTEGRATIONS:
            raise GearoptInputError(f"integration={integration!r} must be one of {INTEGRATIONS}")
        if thrust_free_integrator not in THRUST_FREE_INTEGRATORS:
            raise GearoptInputError(f"thrust_free_integrator={thrust_free_integrator!r} must be one of "
                                    f"{THRUST_FREE_INTEGRATORS}")
        self.integration = integration
        self.thrust_free_integrator = thrust_free_integrator
        self.joints = tuple(joints)
        if not self.joints:
            raise GearoptInputError("joints must name at least one FrictionJoint")
        check_range("rtol", rtol, 0.0, 1e-2, low_inclusive=False)
        atol = 0.1 * rtol if atol is None else atol
        check_range("atol", atol, 0.0, None, low_inclusive=False)
        check_range("output_step_deg", output_step_deg, 0.0, None, low_inclusive=False, unit="deg")
        check_range("max_num_steps", max_num_steps, 1, None)
        n_out = network.cycle_deg / output_step_deg
        if abs(n_out - round(n_out)) > 1e-9 * n_out:
            raise GearoptInputError(f"output_step_deg={output_step_deg} must divide cycle_deg={network.cycle_deg}")
        self.network = network
        self.lash = bool(lash)
        self.min_speed_rpm = float(min_speed_rpm)
        self.jit = bool(jit)
        if integration == "sequential":  # the network's integrator over the forcing grid (_build_sequential)
            check_range("forcing_step_deg", forcing_step_deg, 0.0, output_step_deg, low_inclusive=False, unit="deg")
            self.base = simulator(network, lash=self.lash, rtol=rtol, atol=atol, output_step_deg=forcing_step_deg,
                                  max_step_deg=max_step_deg, min_speed_rpm=self.min_speed_rpm,
                                  contact_quadratures=False, max_steps_per_cycle=max_num_steps, jit=self.jit,
                                  output_functions=False)
        else:
            self.base = simulator(network, lash=self.lash, rtol=rtol, min_speed_rpm=min_speed_rpm)
        self.eq = joint_equations(network, self.joints, self.lash)
        self.n_out = round(n_out)
        self.cycle_rad = math.radians(network.cycle_deg)
        self.grid_rad = np.radians(output_step_deg * np.arange(1, self.n_out + 1))
        self.output_step_deg = float(output_step_deg)
        self.max_step_deg = self.base.max_step_deg if max_step_deg is None else float(max_step_deg)
        opts = {"reltol": float(rtol), "abstol": float(atol), "max_num_steps": int(max_num_steps)}
        self.atol = float(atol)
        if self.max_step_deg is not None:
            opts["max_step_size"] = math.radians(self.max_step_deg)
        t0 = time.perf_counter()
        self.compiled: dict = {}
        self.integrator = None      # "simultaneous": the one integrator; "sequential": self.integrators, per gear
        if integration == "simultaneous":
            ode = ca.Function("joint_ode", [self.eq.tau, self.eq.x, self.eq.p], [self.eq.rhs], {"cse": True})
            dae = {"x": self.eq.x, "p": self.eq.p, "t": self.eq.tau, "ode": ode(self.eq.tau, self.eq.x, self.eq.p)}
            self.integrator = self._build(
                "joint_cycle", dae["ode"],
                lambda extra: ca.integrator("joint_cycle", "cvodes", dae, 0.0, self.grid_rad, dict(opts, **extra)),
                repr(("cvodes", sorted(opts.items()), self.grid_rad.tolist())))
        else:
            self._build_sequential(network, opts, output_step_deg, forcing_step_deg)
        self.output_function = self._build("joint_outputs", self.eq.outputs, lambda extra: ca.Function(
            "joint_outputs", [self.eq.tau, self.eq.x, self.eq.p], [self.eq.outputs],
            dict({"cse": True}, **extra)), "point").map(self.n_out)  # mapped here: a saved map loads slowly
        self._point_outputs = ca.Function("joint_outputs", [self.eq.tau, self.eq.x, self.eq.p], [self.eq.outputs])
        self.build_time_s = time.perf_counter() - t0
        self.options = opts

    def _build_sequential(self, network, opts, output_step_deg, forcing_step_deg):
        """The functions of ``integration="sequential"`` beside the network's integrator over the forcing grid
        (``self.base``): the forcing over that grid, and per gear the slip states' integrator driven by the forcing
        interpolated linearly."""
        ratio = output_step_deg / forcing_step_deg
        if abs(ratio - round(ratio)) > 1e-9 * ratio:
            raise GearoptInputError(f"forcing_step_deg={forcing_step_deg} must divide output_step_deg="
                                    f"{output_step_deg}")
        self.forcing_stride = round(ratio)
        eq = self.eq
        n_net, n_p_net = eq.n_network, network.equations(lash=self.lash).p.numel()
        n_fine = self.n_out * self.forcing_stride
        x_net, p_net = eq.x[:n_net], eq.p[:n_p_net]
        self._forcing_point = ca.Function("joint_forcing", [eq.tau, x_net, p_net], [eq.forcing], {"cse": True})
        self.forcing_function = self._build("joint_forcing", eq.forcing, lambda extra: ca.Function(
            "joint_forcing", [eq.tau, x_net, p_net], [eq.forcing], dict({"cse": True}, **extra)), "point",
            inputs=[eq.tau, x_net, p_net]).map(n_fine)
        # the slip states are integrated chunk by chunk of the cycle, each chunk with its own forcing table (an
        # interpreted Function copies its inputs on every evaluation: a whole cycle's table would cost more than
        # the slip equations)
        self.chunks = max(c for c in range(1, SLIP_CHUNKS_PER_CYCLE + 1) if self.n_out % c == 0)
        per_chunk = self.n_out // self.chunks
        h = math.radians(forcing_step_deg)
        grid = (h * np.arange(per_chunk * self.forcing_stride + 1)).tolist()
        interpolate = ca.interpolant("joint_forcing_table", "linear", [grid], 2, {"lookup_mode": ["exact"]})
        chunk_grid = self.grid_rad[:per_chunk]
        # the joints of each gear in an integration of their own: a gear whose joints stick does not take the
        # steps of one whose joints slip
        self.gear_rows, self.integrators, self.fixed_steps, self._cvodes = [], [], [], []
        u_all = eq.x[n_net:]
        steps = per_chunk * self.forcing_stride
        for g in range(eq.forcing_symbols.numel() // 2):
            members = [i for i in range(len(self.joints)) if eq.gear_of_joint[i] == g]
            blocks = [np.arange(eq.state_offsets[i], eq.state_offsets[i] + self._joint_states(i)) for i in members]
            rows = np.concatenate(blocks).astype(int)
            forcing = eq.forcing_symbols[2 * g:2 * g + 2]
            u = u_all[rows.tolist()]
            rates = ca.Function(f"joint_rates_{g}", [u, forcing, eq.p], [eq.joint_rhs[rows.tolist()]], {"cse": True})
            tau, u_mx = ca.MX.sym("tau"), ca.MX.sym("u", rows.size)
            p_mx, table = ca.MX.sym("p", eq.p.numel()), ca.MX.sym("forcing_table", 2 * len(grid))
            ode = rates(u_mx, interpolate(tau, table), p_mx)
            dae = {"x": u_mx, "p": ca.vertcat(p_mx, table), "t": tau, "ode": ode}
            self.gear_rows.append(rows)
            self._cvodes.append(lambda dae=dae, g=g, ode=ode, ins=[tau, u_mx, p_mx, table]: self._build(
                f"joint_slip_{g}", ode,
                lambda extra: ca.integrator(f"joint_slip_{g}", "cvodes", dae, 0.0, chunk_grid, dict(opts, **extra)),
                repr(("cvodes", sorted(opts.items()), chunk_grid.tolist())), inputs=ins))
            if self.thrust_free_integrator == "bdf2" and all(eq.thrust_free[i] for i in members):
                # joints without thrust: one slip state each, fixed implicit steps on the forcing grid; CVODES is
                # built only for a chunk those steps do not resolve
                pairs = [(u_all[b.tolist()], eq.joint_rhs[b.tolist()]) for b in blocks]
                tol = BDF2_NEWTON_TOLERANCE * self.atol
                fine = steps * BDF2_STEPS_PER_FORCING_STEP
                _, one = implicit_steps(f"joint_slip_bdf2_{g}", pairs, forcing, eq.p, fine, tolerance=tol)
                ins = one.mx_in()
                self.fixed_steps.append(self._build(
                    f"joint_slip_bdf2_{g}", ca.vertcat(*one(*ins)),
                    lambda extra, pairs=pairs, g=g, forcing=forcing, tol=tol: implicit_steps(
                        f"joint_slip_bdf2_{g}", pairs, forcing, eq.p, fine, tolerance=tol, options=extra)[0],
                    repr(("bdf2", fine, tol)), inputs=ins))
                self.integrators.append(None)
            else:
                self.fixed_steps.append(None)
                self.integrators.append(self._cvodes[g]())

    def _fixed_steps_resolved(self, residuals: np.ndarray) -> bool:
        """Whether a chunk's fixed steps all converged: every step's largest residual entry at most ``atol``."""
        return bool(residuals.max() <= self.atol)

    def _joint_states(self, i: int) -> int:
        """Number of slip states of joint ``i``."""
        return THRUST_FREE_STATES if self.eq.thrust_free[i] else STATES_PER_JOINT

    def _build(self, name: str, expression, build, options_repr: str, inputs=None):
        """``build(extra_options)`` through the on-disk compile cache (:mod:`gearopt.compile_cache`) when ``jit``,
        keyed by the serialized graph of ``expression`` over ``inputs`` (default (tau, x, p)) and
        ``options_repr``."""
        if not self.jit:
            self.compiled[name] = "interpreted"
            return build({})
        graph = ca.Function(name, inputs or [self.eq.tau, self.eq.x, self.eq.p], [expression])
        fun, how = compile_cache.compiled(name, graph.serialize() + options_repr, build)
        self.compiled[name] = how
        return fun

    def parameters(self) -> dict[str, float]:
        """Default parameters: the network's and each joint's (``<joint>.capacity_N`` ...)."""
        p = self.network.parameters()
        for j in self.joints:
            p.update(j.parameters())
        return p

    def parameter_vector(self, speed_rpm: float, parameters: dict | None = None) -> np.ndarray:
        check_range("speed_rpm", speed_rpm, self.min_speed_rpm, None, unit="rpm")
        parameters = dict(parameters or {})
        net_names = set(self.network.parameters())
        net_over = {k: v for k, v in parameters.items() if k in net_names}
        joint_p = {}
        for j in self.joints:
            joint_p.update(j.parameters())
        unknown = set(parameters) - net_names - set(joint_p)
        if unknown:
            raise GearoptInputError(f"unknown parameters {sorted(unknown)}; joint parameters: {sorted(joint_p)}")
        for k, v in parameters.items():
            if k in joint_p:
                joint_p[k] = float(v)
        for k, v in joint_p.items():
            if k.endswith(".capacity_N"):
                check_range(k, v, 0.0, None, low_inclusive=False, unit="N")
            elif k.endswith(".slip_speed_m_s"):
                check_range(k, v, 0.0, None, low_inclusive=False, unit="m/s")
            elif k.endswith(".thrust_scale"):
                check_range(k, v)                      # negative: the shoulder on the other side of the gear
            else:
                check_range(k, v, 0.0, None)
        return np.concatenate([self.network.parameter_vector(speed_rpm, net_over),
                               np.array([joint_p[f"{j.name}.{k}"] for j in self.joints for k in JOINT_PARAMETERS])])

    def _axial_preload(self, x: np.ndarray, pvec: np.ndarray) -> np.ndarray:
        """Start each gear at rest in axial equilibrium under the initial thrust F (z = 0): u_a = F/k_c off the
        nose, or F/(k_c + k_sh) against the shoulder (interface and shoulder in parallel)."""
        out = np.array(self._point_outputs(0.0, x, pvec)).ravel()
        names = self.eq.output_names
        x = x.copy()
        for i, j in enumerate(self.joints):
            if self.eq.thrust_free[i]:
                continue
            f = out[names.index(("thrust_N", j.name))]
            if f >= 0.0:  # the interface holds at most its capacity
                f = min(f, pvec[self.eq.parameter_names.index(f"{j.name}.capacity_N")])
            k = j.interface_stiffness_N_per_m + (j.shoulder_stiffness_N_per_m if f < 0.0 else 0.0)
            x[self.eq.n_network + self.eq.state_offsets[i] + 2] = f / k / SLIP_UNIT_M
        return x

    def run(self, speed_rpm: float, cycles: int = 2, *, parameters: dict | None = None, run_in_cycles: int = 1,
            x0=None) -> JointSimulation:
        """Integrate ``run_in_cycles`` + ``cycles`` engine cycles at ``speed_rpm`` from the network's static state
        (``x0`` to continue a run; slip states start at 0: gear centred in the key clearance, against the
        shoulder, at rest in axial equilibrium under the initial thrust) and summarise the recorded cycles. Raises :class:`JointIntegrationError` if CVODES cannot hold
        its tolerance within its step budget."""
        check_range("cycles", cycles, 1, None)
        check_range("run_in_cycles", run_in_cycles, 0, None)
        pvec = self.parameter_vector(speed_rpm, parameters)
        n_net = self.eq.n_network
        if x0 is None:
            net_p = {k: v for k, v in (parameters or {}).items() if k in self.network.parameters()}
            x = np.concatenate([self.base.static_state(speed_rpm, net_p),
                                np.zeros(self.eq.x.numel() - n_net)])
            x = self._axial_preload(x, pvec)
        else:
            x = np.asarray(x0, dtype=float).reshape(-1)
            if x.size != self.eq.x.numel():
                raise GearoptInputError(f"x0 has {x.size} entries, the joint network has {self.eq.x.numel()} states")
        i_off = self.eq.parameter_names.index(OFFSET_PARAMETER)
        t0 = time.perf_counter()
        integrate = self._cycle_function()
        outputs = BufferedFunction(self.output_function, [0, 1, 2], [0])
        recorded, starts = [], []
        for c in range(run_in_cycles + cycles):
            p = pvec.copy()
            p[i_off] = c * self.cycle_rad
            if c >= run_in_cycles:
                starts.append(x.copy())
            try:
                xs = integrate(x, p)
            except RuntimeError as exc:
                raise JointIntegrationError(
                    f"friction-joint integration at {speed_rpm:g} rpm failed in cycle {c + 1}: CVODES could not "
                    f"hold rtol {self.options['reltol']:g} within {self.options['max_num_steps']} steps through the "
                    f"stick-slip transitions", status=str(exc).splitlines()[0][:300],
                    hint="lower the slip regularisation speed slip_speed_m_s (a less stiff slip law) "
                         "or raise max_num_steps") from exc
            if not np.all(np.isfinite(xs)):
                raise JointIntegrationError(f"friction-joint integration at {speed_rpm:g} rpm diverged in cycle "
                                            f"{c + 1} (non-finite state)", status="non-finite")
            if c >= run_in_cycles:
                recorded.append((xs, p))
            x = xs[:, -1].copy()
        outs = np.concatenate([outputs(self.grid_rad, xs, np.tile(p, self.n_out))[0] for xs, p in recorded], axis=1)
        angle = np.concatenate([c * self.cycle_rad + self.grid_rad for c in range(cycles)])
        index = pd.Index(np.degrees(angle), name="crank_angle_deg")
        groups: dict = {q: ([], []) for q in JOINT_OUTPUTS}
        for i, (q, name) in enumerate(self.eq.output_names):
            groups[q][0].append(i)
            groups[q][1].append(name)
        frames = {q: pd.DataFrame(outs[rows].T, index=index, columns=cols) if rows else pd.DataFrame({}, index=index)
                  for q, (rows, cols) in groups.items()}
        rows = []
        for i, j in enumerate(self.joints):
            k = n_net + self.eq.state_offsets[i]
            um = SLIP_UNIT_M * 1e6
            ut = np.concatenate([[starts[0][k] * um], frames["slip_um"][j.name].to_numpy()])
            # creep = change of the plastic axial slip z (the gear's elastic deflection on the interface recovers);
            # a thrust-free joint has none
            axial = (lambda state, q: 0.0) if self.eq.thrust_free[i] else (lambda state, q: state[k + q] * um)
            ua_start, ua_end = axial(starts[0], 1), axial(x, 1)
            ua = np.array([axial(st, 1) for st in starts] + [ua_end])
            per_cycle = np.diff(ua)
            rows.append({"joint": j.name,
                         "max_rigid_utilisation": float(frames["rigid_utilisation"][j.name].max()),
                         "max_utilisation": float(frames["utilisation"][j.name].max()),
                         "slip_um_per_cycle": float(np.sum(np.abs(np.diff(ut)))) / cycles,
                         "axial_creep_um_per_cycle": float(ua_end - ua_start) / cycles,
                         "axial_creep_um_cycle_std": float(np.std(per_cycle, ddof=1)) if cycles > 1 else 0.0,
                         "max_cycle_axial_creep_um": float(per_cycle.max()),
                         "axial_position_um": float(axial(x, 2)),
                         "max_key_force_N": float(frames["key_force_N"][j.name].abs().max()),
                         "max_off_nose_thrust_N": float(frames["thrust_N"][j.name].max())})
        stats = {"integration_time_s": time.perf_counter() - t0, "build_time_s": self.build_time_s,
                 "fallback_chunks": getattr(integrate, "counts", {}).get("fallback_chunks", 0),
                 "substep_steps": getattr(integrate, "counts", {}).get("substep_steps", 0),
                 "cycles_integrated": run_in_cycles + cycles}
        return JointSimulation(speed_rpm=float(speed_rpm), cycles=int(cycles), run_in_cycles=int(run_in_cycles),
                               crank_angle_deg=np.degrees(angle), frames=frames,
                               summary=pd.DataFrame(rows).set_index("joint"), final_state=x, stats=stats)

    def _cycle_function(self):
        """``(x, p) -> states over the output grid`` of one cycle (network and slip states, columns at
        ``grid_rad``), in the chosen ``integration``; raises ``RuntimeError`` as the integrator does."""
        if self.integration == "simultaneous":
            integrate = BufferedFunction(self.integrator, ["x0", "p"], ["xf"])  # no DM conversions (buffered_call)
            return lambda x, p: integrate(x, p)[0]
        n_net, n_p_net = self.eq.n_network, self.network.equations(lash=self.lash).p.numel()
        network = BufferedFunction(self.base.integrator, ["x0", "p"], ["xf"])
        forcing = BufferedFunction(self.forcing_function, [0, 1, 2], [0])
        calls, counts = {}, {"fallback_chunks": 0, "substep_steps": 0}

        def integrator(g):          # CVODES over one chunk of gear g (built on first use for a fixed-step gear)
            if g not in calls:
                if self.integrators[g] is None:
                    self.integrators[g] = self._cvodes[g]()
                calls[g] = BufferedFunction(self.integrators[g], ["x0", "p"], ["xf"])
            return calls[g]
        fixed = {g: BufferedFunction(f, ["start", "forcing_table", "p", "h"], ["trajectory", "residuals", "substeps"])
                 for g, f in enumerate(self.fixed_steps) if f is not None}
        grid, stride = self.base.grid_rad, self.forcing_stride
        per_chunk = self.n_out // self.chunks * stride
        out_chunk = self.n_out // self.chunks
        sub = BDF2_STEPS_PER_FORCING_STEP
        h = np.array([grid[0] / sub])
        at = (np.arange(1, per_chunk * sub + 1) / sub)             # fixed steps' times in forcing steps
        lower = np.minimum(np.floor(at).astype(int), per_chunk - 1)
        weight = at - lower

        def cycle(x, p):
            p_net = p[:n_p_net]
            xs_net = network(x[:n_net], p_net)[0]
            start = np.array(self._forcing_point(0.0, x[:n_net], p_net)).ravel()
            table = np.column_stack([start, forcing(grid, xs_net, np.tile(p_net, grid.size))[0]])
            us = np.empty((x.size - n_net, self.n_out))
            for g, rows in enumerate(self.gear_rows):
                u = x[n_net + rows]
                history = np.concatenate([u, u, [0.0], table[2 * g:2 * g + 2, 0]])     # backward Euler first
                for c in range(self.chunks):
                    chunk = table[2 * g:2 * g + 2, c * per_chunk:(c + 1) * per_chunk + 1]
                    part = None
                    if g in fixed:
                        new = chunk[:, lower] * (1.0 - weight) + chunk[:, lower + 1] * weight
                        trajectory, residuals, substeps = fixed[g](history, new, p, h)
                        if self._fixed_steps_resolved(residuals):
                            counts["substep_steps"] += int(substeps.sum())
                            part = trajectory[:rows.size, stride * sub - 1::stride * sub]
                            history = trajectory[:, -1]
                        else:
                            counts["fallback_chunks"] += 1
                    if part is None:
                        part = integrator(g)(u, np.concatenate([p, chunk.ravel(order="F")]))[0]
                        history = np.concatenate([part[:, -1], part[:, -1], [0.0], chunk[:, -1]])
                    us[rows, c * out_chunk:(c + 1) * out_chunk] = part
                    u = part[:, -1]
            return np.vstack([xs_net[:, stride - 1::stride], us])
        cycle.counts = counts
        return cycle


def joint_simulator(network: TorsionalNetwork, joints, **options) -> JointSimulator:
    """The network's cached :class:`JointSimulator` for these joints and options (built on first use)."""
    key = ("joint_simulator", tuple(joints)) + tuple(sorted((k, repr(v)) for k, v in options.items()))
    if key not in network._cache:
        network._cache[key] = JointSimulator(network, joints, **options)
    return network._cache[key]


def walked_distance_mm(creep_um_per_cycle, speed_rpm, hours, cycle_deg: float = 720.0):
    """Distance a gear walks [mm] at a constant creep per engine cycle [um] after ``hours`` at ``speed_rpm``:
    ``creep x cycles``, cycles = speed x 60 x hours x 360 / cycle_deg (720 for a four-stroke)."""
    hours, speed = np.asarray(hours, dtype=float), np.asarray(speed_rpm, dtype=float)
    for name, v, unit in (("hours", hours, "h"), ("speed_rpm", speed, "rpm")):
        if v.size and not (np.all(np.isfinite(v)) and v.min() >= 0.0):
            raise GearoptInputError(f"{name}={v.min() if v.size else v!r} {unit}: must be finite and >= 0")
    cycles = speed * 60.0 * hours * 360.0 / cycle_deg
    return np.asarray(creep_um_per_cycle, dtype=float) * cycles * 1e-3


__all__ = [
    "INTEGRATIONS",
    "JOINT_OUTPUTS",
    "JOINT_PARAMETERS",
    "SLIP_UNIT_M",
    "STATES_PER_JOINT",
    "THRUST_FREE_STATES",
    "FrictionJoint",
    "JointIntegrationError",
    "JointSimulation",
    "JointSimulator",
    "joint_equations",
    "joint_rates",
    "joint_simulator",
    "key_force_N",
    "shoulder_force_N",
    "slip_rates_m_s",
    "walked_distance_mm",
]
