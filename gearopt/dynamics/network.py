"""Torsional network builder: named inertias, shafts, viscous dampers, gear meshes, external torques, speed boundary.

Coordinates. Every node rotates nominally at ``r_i Omega`` where ``Omega`` [rad/s] is the speed of the reference
node (the speed boundary, else the first inertia) and ``r_i`` its signed speed ratio (shafts keep the ratio, an
external mesh multiplies it by ``-r_b1/r_b2``). The states are the *deviations* from that rigid rotation, angle
``phi_i`` [rad] and speed ``phi_i_dot`` [rad/s], in one common sign convention (positive = the reference node's
sense). Deviation coordinates keep the vibratory angles (1e-6..1e-2 rad) free of the growing nominal angle, so the
integrator's tolerances apply to what matters. The independent variable of the equations is the nominal angle of
the reference node ``tau = Omega t`` [rad] (crank angle for an engine), so one integrator with one output grid in
crank angle serves every speed.

Elements (SI units inside):

* inertia ``J`` [kg m^2], optionally damped against the nominally rotating frame (absolute damping of the
  vibratory speed, as the frequency-domain source of the default crank model uses it);
* shaft between two nodes: ``T = k (phi_a - phi_b) + c (phi_a_dot - phi_b_dot)`` [N m] (a viscous damper is a shaft
  with ``k = 0``, e.g. the ring of an untuned viscous crank damper);
* gear mesh (external spur/helical): force along the transverse line of action from
  ``delta = s1 (r_b1 phi_1 + r_b2 phi_2)``, see :mod:`gearopt.dynamics.mesh`; it acts on gear i with the torque
  ``-F s1 r_bi``;
* external torque on a node: a callable ``f(t_s, angle_rad, speed_rad_s, **parameters)`` (plus ``accel_rad_s2``
  when declared acceleration-dependent, and ``nominal_angle_rad`` -- the node's angle along the nominal motion --
  if the callable accepts that keyword) with the node's *own* angle and speed, i.e. measured positive in the node's
  nominal sense of rotation (zero at ``t = 0``), returning a torque [N m] positive when it drives the node in that
  sense (a load torque is negative). Acceleration-dependent torques must be affine in the acceleration (the
  reciprocating-mass torque ``-m s'^2 theta_ddot - ...``); the network moves the linear part to the mass side;
* speed boundary: a node whose motion is prescribed (constant speed ``r_b Omega``: a speed-controlled flywheel or
  dynamometer, thesis sec. 3.6). Its reaction torque is an output.

Every numeric property that an analysis may want to vary is a named *parameter* of the equations (mesh stiffness,
damping, backlash, stiffness-variation amplitude; shaft stiffness and damping; external-torque parameters), so an
integrator is built once per network structure and re-used for any parameter values.
"""

from __future__ import annotations

import inspect
import math
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError
from ..geometry.forces import axial_force_N, mesh_torque_Nm
from ..validation import check_int, check_range
from .mesh import (
    DEFAULT_CONTACT_WIDTH_M,
    DEFAULT_DAMPING_WIDTH_M,
    MeshStiffnessShape,
    mesh_force,
)

#: State unit of the angle deviations [rad] (states are in mrad so angles and speeds have similar magnitudes).
ANGLE_UNIT_RAD = 1e-3
SPEED_PARAMETER = "speed_rad_s"
#: Mesh deflections are clipped to this magnitude [m] (never reached by a physical solution; see _build_equations).
DEFLECTION_LIMIT_M = 0.01
OFFSET_PARAMETER = "angle_offset_rad"


@dataclass(frozen=True)
class Inertia:
    """A rigid inertia [kg m^2]; ``damping_to_frame_Nms_per_rad`` damps its vibratory speed (absolute damping)."""

    name: str
    inertia_kgm2: float
    damping_to_frame_Nms_per_rad: float = 0.0


@dataclass(frozen=True)
class Shaft:
    """Torsional spring [N m/rad] and parallel viscous damper [N m s/rad] between two nodes."""

    name: str
    node_a: str
    node_b: str
    stiffness_Nm_per_rad: float
    damping_Nms_per_rad: float = 0.0


@dataclass(frozen=True)
class Mesh:
    """External gear mesh: gear 1 drives gear 2. Base radii [mm] (transverse), teeth, mean mesh stiffness along the
    transverse line of action [N/m], viscous damping [N s/m], backlash along the line of action [mm], stiffness
    shape over the mesh angle and its amplitude, base helix angle [deg] (axial force), phase of the mesh angle at
    t = 0 [rad], width of the smooth dead zone [um], width over which the dashpot engages [um]."""

    name: str
    gear_1: str
    gear_2: str
    base_radii_mm: tuple
    teeth: tuple
    stiffness_N_per_m: float
    damping_N_s_per_m: float = 0.0
    backlash_mm: float = 0.0
    stiffness_shape: object = field(default_factory=MeshStiffnessShape.constant)
    stiffness_variation: float = 1.0
    base_helix_angle_deg: float = 0.0
    phase_rad: float = 0.0
    contact_width_um: float = DEFAULT_CONTACT_WIDTH_M * 1e6
    damping_width_um: float = DEFAULT_DAMPING_WIDTH_M * 1e6


@dataclass(frozen=True)
class ExternalTorque:
    """External torque on a node (see the module docstring for the callable's signature and sign convention)."""

    name: str
    node: str
    function: Callable
    parameters: tuple = ()
    acceleration_dependent: bool = False
    description: str = ""
    parameter_prefix: str = ""

    def parameter_name(self, key: str) -> str:
        return f"{self.parameter_prefix or self.name}.{key}"


@dataclass
class NetworkEquations:
    """Symbolic equations of a network (CasADi SX), built by :meth:`TorsionalNetwork.equations`.

    ``tau`` nominal reference angle [rad]; ``x`` states (angle deviations [mrad] of the free nodes, then their speed
    deviations [rad/s]); ``p`` parameters (``parameter_names``); ``rhs`` = dx/dtau; ``quad`` = quadrature integrands
    (d/dtau, names ``quad_names``); ``outputs`` with ``output_names``; ``free_nodes`` order of the states.
    """

    tau: ca.SX
    x: ca.SX
    p: ca.SX
    rhs: ca.SX
    quad: ca.SX
    outputs: ca.SX
    parameter_names: list
    quad_names: list
    output_names: list
    free_nodes: list
    lash: bool
    nominal_torques: ca.Function  # (tau, p) -> external torques on the free nodes at the nominal motion [N m]
    effective_inertias: ca.Function  # (tau, x, p) -> J_eff of the free nodes [kg m^2]


def _check_stiffness_variation(name: str, shape, variation) -> None:
    """``stiffness_variation`` >= 0 keeping the mesh stiffness 1 + a v(psi) positive over the whole mesh cycle
    (a negative stiffness has no physical meaning and makes the integration diverge)."""
    check_range(f"stiffness_variation of {name!r}", variation, 0.0, None)
    if isinstance(shape, MeshStiffnessShape) and shape.harmonics:
        low = float(np.min(shape.variation(np.linspace(0.0, 2.0 * np.pi, 1024, endpoint=False))))
        if low < 0.0 and float(variation) * -low >= 1.0:
            raise GearoptInputError(f"stiffness_variation of {name!r}={float(variation):g} makes the mesh stiffness "
                                    f"negative: must be < {1.0 / -low:.4g} for this stiffness shape (its minimum "
                                    f"variation is {low:.4g})")


class TorsionalNetwork:
    """Builder of a torsional network (lumped inertias, shafts, dampers, gear meshes, external torques).

    ``cycle_deg``: period of the excitation in reference-node degrees (720 for a four-stroke engine); simulations
    run in whole cycles. See the module docstring for coordinates, sign conventions and units.
    """

    def __init__(self, name: str = "", cycle_deg: float = 360.0):
        check_range("cycle_deg", cycle_deg, 0.0, None, low_inclusive=False, unit="deg")
        self.name = name
        self.cycle_deg = float(cycle_deg)
        self.inertias: dict[str, Inertia] = {}
        self.shafts: dict[str, Shaft] = {}
        self.meshes: dict[str, Mesh] = {}
        self.torques: dict[str, ExternalTorque] = {}
        self.boundary_nodes: list[str] = []
        self._cache: dict = {}

    # ------------------------------------------------------------------------------------------------------------
    # building
    # ------------------------------------------------------------------------------------------------------------

    def _changed(self) -> None:
        self._cache.clear()

    def _check_new_name(self, name: str, table: dict, kind: str) -> None:
        if not isinstance(name, str) or not name:
            raise GearoptInputError(f"{kind} name={name!r} must be a non-empty string")
        if name in table:
            raise GearoptInputError(f"{kind} {name!r} already exists in the network")

    def _check_node(self, node: str, what: str) -> None:
        if node not in self.inertias:
            raise GearoptInputError(f"{what}={node!r} is not an inertia of the network {list(self.inertias)}")

    def add_inertia(self, name: str, inertia_kgm2: float, damping_to_frame_Nms_per_rad: float = 0.0):
        """Add a node of polar inertia ``inertia_kgm2`` [kg m^2] (> 0). ``damping_to_frame_Nms_per_rad`` >= 0 damps
        its vibratory speed against the nominally rotating frame. Returns the network (chainable)."""
        self._check_new_name(name, self.inertias, "inertia")
        check_range(f"inertia_kgm2 of {name!r}", inertia_kgm2, 0.0, None, low_inclusive=False, unit="kg m^2")
        check_range(f"damping_to_frame_Nms_per_rad of {name!r}", damping_to_frame_Nms_per_rad, 0.0, None,
                    unit="N m s/rad")
        self.inertias[name] = Inertia(name, float(inertia_kgm2), float(damping_to_frame_Nms_per_rad))
        self._changed()
        return self

    def add_shaft(self, node_a: str, node_b: str, stiffness_Nm_per_rad: float, damping_Nms_per_rad: float = 0.0,
                  name: str | None = None):
        """Connect two nodes by a torsional spring ``stiffness_Nm_per_rad`` [N m/rad] >= 0 and a parallel viscous
        damper ``damping_Nms_per_rad`` [N m s/rad] >= 0 (not both zero). Default name ``"a-b"``."""
        name = name or f"{node_a}-{node_b}"
        self._check_new_name(name, self.shafts, "shaft")
        self._check_node(node_a, "node_a")
        self._check_node(node_b, "node_b")
        if node_a == node_b:
            raise GearoptInputError(f"shaft {name!r} connects node {node_a!r} with itself")
        check_range(f"stiffness_Nm_per_rad of {name!r}", stiffness_Nm_per_rad, 0.0, None, unit="N m/rad")
        check_range(f"damping_Nms_per_rad of {name!r}", damping_Nms_per_rad, 0.0, None, unit="N m s/rad")
        if float(stiffness_Nm_per_rad) == 0.0 and float(damping_Nms_per_rad) == 0.0:
            raise GearoptInputError(f"shaft {name!r} has zero stiffness and zero damping")
        self.shafts[name] = Shaft(name, node_a, node_b, float(stiffness_Nm_per_rad), float(damping_Nms_per_rad))
        self._changed()
        return self

    def add_damper(self, node_a: str, node_b: str, damping_Nms_per_rad: float, name: str | None = None):
        """A pure viscous coupling [N m s/rad] between two nodes (e.g. damper ring and housing): a shaft with k = 0."""
        check_range("damping_Nms_per_rad", damping_Nms_per_rad, 0.0, None, low_inclusive=False, unit="N m s/rad")
        return self.add_shaft(node_a, node_b, 0.0, damping_Nms_per_rad, name=name)

    def add_mesh(self, gear_1: str, gear_2: str, *, base_radii_mm, teeth, stiffness_N_per_m: float,
                 damping_N_s_per_m: float = 0.0, backlash_mm: float = 0.0, stiffness_shape=None,
                 stiffness_variation: float = 1.0, base_helix_angle_deg: float = 0.0, phase_deg: float = 0.0,
                 contact_width_um: float = DEFAULT_CONTACT_WIDTH_M * 1e6,
                 damping_width_um: float = DEFAULT_DAMPING_WIDTH_M * 1e6, name: str | None = None):
        """Add an external gear mesh; gear 1 drives gear 2 (its drive flanks are loaded when delta > 0).

        ``base_radii_mm`` (r_b1, r_b2) transverse base radii [mm]; ``teeth`` (z1, z2) (their ratio must equal the
        base-radius ratio to 1e-6); ``stiffness_N_per_m`` mean mesh stiffness k_mean along the transverse line of
        action [N/m] (> 0); ``damping_N_s_per_m`` c [N s/m]; ``backlash_mm`` j along the line of action [mm]
        (transverse base-circle backlash, ``j_bt = j_wt cos(alpha_wt)``); ``stiffness_shape`` a
        :class:`~gearopt.dynamics.mesh.MeshStiffnessShape` (default constant) or a dual-typed callable
        ``psi_rad -> k(psi)/k_mean`` (2 pi-periodic, mean 1: e.g. the LTCA's stiffness); ``stiffness_variation`` its
        amplitude (MeshStiffnessShape only); ``base_helix_angle_deg`` beta_b for the axial force; ``phase_deg`` mesh
        angle at t = 0; ``contact_width_um`` width of the smooth dead zone and ``damping_width_um`` the width over
        which the dashpot engages (lash model; :func:`~gearopt.dynamics.mesh.mesh_force`).
        """
        name = name or f"{gear_1}-{gear_2}"
        self._check_new_name(name, self.meshes, "mesh")
        self._check_node(gear_1, "gear_1")
        self._check_node(gear_2, "gear_2")
        if gear_1 == gear_2:
            raise GearoptInputError(f"mesh {name!r} meshes gear {gear_1!r} with itself")
        if not isinstance(base_radii_mm, (tuple, list)) or not isinstance(teeth, (tuple, list)) \
                or len(base_radii_mm) != 2 or len(teeth) != 2:
            raise GearoptInputError(f"mesh {name!r}: base_radii_mm={base_radii_mm!r} and teeth={teeth!r} must be "
                                    f"2-tuples (gear 1, gear 2)")
        for i in range(2):
            check_range(f"base_radii_mm[{i}] of {name!r}", base_radii_mm[i], 0.0, 1e5, low_inclusive=False,
                        unit="mm")
        radii = tuple(float(r) for r in base_radii_mm)
        teeth = tuple(check_int(f"teeth[{i}] of {name!r}", z, 1, 100000) for i, z in enumerate(teeth))
        if abs(radii[0] / radii[1] * teeth[1] / teeth[0] - 1.0) > 1e-6:
            raise GearoptInputError(f"mesh {name!r}: base radius ratio {radii[0] / radii[1]:.8f} differs from the "
                                    f"tooth ratio {teeth[0] / teeth[1]:.8f} (limit 1e-6 relative)")
        check_range(f"stiffness_N_per_m of {name!r}", stiffness_N_per_m, 0.0, None, low_inclusive=False, unit="N/m")
        check_range(f"damping_N_s_per_m of {name!r}", damping_N_s_per_m, 0.0, None, unit="N s/m")
        check_range(f"backlash_mm of {name!r}", backlash_mm, 0.0, None, unit="mm")
        check_range(f"contact_width_um of {name!r}", contact_width_um, 0.0, None, low_inclusive=False, unit="um")
        check_range(f"damping_width_um of {name!r}", damping_width_um, 0.0, None, low_inclusive=False, unit="um")
        check_range(f"base_helix_angle_deg of {name!r}", base_helix_angle_deg, 0.0, 45.0, high_inclusive=False,
                    unit="deg")
        shape = MeshStiffnessShape.constant() if stiffness_shape is None else stiffness_shape
        _check_stiffness_variation(name, shape, stiffness_variation)
        if not isinstance(shape, MeshStiffnessShape):
            if not callable(shape):
                raise GearoptInputError(f"stiffness_shape of {name!r} must be a MeshStiffnessShape or a callable")
            psi = np.linspace(0.0, 2.0 * np.pi, 720, endpoint=False)
            values = np.asarray([nm.to_float(shape(v)) for v in psi])
            if not np.all(np.isfinite(values)) or np.any(values <= 0.0) or abs(values.mean() - 1.0) > 1e-3:
                raise GearoptInputError(f"stiffness_shape callable of {name!r} must be positive with mean 1 over "
                                        f"[0, 2 pi) (got mean {values.mean():.6g}, min {values.min():.6g})")
        self.meshes[name] = Mesh(name, gear_1, gear_2, radii, teeth, float(stiffness_N_per_m),
                                 float(damping_N_s_per_m), float(backlash_mm), shape, float(stiffness_variation),
                                 float(base_helix_angle_deg), math.radians(phase_deg), float(contact_width_um),
                                 float(damping_width_um))
        self._changed()
        return self

    def add_torque(self, node: str, function: Callable, *, name: str | None = None, parameters: dict | None = None,
                   acceleration_dependent: bool = False, description: str = "", parameter_prefix: str | None = None):
        """Apply an external torque to ``node``: ``function(t_s, angle_rad, speed_rad_s, **parameters)`` [N m]
        (plus ``accel_rad_s2=`` if ``acceleration_dependent``) in the node's own sense of rotation (module
        docstring). ``parameters`` name -> default value become parameters of the equations (named
        ``"<parameter_prefix>.<parameter>"``, prefix default the torque's name; torques with the same prefix share
        their equally named parameters, whose defaults must agree), so they can change without rebuilding the
        integrator. The function receives CasADi SX symbols and must be built from :mod:`gearopt.numerics`
        operations."""
        name = name or f"torque@{node}"
        self._check_new_name(name, self.torques, "torque")
        self._check_node(node, "node")
        if not callable(function):
            raise GearoptInputError(f"torque {name!r}: function must be callable")
        params = tuple((str(k), float(v)) for k, v in (parameters or {}).items())
        sig = inspect.signature(function)
        accepts_kwargs = any(p.kind == p.VAR_KEYWORD for p in sig.parameters.values())
        needed = [k for k, _ in params] + (["accel_rad_s2"] if acceleration_dependent else [])
        missing = [k for k in needed if k not in sig.parameters and not accepts_kwargs]
        if missing:
            raise GearoptInputError(f"torque {name!r}: function does not accept the keyword(s) {missing}")
        torque = ExternalTorque(name, node, function, params, bool(acceleration_dependent), description,
                                parameter_prefix or "")
        existing = self.parameters()
        for k, v in params:
            full = torque.parameter_name(k)
            if full in existing and existing[full] != v:
                raise GearoptInputError(f"torque {name!r}: shared parameter {full!r} has default {existing[full]!r} "
                                        f"elsewhere, not {v!r}")
        self.torques[name] = torque
        self._changed()
        return self

    def set_speed_boundary(self, node: str):
        """Prescribe the motion of ``node``: it rotates at constant nominal speed (speed-controlled flywheel or
        dynamometer). The first boundary node is the reference node (speed ratio +1)."""
        self._check_node(node, "node")
        if node not in self.boundary_nodes:
            self.boundary_nodes.append(node)
        self._changed()
        return self

    # ------------------------------------------------------------------------------------------------------------
    # structure
    # ------------------------------------------------------------------------------------------------------------

    @property
    def reference_node(self) -> str:
        if not self.inertias:
            raise GearoptInputError("the network has no inertias")
        return self.boundary_nodes[0] if self.boundary_nodes else next(iter(self.inertias))

    @property
    def free_nodes(self) -> list[str]:
        return [n for n in self.inertias if n not in self.boundary_nodes]

    def speed_ratios(self) -> dict[str, float]:
        """Signed nominal speed of every node relative to the reference node (shafts keep it, an external mesh
        multiplies it by -r_b1/r_b2). Raises if the network is disconnected or a loop is kinematically
        inconsistent."""
        if "speed_ratios" in self._cache:
            return dict(self._cache["speed_ratios"])
        edges: dict[str, list] = {n: [] for n in self.inertias}
        for s in self.shafts.values():
            edges[s.node_a].append((s.node_b, 1.0))
            edges[s.node_b].append((s.node_a, 1.0))
        for m in self.meshes.values():
            r1, r2 = m.base_radii_mm
            edges[m.gear_1].append((m.gear_2, -r1 / r2))
            edges[m.gear_2].append((m.gear_1, -r2 / r1))
        ref = self.reference_node
        ratios, queue = {ref: 1.0}, deque([ref])
        while queue:
            a = queue.popleft()
            for b, factor in edges[a]:
                r = ratios[a] * factor
                if b not in ratios:
                    ratios[b] = r
                    queue.append(b)
                elif abs(ratios[b] - r) > 1e-9 * max(abs(r), 1.0):
                    raise GearoptInputError(f"kinematically inconsistent loop at node {b!r}: speed ratio "
                                            f"{ratios[b]:.9g} vs {r:.9g}")
        missing = [n for n in self.inertias if n not in ratios]
        if missing:
            raise GearoptInputError(f"nodes {missing} are not connected to the reference node {ref!r}")
        self._cache["speed_ratios"] = dict(ratios)
        return ratios

    def parameters(self) -> dict[str, float]:
        """Names and default values of the equations' parameters (units in the names; ``speed_rad_s`` is the
        reference node's nominal speed, ``angle_offset_rad`` the reference angle at the start of the integration)."""
        p = {SPEED_PARAMETER: 0.0, OFFSET_PARAMETER: 0.0}
        for m in self.meshes.values():
            p[f"{m.name}.stiffness_N_per_m"] = m.stiffness_N_per_m
            p[f"{m.name}.damping_N_s_per_m"] = m.damping_N_s_per_m
            p[f"{m.name}.backlash_mm"] = m.backlash_mm
            p[f"{m.name}.stiffness_variation"] = m.stiffness_variation
        for s in self.shafts.values():
            p[f"{s.name}.stiffness_Nm_per_rad"] = s.stiffness_Nm_per_rad
            p[f"{s.name}.damping_Nms_per_rad"] = s.damping_Nms_per_rad
        for t in self.torques.values():
            for k, v in t.parameters:
                p[t.parameter_name(k)] = v
        return p

    def parameter_vector(self, speed_rpm: float, overrides: dict | None = None) -> np.ndarray:
        """Numeric parameter vector in the order of :meth:`parameters` at ``speed_rpm`` [rpm] with ``overrides``."""
        check_range("speed_rpm", speed_rpm, 0.0, None, low_inclusive=False, unit="rpm")
        p = self.parameters()
        for k, v in (overrides or {}).items():
            if k not in p:
                raise GearoptInputError(f"unknown parameter {k!r}; known: {list(p)}")
            p[k] = float(v)
        p[SPEED_PARAMETER] = float(speed_rpm) * math.pi / 30.0
        return np.array(list(p.values()), dtype=float)

    # ------------------------------------------------------------------------------------------------------------
    # linear analysis (delegates to modes.py)
    # ------------------------------------------------------------------------------------------------------------

    def linear_matrices(self, boundary: str = "network", parameters: dict | None = None,
                        speed_rpm: float | None = None) -> dict:
        """Mass, stiffness and damping matrices of the linearised network (see
        :func:`gearopt.dynamics.modes.linear_matrices`)."""
        from .modes import linear_matrices
        return linear_matrices(self, boundary=boundary, parameters=parameters, speed_rpm=speed_rpm)

    def natural_frequencies_Hz(self, boundary: str = "network", parameters: dict | None = None) -> np.ndarray:
        """Undamped natural frequencies [Hz], ascending (mean mesh stiffness, no lash). ``boundary="network"``:
        speed-boundary nodes held; ``"free"``: free-free (first frequency ~0, the rigid-body mode)."""
        from .modes import natural_frequencies_Hz
        return natural_frequencies_Hz(self, boundary=boundary, parameters=parameters)

    # ------------------------------------------------------------------------------------------------------------
    # equations
    # ------------------------------------------------------------------------------------------------------------

    def equations(self, lash: bool = True) -> NetworkEquations:
        """Symbolic equations of motion (cached per structure): see :class:`NetworkEquations`.

        ``lash=True``: meshes with the smooth dead zone (backlash parameters active; backlash 0 reproduces the
        linear mesh exactly); ``lash=False``: linear meshes (both flanks always in contact).
        """
        key = ("equations", bool(lash))
        if key not in self._cache:
            self._cache[key] = _build_equations(self, bool(lash))
        return self._cache[key]


# ----------------------------------------------------------------------------------------------------------------
# equation assembly
# ----------------------------------------------------------------------------------------------------------------

def _accepts(function, keyword: str) -> bool:
    params = inspect.signature(function).parameters
    return keyword in params


def _sign(v: float) -> float:
    return 1.0 if v >= 0.0 else -1.0


def _build_equations(net: TorsionalNetwork, lash: bool) -> NetworkEquations:
    ratios = net.speed_ratios()
    free = net.free_nodes
    if not free:
        raise GearoptInputError("the network has no free inertia (every node is a speed boundary)")
    index = {n: i for i, n in enumerate(free)}
    n = len(free)
    names = list(net.parameters())
    tau = ca.SX.sym("tau")
    x = ca.SX.sym("x", 2 * n)
    p = ca.SX.sym("p", len(names))
    par = {k: p[i] for i, k in enumerate(names)}
    omega = par[SPEED_PARAMETER]
    tau_abs = tau + par[OFFSET_PARAMETER]
    t_s = tau_abs / omega

    def angle(node):  # deviation [rad]
        return x[index[node]] * ANGLE_UNIT_RAD if node in index else 0.0

    def rate(node):  # deviation speed [rad/s]
        return x[n + index[node]] if node in index else 0.0

    torque = {node: 0.0 for node in net.inertias}  # absolute sign convention
    outputs, out_names, quad, quad_names = [], [], [], []

    for node, inertia in net.inertias.items():
        if inertia.damping_to_frame_Nms_per_rad:
            torque[node] = torque[node] - inertia.damping_to_frame_Nms_per_rad * rate(node)

    for s in net.shafts.values():
        k, c = par[f"{s.name}.stiffness_Nm_per_rad"], par[f"{s.name}.damping_Nms_per_rad"]
        t = k * (angle(s.node_a) - angle(s.node_b)) + c * (rate(s.node_a) - rate(s.node_b))
        torque[s.node_a] = torque[s.node_a] - t
        torque[s.node_b] = torque[s.node_b] + t
        outputs.append(_sign(ratios[s.node_a]) * t)
        out_names.append(("shaft_torque_Nm", s.name))

    for m in net.meshes.values():
        s1 = _sign(ratios[m.gear_1])
        r1, r2 = (r * 1e-3 for r in m.base_radii_mm)
        delta = s1 * (r1 * angle(m.gear_1) + r2 * angle(m.gear_2))
        delta_rate = s1 * (r1 * rate(m.gear_1) + r2 * rate(m.gear_2))
        psi = m.teeth[0] * (abs(ratios[m.gear_1]) * tau_abs + s1 * angle(m.gear_1)) + m.phase_rad
        if isinstance(m.stiffness_shape, MeshStiffnessShape):
            factor = m.stiffness_shape.factor(psi, par[f"{m.name}.stiffness_variation"])
        else:
            factor = m.stiffness_shape(psi)
        k = par[f"{m.name}.stiffness_N_per_m"] * factor
        c = par[f"{m.name}.damping_N_s_per_m"]
        width = m.contact_width_um * 1e-6
        # deflections beyond +-10 mm are unphysical; the clip only keeps a diverging Newton iterate of the
        # integrator finite (softplus(-inf) is NaN), so that CVODES can recover by shortening the step
        f = mesh_force(nm.clip(delta, -DEFLECTION_LIMIT_M, DEFLECTION_LIMIT_M), delta_rate, k, c,
                       par[f"{m.name}.backlash_mm"] * 1e-3 if lash else None, width, m.damping_width_um * 1e-6)
        force = f["force_N"]
        torque[m.gear_1] = torque[m.gear_1] - mesh_torque_Nm(force * s1, m.base_radii_mm[0])
        torque[m.gear_2] = torque[m.gear_2] - mesh_torque_Nm(force * s1, m.base_radii_mm[1])
        outputs += [force, f["drive_force_N"], f["back_force_N"], delta * 1e6, k, f["drive_contact"],
                    f["back_contact"], axial_force_N(force, m.base_helix_angle_deg)]
        out_names += [(q, m.name) for q in ("mesh_force_N", "drive_force_N", "back_force_N",
                                            "transmission_error_um", "mesh_stiffness_N_per_m", "drive_contact",
                                            "back_contact", "axial_force_N")]
        if lash:  # total variation of the contact indicators: counts contact changes whatever the output grid
            d_delta = delta_rate / omega
            for kind, sig, sgn in (("drive", f["drive_contact"], 1.0), ("back", f["back_contact"], -1.0)):
                quad.append(nm.fabs(sig * (1.0 - sig) / width * sgn * d_delta))
                quad_names.append((f"{kind}_contact_variation", m.name))

    # external torques, own sense of rotation -> absolute
    accel_coeff = {node: 0.0 for node in net.inertias}
    ext_nominal = {node: 0.0 for node in net.inertias}
    ext = {node: 0.0 for node in net.inertias}
    ext_outputs = []
    for t in net.torques.values():
        node = t.node
        s = _sign(ratios[node])
        own_angle = abs(ratios[node]) * tau_abs + s * angle(node)
        own_speed = abs(ratios[node]) * omega + s * rate(node)
        kwargs = {k: par[t.parameter_name(k)] for k, _ in t.parameters}
        nominal_angle = abs(ratios[node]) * tau_abs
        nominal_speed = abs(ratios[node]) * omega
        if _accepts(t.function, "nominal_angle_rad"):
            kwargs["nominal_angle_rad"] = nominal_angle
        if t.acceleration_dependent:
            t0 = t.function(t_s, own_angle, own_speed, accel_rad_s2=0.0, **kwargs)
            t1 = t.function(t_s, own_angle, own_speed, accel_rad_s2=1.0, **kwargs) - t0
            accel_coeff[node] = accel_coeff[node] + t1  # own accel = s * phi_ddot, own torque -> s * torque
            nominal = t.function(t_s, nominal_angle, nominal_speed, accel_rad_s2=0.0, **kwargs)
        else:
            t0 = t.function(t_s, own_angle, own_speed, **kwargs)
            nominal = t.function(t_s, nominal_angle, nominal_speed, **kwargs)
        ext[node] = ext[node] + s * t0
        ext_nominal[node] = ext_nominal[node] + s * nominal
        ext_outputs.append((t.name, node, t0, t1 if t.acceleration_dependent else None))
    for node in net.inertias:
        torque[node] = torque[node] + ext[node]

    j_eff = [net.inertias[node].inertia_kgm2 - accel_coeff[node] for node in free]
    acc = [torque[node] / j_eff[i] for i, node in enumerate(free)]
    for name, node, t0, t1 in ext_outputs:  # the applied torque, including its acceleration-dependent part
        if t1 is not None and node in index:
            t0 = t0 + t1 * _sign(ratios[node]) * acc[index[node]]
        outputs.append(t0)
        out_names.append(("external_torque_Nm", name))
    for node in net.boundary_nodes:  # reaction needed to keep the prescribed motion, in the node's sense
        outputs.append(-_sign(ratios[node]) * torque[node])
        out_names.append(("boundary_torque_Nm", node))

    rhs = ca.vertcat(*[x[n + i] / ANGLE_UNIT_RAD for i in range(n)], *acc) / omega
    nominal_torques = ca.Function("nominal_torques", [tau, p],
                                  [ca.vertcat(*[ext_nominal[node] for node in free])], {"cse": True})
    effective = ca.Function("effective_inertias", [tau, x, p], [ca.vertcat(*j_eff)], {"cse": True})
    return NetworkEquations(tau=tau, x=x, p=p, rhs=rhs, quad=ca.vertcat(*quad) if quad else ca.SX(0, 1),
                            outputs=ca.vertcat(*outputs), parameter_names=names, quad_names=quad_names,
                            output_names=out_names, free_nodes=free, lash=lash, nominal_torques=nominal_torques,
                            effective_inertias=effective)


__all__ = ["TorsionalNetwork", "Inertia", "Shaft", "Mesh", "ExternalTorque", "NetworkEquations", "ANGLE_UNIT_RAD",
           "SPEED_PARAMETER", "OFFSET_PARAMETER"]
