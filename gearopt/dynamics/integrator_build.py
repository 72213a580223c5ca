"""Assembly of a :class:`~gearopt.dynamics.simulate.Simulator`: the checked settings, the CasADi integrator over one
excitation cycle and the output functions, built once per network structure (through the compile cache when
``jit``), the impact step limit of the lash model, and the static start state.

:class:`IntegratorBuild` is the base of :class:`~gearopt.dynamics.simulate.Simulator`, whose docstring lists the
arguments; the step limit is explained in the docstring of :mod:`gearopt.dynamics.simulate`.
"""

from __future__ import annotations

import math
import time

import casadi as ca
import numpy as np

from .. import compile_cache
from ..errors import GearoptInputError
from ..validation import check_range
from . import budget
from .buffered_call import BufferedFunction
from .network import ANGLE_UNIT_RAD, TorsionalNetwork

INTEGRATORS = ("cvodes", "idas", "collocation", "rk")


class IntegratorBuild:
    """Settings, integrator and output functions of a simulator (base of
    :class:`~gearopt.dynamics.simulate.Simulator`)."""

    def __init__(self, network: TorsionalNetwork, *, lash: bool = True, method: str = "cvodes", rtol: float = 1e-6,
                 atol: float | None = None, output_step_deg: float = 0.25, max_step_deg: float | None = None,
                 min_speed_rpm: float = 700.0, fixed_step_deg: float = 0.02, options: dict | None = None,
                 jit: bool = False, external_torques: bool = False, contact_quadratures: bool = True,
                 max_steps_per_cycle: int = budget.DEFAULT_MAX_STEPS_PER_CYCLE,
                 max_wall_time_s: float = budget.DEFAULT_MAX_WALL_TIME_S, output_functions: bool = True):
        self.max_steps_per_cycle, self.max_wall_time_s = budget.check_budget_settings(max_steps_per_cycle,
                                                                                      max_wall_time_s)
        if method not in INTEGRATORS:
            raise GearoptInputError(f"method={method!r} must be one of {INTEGRATORS}")
        check_range("rtol", rtol, 0.0, 1e-2, low_inclusive=False)
        atol = 0.1 * rtol if atol is None else atol
        check_range("atol", atol, 0.0, None, low_inclusive=False)
        check_range("output_step_deg", output_step_deg, 0.0, None, low_inclusive=False, unit="deg")
        check_range("min_speed_rpm", min_speed_rpm, 0.0, None, low_inclusive=False, unit="rpm")
        check_range("fixed_step_deg", fixed_step_deg, 0.0, None, low_inclusive=False, unit="deg")
        n_out = network.cycle_deg / output_step_deg
        if abs(n_out - round(n_out)) > 1e-9 * n_out:
            raise GearoptInputError(f"output_step_deg={output_step_deg} must divide cycle_deg={network.cycle_deg}")
        self.network = network
        self.lash = bool(lash)
        self.method = method
        self.rtol, self.atol = float(rtol), float(atol)
        self.min_speed_rpm = float(min_speed_rpm)
        self.output_step_deg = float(output_step_deg)
        self.n_out = int(round(n_out))
        self.eq = network.equations(lash=self.lash)
        self.max_step_deg = self._default_max_step_deg() if max_step_deg is None else float(max_step_deg)
        if self.max_step_deg is not None:
            check_range("max_step_deg", self.max_step_deg, 0.0, None, low_inclusive=False, unit="deg")
        self.grid_rad = np.radians(self.output_step_deg * np.arange(1, self.n_out + 1))
        cycle_rad = math.radians(network.cycle_deg)
        ode = ca.Function("ode", [self.eq.tau, self.eq.x, self.eq.p], [self.eq.rhs, self.eq.quad], {"cse": True})
        rhs, quad = ode(self.eq.tau, self.eq.x, self.eq.p)  # common subexpressions eliminated once
        dae = {"x": self.eq.x, "p": self.eq.p, "t": self.eq.tau, "ode": rhs}
        self.contact_quadratures = bool(contact_quadratures) and self.eq.quad.numel() > 0
        if self.contact_quadratures:
            dae["quad"] = quad
        opts = {}
        if method in ("cvodes", "idas"):
            opts.update({"reltol": self.rtol, "abstol": self.atol,
                         "max_num_steps": min(10 ** 7, self.max_steps_per_cycle)})
            if self.max_step_deg is not None:
                opts["max_step_size"] = math.radians(self.max_step_deg)
        else:
            opts["number_of_finite_elements"] = max(self.n_out, int(math.ceil(network.cycle_deg / fixed_step_deg)))
        opts.update(options or {})
        self.options = opts
        self.jit = bool(jit) and not any(k.startswith("jit") or k == "compiler" for k in opts)
        t0 = time.perf_counter()
        self.compiled: dict = {}
        self.integrator = self._build(
            "torsional_cycle", {k: dae[k] for k in ("ode", "quad") if k in dae},
            lambda extra: ca.integrator("torsional_cycle", method, dae, 0.0, self.grid_rad, dict(opts, **extra)),
            repr((method, sorted(opts.items()), self.grid_rad.tolist())))
        self._dae = {"x": self.eq.x, "p": self.eq.p, "t": self.eq.tau, "ode": rhs}
        self._shooting_cache: dict = {}
        self.build_time_s = time.perf_counter() - t0
        self._torque_map = None  # nominal torques over the static state's samples (static_state)
        self.last_cycle_stats: dict = {}  # integrator statistics of the last cycle run (Simulator.run)
        self.cycle_rad = cycle_rad
        self.output_function = self.check_function = None
        self.output_names, self._check_rows = [], []
        if output_functions:
            self._build_output_functions(external_torques)
            self.build_time_s = time.perf_counter() - t0

    def _build_output_functions(self, external_torques: bool) -> None:
        """The output and check functions over the output grid (``output_functions``)."""
        names = self.eq.output_names
        keep = [i for i, (q, _) in enumerate(names) if external_torques or q != "external_torque_Nm"]
        self.output_names = [names[i] for i in keep]
        args = [self.eq.tau, self.eq.x, self.eq.p]
        out_expr = {"outputs": self.eq.outputs[keep]}
        # the point functions are compiled and mapped here: a saved map takes ~1 s to load (tens of MB)
        self.output_function = self._build("outputs", out_expr, lambda extra: ca.Function(
            "outputs", args, [out_expr["outputs"]], dict({"cse": True}, **extra)), "point").map(self.n_out)
        check = [i for i, (q, _) in enumerate(names) if q in ("mesh_force_N", "shaft_torque_Nm")]
        self._check_rows = [i for i, (q, _) in enumerate(self.output_names)
                            if q in ("mesh_force_N", "shaft_torque_Nm")]
        check_expr = {"check": self.eq.outputs[check]}
        self.check_function = self._build("check", check_expr, lambda extra: ca.Function(
            "check", args, [check_expr["check"]], dict({"cse": True}, **extra)), "point").map(self.n_out)

    def _build(self, name: str, expressions: dict, build, options_repr: str):
        """``build(extra_options)`` through the on-disk compile cache (:mod:`gearopt.compile_cache`) when ``jit``:
        keyed by the serialized graph of ``expressions`` (over tau, x, p) and ``options_repr``; records how the
        function was obtained in ``self.compiled``."""
        if not self.jit:  # interpreted, or JIT options of the caller's own (not cached)
            self.compiled[name] = "uncached" if self.options.get("jit") and name == "torsional_cycle" else \
                "interpreted"
            return build({})
        graph = ca.Function(name, [self.eq.tau, self.eq.x, self.eq.p], list(expressions.values()))
        fun, how = compile_cache.compiled(name, graph.serialize() + options_repr, build)
        self.compiled[name] = how
        return fun

    def _default_max_step_deg(self) -> float | None:
        """``1/omega_c`` of the fastest mesh contact at ``min_speed_rpm``, in reference degrees (lash model only;
        ``None`` = no limit for linear meshes)."""
        net = self.network
        if not net.meshes or not self.lash:
            return None
        f_max = 0.0
        for m in net.meshes.values():
            j1, j2 = net.inertias[m.gear_1].inertia_kgm2, net.inertias[m.gear_2].inertia_kgm2
            r1, r2 = (r * 1e-3 for r in m.base_radii_mm)
            m_eq = 1.0 / (r1 * r1 / j1 + r2 * r2 / j2)
            k_max = m.stiffness_N_per_m * (1.0 + abs(m.stiffness_variation) * _shape_peak(m.stiffness_shape))
            f_max = max(f_max, math.sqrt(k_max / m_eq) / (2.0 * math.pi))
        omega_min = self.min_speed_rpm * math.pi / 30.0
        return math.degrees(omega_min / (2.0 * math.pi * f_max))

    def parameter_vector(self, speed_rpm: float, parameters: dict | None = None) -> np.ndarray:
        return self.network.parameter_vector(speed_rpm, parameters)

    def static_state(self, speed_rpm: float, parameters: dict | None = None) -> np.ndarray:
        """Initial state: the linear static deflection under the cycle-mean external torques (speed boundary held),
        zero speed deviations. A network without speed boundary has the rigid-body motion as the null space of its
        static problem: it starts from the static deflection when the mean torques do no work on that motion (they
        balance, e.g. a drive and its loads), else from zero."""
        n = len(self.eq.free_nodes)
        x0 = np.zeros(2 * n)
        if not self.network.boundary_nodes and not self.network.torques:
            return x0
        pvec = self.parameter_vector(speed_rpm, parameters)
        samples = 720
        tau = np.linspace(0.0, self.cycle_rad, samples, endpoint=False)
        if self._torque_map is None:  # CasADi keeps a map only weakly: rebuilt on every call otherwise
            self._torque_map = self.eq.nominal_torques.map(samples, "serial")
        torques = np.ascontiguousarray(BufferedFunction(self._torque_map, [0, 1], [0])(tau, np.tile(pvec, samples))[0])
        mean = torques.mean(axis=1)
        if not self.network.boundary_nodes:
            ratios = self.network.speed_ratios()
            work = np.array([ratios[nd] for nd in self.eq.free_nodes]) * mean
            if abs(float(work.sum())) > 1e-9 * max(float(np.abs(work).sum()), 1e-300):
                return x0  # unbalanced: no static state (the train accelerates)
        mats = self.network.linear_matrices(parameters=parameters, speed_rpm=speed_rpm)
        # least squares: a node coupled only viscously (damper ring) has no static stiffness; it starts at zero
        x0[:n] = np.linalg.lstsq(mats["K"], mean, rcond=None)[0] / ANGLE_UNIT_RAD
        return x0


def _shape_peak(shape) -> float:
    """Largest |v(psi)| of a stiffness shape (1 for a user callable, whose factor is used as given)."""
    from .mesh import MeshStiffnessShape
    if isinstance(shape, MeshStiffnessShape):
        psi = np.linspace(0.0, 2.0 * np.pi, 1024, endpoint=False)
        return float(np.max(np.abs(shape.variation(psi)))) if shape.harmonics else 0.0
    psi = np.linspace(0.0, 2.0 * np.pi, 1024, endpoint=False)
    return float(np.max(np.abs(np.array([float(shape(v)) for v in psi]) - 1.0)))
