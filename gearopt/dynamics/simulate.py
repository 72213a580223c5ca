"""Time integration of a torsional network with a CasADi integrator, built once per network structure.

:class:`Simulator` wraps one CasADi integrator over one excitation cycle (``network.cycle_deg`` of the reference
node, e.g. 720 deg of crank angle) with every numeric property of the network as an integrator *parameter*
(:meth:`TorsionalNetwork.parameters`: speed, angle offset, mesh stiffness/damping/backlash, shaft stiffness/damping,
torque parameters). A simulation chains cycle integrations (each starts where the last ended, with the angle
offset as a parameter), so any number of cycles, any speed and any parameter values re-use the same integrator.

Integrators: ``"cvodes"`` (default; SUNDIALS BDF with error control, ``rtol``/``atol``), ``"idas"`` (SUNDIALS DAE
solver on the same ODE), and the fixed-step ``"collocation"`` and ``"rk"``, whose ``number_of_finite_elements``
counts steps over the whole cycle horizon (at least one per output interval): the step is set here in degrees
(``fixed_step_deg``). Each option is checked against CVODES in the tests.

Impacts: the lash model is smooth (dead zone of width ``w``, :mod:`gearopt.dynamics.mesh`), so the integrator's
error control sees every contact change it steps into. To make sure it cannot step *over* a whole contact, the
step of the lash model is limited to ``1/omega_c`` (a third of the contact duration ``pi/omega_c``),
``omega_c = sqrt(k_max/m_eq)`` the fastest mesh mode of two gears, at the lowest speed the simulator is built for
(``min_speed_rpm``; at higher speeds the limit is stricter in time than needed, since the independent variable is
the crank angle): every contact then contains step ends, where the error test applies. (Steps of about one
contact duration were also seen to let CVODES' corrector diverge on entering a stiff contact.) Contact
changes are counted twice: from the sampled outputs (``*_sampled``) and from integrated total variations of the
smooth contact indicators (quadratures, independent of the output grid); the two agree when the output grid
resolves the contacts (reported in :meth:`Simulation.contact_summary`).

Periodic steady state, two ways: run-in cycles until the cycle-to-cycle change of the mesh forces and shaft torques
(maximum difference between consecutive cycles divided by the peak magnitude) falls below ``steady_state_tol`` (the
changes of every cycle are reported); or single shooting (``steady_state="shooting"``,
:meth:`Simulator.periodic_state`): Newton on ``Phi(x) - x = 0`` over one cycle with the Jacobian from CVODES forward
sensitivities, reporting residual and iterations, and a typed error (:class:`PeriodicStateError`) when no periodic
state is found (the rattling lash model).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np
import pandas as pd
from scipy.linalg import lu_factor as scipy_lu_factor
from scipy.linalg import lu_solve as scipy_lu_solve

from .. import compile_cache
from ..errors import GearoptInputError, SolveError
from ..validation import check_int, check_range
from . import budget
from .network import ANGLE_UNIT_RAD, OFFSET_PARAMETER, SPEED_PARAMETER, TorsionalNetwork

INTEGRATORS = ("cvodes", "idas", "collocation", "rk")
#: Quantities of the output DataFrames (one column per element).
_QUANTITIES = ("mesh_force_N", "drive_force_N", "back_force_N", "transmission_error_um", "mesh_stiffness_N_per_m",
               "drive_contact", "back_contact", "axial_force_N", "shaft_torque_Nm", "external_torque_Nm",
               "boundary_torque_Nm")


@dataclass
class Simulation:
    """Result of :meth:`Simulator.run`: time series as DataFrames (index ``time_s``, one column per element).

    ``mesh_force_N`` signed force along the line of action (drive flanks positive), ``drive_force_N`` /
    ``back_force_N`` flank forces, ``transmission_error_um`` dynamic transmission error delta along the line of
    action, ``mesh_stiffness_N_per_m`` k(psi), ``drive_contact``/``back_contact`` smooth contact indicators,
    ``axial_force_N`` F_bt tan(beta_b) (helical meshes), ``shaft_torque_Nm`` in each shaft's sense of rotation,
    ``external_torque_Nm`` in each node's own sense, ``boundary_torque_Nm`` reaction torques of the speed boundary,
    ``node_angle_mrad`` angle deviations, ``node_speed_rpm`` absolute speeds. ``time_s`` and ``crank_angle_deg``
    (reference-node angle) arrays; ``cycle_change`` per simulated cycle (run-in first); ``contact_variation``
    integrated contact-indicator variations per mesh; ``stats`` run time and integrator counters; ``cycles``
    recorded cycles; ``mesh_base_radii_mm`` (r_b1, r_b2) per mesh; ``angle_offset_rad`` the reference-node angle
    [rad] at the start of the first recorded cycle (so ``crank_angle_deg`` + it is the integration's own angle);
    ``steady_state_method`` ``"run-in"`` or ``"shooting"`` and ``shooting`` (residual, iterations, ...; see
    :meth:`Simulator.periodic_state`).
    """

    speed_rpm: float
    backlash: bool
    time_s: np.ndarray
    crank_angle_deg: np.ndarray
    frames: dict
    contact_variation: pd.DataFrame
    cycle_change: list
    run_in_cycles: int
    steady_state_tol: float | None
    final_state: np.ndarray
    stats: dict = field(default_factory=dict)
    parameters: dict = field(default_factory=dict)
    cycles: int = 1
    mesh_base_radii_mm: dict = field(default_factory=dict)
    angle_offset_rad: float = 0.0
    steady_state_method: str = "run-in"
    shooting: dict = field(default_factory=dict)

    def __getattr__(self, name):
        frames = self.__dict__.get("frames", {})
        if name in frames:
            return frames[name]
        raise AttributeError(name)

    def frame(self, quantity: str, index: str = "time_s") -> pd.DataFrame:
        """One output DataFrame (e.g. ``"mesh_force_N"``) indexed by ``"time_s"`` or ``"crank_angle_deg"``."""
        if quantity not in self.frames:
            raise GearoptInputError(f"quantity={quantity!r} is not an output; available: {sorted(self.frames)}")
        if index == "time_s":
            return self.frames[quantity]
        if index == "crank_angle_deg":
            return self.frames[quantity].set_axis(pd.Index(self.crank_angle_deg, name="crank_angle_deg"), axis=0)
        raise GearoptInputError(f"index={index!r} must be 'time_s' or 'crank_angle_deg'")

    @property
    def converged(self) -> bool:
        """True if a steady-state tolerance was given and the last cycle change is below it."""
        return self.steady_state_tol is not None and bool(self.cycle_change) and \
            self.cycle_change[-1] < self.steady_state_tol

    def contact_summary(self) -> pd.DataFrame:
        """Per mesh: contact changes counted on the output samples and from the integrated indicator variation.

        ``drive_separations_sampled`` (drive-contact indicator falling through 0.5), ``back_impacts_sampled``
        (back-contact indicator rising through 0.5), and the integrated equivalents ``drive_separations_integrated``
        = total variation of the drive indicator / 2 and ``back_impacts_integrated`` = that of the back indicator / 2
        (over the recorded cycles; fractional when a contact starts or ends mid-way). ``integrated - sampled`` well
        above 0.5 means the output grid is too coarse to show every contact change (the integration itself is not
        affected)."""
        rows = []
        for mesh in self.frames["mesh_force_N"].columns:
            d = self.frames["drive_contact"][mesh].to_numpy()
            b = self.frames["back_contact"][mesh].to_numpy()
            row = {"mesh": mesh,
                   "drive_separations_sampled": int(np.sum((d[:-1] >= 0.5) & (d[1:] < 0.5))),
                   "back_impacts_sampled": int(np.sum((b[:-1] < 0.5) & (b[1:] >= 0.5)))}
            if mesh in self.contact_variation.index:
                row["drive_separations_integrated"] = float(self.contact_variation.loc[mesh, "drive"] / 2.0)
                row["back_impacts_integrated"] = float(self.contact_variation.loc[mesh, "back"] / 2.0)
            rows.append(row)
        return pd.DataFrame(rows).set_index("mesh")

    def summary(self) -> pd.DataFrame:
        """Per mesh over the recorded cycles: peak drive/back flank force [N], mean, RMS and minimum of the signed
        force [N], peak |axial force| [N], peak-to-peak TE [um], and the contact counts of :meth:`contact_summary`."""
        f = self.frames
        out = pd.DataFrame({
            "peak_drive_force_N": f["drive_force_N"].max(),
            "peak_back_force_N": f["back_force_N"].max(),
            "mean_force_N": f["mesh_force_N"].mean(),
            "rms_force_N": np.sqrt((f["mesh_force_N"] ** 2).mean()),
            "min_force_N": f["mesh_force_N"].min(),
            "peak_axial_force_N": f["axial_force_N"].abs().max(),
            "te_peak_to_peak_um": f["transmission_error_um"].max() - f["transmission_error_um"].min(),
        })
        out.index.name = "mesh"
        return out.join(self.contact_summary())


_SHOOTING_HINT = ("with backlash the response may be non-periodic (chaotic rattle) and has no periodic state at the "
                  "cycle period: use steady_state='run-in' (steady_state_tol, max_run_in_cycles) and report the "
                  "cycle-to-cycle change, or start the shooting from a run-in state (run_in_cycles)")


class PeriodicStateError(SolveError):
    """The shooting method found no periodic steady state (``result`` holds the last iterate's residual,
    ``status`` the iteration's return status)."""

    def __init__(self, message: str, *, status: str = "", hint: str = "", result=None):
        super().__init__(f"{message} [status: {status}]" if status else message, hint=hint, result=result)
        self.status = status


class Simulator:
    """One CasADi integrator for a network structure (module docstring), re-used for any speed and parameters.

    Arguments: ``lash`` (smooth dead-zone meshes; False: linear meshes), ``method`` (one of ``INTEGRATORS``),
    ``rtol``/``atol`` (CVODES/IDAS tolerances; states are angle deviations in mrad and speed deviations in rad/s;
    default ``atol = 0.1 rtol``), ``output_step_deg`` (output grid in reference-node degrees; must divide the cycle),
    ``max_step_deg`` (step limit of CVODES/IDAS; default for the lash model from the contact half-periods at
    ``min_speed_rpm``, see the module docstring; none for linear meshes), ``fixed_step_deg`` (collocation/rk step),
    ``options`` (extra CasADi integrator options), ``jit`` (compile the
    integrator and the output functions with the system C compiler, once: :mod:`gearopt.compile_cache` keeps the
    binaries on disk; ``compiled`` says per function whether it was ``"cached"``, ``"compiled"``,
    ``"interpreted"`` or ``"uncached"`` (JIT options passed in ``options``: compiled by CasADi, not cached); run-time gains are measured in ``benchmarks/results/dynamics_speed.json``),
    ``external_torques`` (also record the external torques, which re-evaluates the excitation at every output),
    ``contact_quadratures`` (integrate the contact-indicator variations, lash model; about 15 % of the run time on the
    default train -- without them only the sampled contact counts are reported), the budgets ``max_steps_per_cycle``
    (estimated steps per cycle before a run; also CVODES/IDAS ``max_num_steps``) and ``max_wall_time_s`` (checked
    between cycles), each raising :class:`~gearopt.errors.BudgetExceededError` (:mod:`gearopt.dynamics.budget`).
    """

    def __init__(self, network: TorsionalNetwork, *, lash: bool = True, method: str = "cvodes", rtol: float = 1e-6,
                 atol: float | None = None, output_step_deg: float = 0.25, max_step_deg: float | None = None,
                 min_speed_rpm: float = 700.0, fixed_step_deg: float = 0.02, options: dict | None = None,
                 jit: bool = False, external_torques: bool = False, contact_quadratures: bool = True,
                 max_steps_per_cycle: int = budget.DEFAULT_MAX_STEPS_PER_CYCLE,
                 max_wall_time_s: float = budget.DEFAULT_MAX_WALL_TIME_S):
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
        names = self.eq.output_names
        keep = [i for i, (q, _) in enumerate(names) if external_torques or q != "external_torque_Nm"]
        self.output_names = [names[i] for i in keep]
        args = [self.eq.tau, self.eq.x, self.eq.p]
        out_expr = {"outputs": self.eq.outputs[keep]}
        self.output_function = self._build("outputs", out_expr, lambda extra: ca.Function(
            "outputs", args, [out_expr["outputs"]], dict({"cse": True}, **extra)).map(self.n_out),
            repr(("map", self.n_out)))
        check = [i for i, (q, _) in enumerate(names) if q in ("mesh_force_N", "shaft_torque_Nm")]
        self._check_rows = [i for i, (q, _) in enumerate(self.output_names)
                            if q in ("mesh_force_N", "shaft_torque_Nm")]
        check_expr = {"check": self.eq.outputs[check]}
        self.check_function = self._build("check", check_expr, lambda extra: ca.Function(
            "check", args, [check_expr["check"]], dict({"cse": True}, **extra)).map(self.n_out),
            repr(("map", self.n_out)))
        self.build_time_s = time.perf_counter() - t0
        self.cycle_rad = cycle_rad

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

    # ------------------------------------------------------------------------------------------------------------

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
        zero speed deviations. Zero for a network without speed boundary (its static problem is singular)."""
        n = len(self.eq.free_nodes)
        x0 = np.zeros(2 * n)
        if not self.network.boundary_nodes:
            return x0
        pvec = self.parameter_vector(speed_rpm, parameters)
        samples = 720
        tau = np.linspace(0.0, self.cycle_rad, samples, endpoint=False)
        torques = np.array(self.eq.nominal_torques.map(samples)(tau[None, :], np.repeat(pvec[:, None], samples, 1)))
        mats = self.network.linear_matrices(parameters=parameters, speed_rpm=speed_rpm)
        # least squares: a node coupled only viscously (damper ring) has no static stiffness; it starts at zero
        x0[:n] = np.linalg.lstsq(mats["K"], torques.mean(axis=1), rcond=None)[0] / ANGLE_UNIT_RAD
        return x0

    # ------------------------------------------------------------------------------------------------------------
    # periodic steady state by shooting
    # ------------------------------------------------------------------------------------------------------------

    def _neutral_directions(self) -> np.ndarray:
        """Unit state vectors (columns) of the angle coordinates that no stiffness holds (null space of the linear
        stiffness matrix with the speed boundary held, e.g. the ring of a viscous damper): any constant shift along
        them is again periodic, so shooting pins them to the initial guess (module docstring of
        :meth:`periodic_state`)."""
        import scipy.linalg
        mats = self.network.linear_matrices()
        null = scipy.linalg.null_space(mats["K"], rcond=1e-10)
        n = len(self.eq.free_nodes)
        out = np.zeros((2 * n, null.shape[1]))
        out[:n] = null
        return out

    def _check_periodic_structure(self) -> None:
        net = self.network
        if not net.boundary_nodes:
            raise GearoptInputError("steady_state='shooting' needs a speed boundary: a free network's rigid-body "
                                    "rotation makes the periodic state undetermined (use run-in)")
        ratios = net.speed_ratios()
        for m in net.meshes.values():
            periods = m.teeth[0] * abs(ratios[m.gear_1]) * net.cycle_deg / 360.0
            if abs(periods - round(periods)) > 1e-9 * max(periods, 1.0):
                raise GearoptInputError(f"steady_state='shooting': mesh {m.name!r} completes {periods:.6g} tooth "
                                        f"periods per cycle of {net.cycle_deg} deg (not an integer), so the "
                                        f"response is not periodic in the cycle")

    def _cycle_map(self):
        """CasADi Function ``(x, p) -> x`` after one cycle (an integrator with the cycle end as its only output)."""
        if "cycle_map" not in self._shooting_cache:
            self._check_periodic_structure()
            nx, npar = self.eq.x.numel(), self.eq.p.numel()
            end = ca.integrator("torsional_cycle_end", self.method, self._dae, 0.0, [self.cycle_rad],
                                self._sensitivity_options())
            x, p = ca.MX.sym("x", nx), ca.MX.sym("p", npar)
            self._shooting_cache["cycle_map"] = (ca.Function("cycle_map", [x, p], [end(x0=x, p=p)["xf"]]), x, p)
        return self._shooting_cache["cycle_map"]

    def _sensitivity_options(self) -> dict:
        # JIT-compiling the forward-sensitivity equations of the default train takes minutes (measured 160 s):
        # the shooting integrator is interpreted
        return {k: v for k, v in self.options.items() if not (k.startswith("jit") or k == "compiler")}

    def _newton_solver(self, tol: float, max_iter: int):
        key = ("newton", float(tol), int(max_iter))
        if key not in self._shooting_cache:
            cycle_map, x, p = self._cycle_map()
            xg = ca.MX.sym("xg", x.numel())
            neutral = ca.DM(self._neutral_directions())
            residual = cycle_map(x, p) - x + ca.mtimes(neutral, ca.mtimes(neutral.T, x - xg))
            g = ca.Function("periodicity", [x, ca.vertcat(p, xg)], [residual])
            self._shooting_cache[key] = ca.rootfinder("periodic_state", "newton", g,
                                                      {"abstol": float(tol), "max_iter": int(max_iter),
                                                       "error_on_fail": False})
        return self._shooting_cache[key]

    def linear_monodromy(self, speed_rpm: float, parameters: dict | None = None) -> np.ndarray:
        """State transition matrix over one cycle of the linear time-invariant model (mean mesh stiffness, no
        lash, mean effective inertias; :func:`gearopt.dynamics.modes.linear_matrices`) in the integrator's
        state units: ``expm(A cycle)`` with ``dx/dtau = A x``. The chord Jacobian of ``jacobian="linear"``."""
        import scipy.linalg
        mats = self.network.linear_matrices(parameters=parameters, speed_rpm=speed_rpm)
        n = len(self.eq.free_nodes)
        omega = speed_rpm * math.pi / 30.0
        minv = np.linalg.inv(mats["M"])
        a = np.block([[np.zeros((n, n)), np.eye(n) / ANGLE_UNIT_RAD],
                      [-minv @ mats["K"] * ANGLE_UNIT_RAD, -minv @ mats["C"]]]) / omega
        return scipy.linalg.expm(a * self.cycle_rad)

    def periodic_state(self, speed_rpm: float, parameters: dict | None = None, x0=None, *, tol: float | None = None,
                       max_iter: int = 20, jacobian: str = "sensitivity") -> dict:
        """Periodic steady state by single shooting: the state ``x`` at the cycle start (reference angle 0 of a
        cycle) with ``Phi(x) = x``, ``Phi`` the integration over one cycle (``cycle_deg``, 720 deg of crank angle
        for the engine).

        ``jacobian="sensitivity"``: a CasADi ``newton`` rootfinder whose Jacobian ``dPhi/dx - I`` comes from the
        integrator's forward sensitivities (one direction per state; exact Newton, for any model including lash;
        costly: about 20 s per iteration for the 46-state default train without lash, 110x one cycle).
        ``"linear"``: chord iterations with the fixed Jacobian ``expm(A T) - I`` of the linear time-invariant model
        (:meth:`linear_monodromy`) and the residual from the full nonlinear integration -- one plain cycle per
        iteration, linear convergence at the rate of the model's departure from the LTI one (mesh-stiffness
        variation, reciprocating inertia); meant for the no-lash model, where it converges in a few iterations.

        States are the deviations from the rigid rotation at the controlled speed (angles [mrad], speeds [rad/s];
        :mod:`gearopt.dynamics.network`). Angle coordinates that no stiffness holds (a viscous damper ring) make
        ``Phi - I`` singular: their level is pinned to ``x0`` by adding ``N N^T (x - x0)`` to the residual (``N``
        the unit null vectors of the linear stiffness matrix); ``N N^T (x - x0) = 0`` at the root whenever a
        periodic state exists (the pinned direction is the right null vector of ``dPhi/dx - I`` and not orthogonal
        to the left one), so the root is periodic -- reported as ``residual``.

        ``x0``: initial guess (default :meth:`static_state`); ``tol``: tolerance on max |residual| in state units
        (default ``max(100 atol, 50 rtol max(1, max |x0|))``, above the integration error of one cycle: the
        residual of the default train stalls near 1e-5 max |x| at rtol 1e-6); ``max_iter`` iterations.
        Returns a dict: ``x0`` (the periodic state), ``residual`` = max |Phi(x) - x| [state units],
        ``relative_residual`` (divided by max |x|), ``iterations``, ``converged``, ``time_s``, ``jacobian``,
        ``neutral_directions`` (count pinned). Raises :class:`PeriodicStateError` if it does not converge (a lash
        model that rattles chaotically has no periodic state at the cycle period; use run-in then).

        Periodicity in the cycle is assumed for the external torques (the network's contract for ``cycle_deg``)
        and checked for the mesh phases. The default timing model's lube-pump ripple (rotor order 7 at 38/24 of
        crank speed) repeats only every 6 engine cycles; its effect is a cycle-to-cycle change of about 0.2 % of
        the peak mesh force (measured), which bounds how periodic any one-cycle state of that model can be.
        """
        check_range("max_iter", max_iter, 1, None)
        if jacobian not in ("sensitivity", "linear"):
            raise GearoptInputError(f"jacobian={jacobian!r} must be 'sensitivity' or 'linear'")
        t0 = time.perf_counter()
        cycle_map = self._cycle_map()[0]
        pvec = self.parameter_vector(speed_rpm, parameters)
        pvec[self.eq.parameter_names.index(OFFSET_PARAMETER)] = 0.0
        guess = self.static_state(speed_rpm, parameters) if x0 is None else np.asarray(x0, dtype=float).reshape(-1)
        if guess.size != self.eq.x.numel():
            raise GearoptInputError(f"x0 has {guess.size} entries, the network has {self.eq.x.numel()} states")
        if tol is None:  # above the one-cycle integration error (measured ~1e-5 relative at rtol 1e-6)
            tol = max(100.0 * self.atol, 50.0 * self.rtol * max(1.0, float(np.max(np.abs(guess)))))
        check_range("tol", tol, 0.0, None, low_inclusive=False)
        neutral = self._neutral_directions()
        history = []

        def residual_of(x):
            r = np.array(cycle_map(x, pvec)).reshape(-1) - x
            return r + neutral @ (neutral.T @ (x - guess))

        try:
            if jacobian == "sensitivity":
                solver = self._newton_solver(tol, max_iter)
                x = np.array(solver(guess, np.concatenate([pvec, guess]))).reshape(-1)
                stats = solver.stats()
                iterations = int(stats.get("iter_count", -1))
                status, success = str(stats.get("return_status", "")), bool(stats.get("success", False))
            else:
                jac = self.linear_monodromy(speed_rpm, parameters) - np.eye(guess.size) + neutral @ neutral.T
                lu = scipy_lu_factor(jac)
                x, iterations, success, status = guess.copy(), 0, False, "max_iter"
                for iterations in range(1, max_iter + 1):
                    r = residual_of(x)
                    history.append(float(np.max(np.abs(r))))
                    if not np.isfinite(history[-1]):
                        status = "non-finite residual"
                        break
                    if history[-1] <= tol:
                        success, status = True, "success"
                        iterations -= 1
                        break
                    x = x - scipy_lu_solve(lu, r)
        except RuntimeError as exc:  # integrator failure inside the iteration (diverging iterate)
            raise PeriodicStateError(f"shooting at {speed_rpm} rpm failed inside the integration: {exc}",
                                     status="integrator_error", hint=_SHOOTING_HINT) from exc
        finite = bool(np.all(np.isfinite(x)))
        residual = float(np.max(np.abs(np.array(cycle_map(x, pvec)).reshape(-1) - x))) if finite else float("nan")
        scale = max(float(np.max(np.abs(x))) if finite else 0.0, 1e-300)
        result = {"x0": x, "residual": residual, "relative_residual": residual / scale, "iterations": iterations,
                  "converged": success and finite and residual <= 10.0 * tol, "time_s": time.perf_counter() - t0,
                  "tolerance": tol, "jacobian": jacobian, "neutral_directions": int(neutral.shape[1]),
                  "return_status": status, "residual_history": history}
        if not result["converged"]:
            raise PeriodicStateError(
                f"shooting at {speed_rpm} rpm did not converge: residual {residual:.3g} (tolerance {tol:.3g}) after "
                f"{iterations} iterations (jacobian={jacobian!r})", status=status or "not converged",
                hint=_SHOOTING_HINT, result=result)
        return result

    def run(self, speed_rpm: float, cycles: int = 10, *, parameters: dict | None = None, x0=None,
            run_in_cycles: int = 0, steady_state_tol: float | None = None, max_run_in_cycles: int = 60,
            steady_state: str = "run-in", shooting_tol: float | None = None, shooting_max_iter: int = 20,
            shooting_jacobian: str = "sensitivity", on_shooting_failure: str = "raise") -> Simulation:
        """Simulate ``cycles`` recorded cycles at ``speed_rpm`` [rpm] of the reference node.

        ``parameters``: overrides of the network parameters; ``x0``: initial state (default :meth:`static_state`);
        ``run_in_cycles``: cycles integrated before recording; with ``steady_state_tol`` the run-in continues until
        the cycle-to-cycle change (module docstring) is below it (at most ``max_run_in_cycles``).
        ``steady_state="shooting"``: after ``run_in_cycles`` the periodic state is solved by
        :meth:`periodic_state` (``shooting_tol``, ``shooting_max_iter``, ``shooting_jacobian``) and the recording starts there
        (``Simulation.shooting`` reports residual and iterations); if it fails, ``on_shooting_failure="raise"``
        raises :class:`PeriodicStateError`, ``"run-in"`` falls back to the run-in (``steady_state_tol``, default
        1e-4) and says so in ``Simulation.steady_state_method`` and ``Simulation.shooting``. Raises
        ``GearoptInputError`` below ``min_speed_rpm`` (the impact step limit would not hold).
        """
        check_range("speed_rpm", speed_rpm, self.min_speed_rpm, None, unit="rpm")
        cycles = check_int("cycles", cycles, 1, budget.MAX_CYCLES)
        run_in_cycles = check_int("run_in_cycles", run_in_cycles, 0, budget.MAX_CYCLES)
        if steady_state_tol is not None:
            check_range("steady_state_tol", steady_state_tol, 0.0, None, low_inclusive=False)
        if steady_state not in ("run-in", "shooting"):
            raise GearoptInputError(f"steady_state={steady_state!r} must be 'run-in' or 'shooting'")
        if on_shooting_failure not in ("raise", "run-in"):
            raise GearoptInputError(f"on_shooting_failure={on_shooting_failure!r} must be 'raise' or 'run-in'")
        t_start = time.perf_counter()
        budget.check_step_budget(self.network, float(speed_rpm), self.max_step_deg, self.max_steps_per_cycle)
        pvec = self.parameter_vector(speed_rpm, parameters)
        i_off = self.eq.parameter_names.index(OFFSET_PARAMETER)
        x = self.static_state(speed_rpm, parameters) if x0 is None else np.asarray(x0, dtype=float).reshape(-1)
        if x.size != self.eq.x.numel():
            raise GearoptInputError(f"x0 has {x.size} entries, the network has {self.eq.x.numel()} states")
        method, shooting = "run-in", {}
        if steady_state == "shooting":
            x_start = x
            for c in range(run_in_cycles):
                p = pvec.copy()
                p[i_off] = c * self.cycle_rad
                x = np.array(self.integrator(x0=x, p=p)["xf"])[:, -1]
            try:
                shooting = self.periodic_state(speed_rpm, parameters, x0=x, tol=shooting_tol,
                                               max_iter=shooting_max_iter, jacobian=shooting_jacobian)
                x, run_in_cycles, steady_state_tol, method = shooting["x0"], 0, None, "shooting"
            except PeriodicStateError as exc:
                if on_shooting_failure == "raise":
                    raise
                shooting = dict(exc.result or {}, converged=False, error=str(exc).splitlines()[0])
                x, method = x_start, "run-in (shooting failed)"
                steady_state_tol = 1e-4 if steady_state_tol is None else steady_state_tol
        changes, recorded, quads, previous = [], [], [], None
        cycle, run_in_done = 0, 0
        nsteps, t_loop = [], time.perf_counter()
        recording = False
        while True:
            recording = recording or (run_in_done >= run_in_cycles and (
                steady_state_tol is None or (bool(changes) and changes[-1] < steady_state_tol)
                or run_in_done >= max_run_in_cycles))
            if recording and len(recorded) >= cycles:
                break
            p = pvec.copy()
            p[i_off] = cycle * self.cycle_rad
            budget.check_wall_time(t_start, self.max_wall_time_s, cycle)
            res = budget.integrate(self.integrator, x, p, self.options.get("max_num_steps", 0))
            xs = res["xf"].full()
            stats = self.integrator.stats()
            nsteps.append(stats.get("nsteps", stats.get("n_step", 0)))
            pmat = np.repeat(p[:, None], self.n_out, 1)
            if recording:  # the recorded cycle's outputs hold the checked quantities: evaluate once
                outs = self.output_function(self.grid_rad[None, :], xs, pmat).full()
                check = outs[self._check_rows]
            else:
                check = self.check_function(self.grid_rad[None, :], xs, pmat).full()
            if previous is not None and check.size:
                scale = max(float(np.max(np.abs(check))), 1e-9)
                changes.append(float(np.max(np.abs(check - previous)) / scale))
            elif check.size:
                changes.append(float("nan"))
            previous = check
            if recording:
                recorded.append((cycle, xs, p, outs))
                if self.contact_quadratures:
                    quads.append(np.array(res["qf"])[:, -1])
            else:
                run_in_done += 1
            x = xs[:, -1]
            cycle += 1
            if not math.isfinite(float(np.max(np.abs(x)))):
                raise GearoptInputError(f"simulation diverged at cycle {cycle} (speed {speed_rpm} rpm): check the "
                                        f"parameters (negative stiffness? unbounded free system?)")
        stats = {"integration_time_s": time.perf_counter() - t_loop, "cycles_integrated": cycle,
                 "steps_per_cycle": nsteps, "build_time_s": self.build_time_s, "method": self.method,
                 "rtol": self.rtol, "atol": self.atol, "max_step_deg": self.max_step_deg}
        result = self._result(speed_rpm, pvec, recorded, quads, changes, run_in_done, steady_state_tol, x, stats)
        result.steady_state_method, result.shooting = method, shooting
        stats["run_time_s"] = time.perf_counter() - t_start  # static state + integration + outputs
        return result

    def _result(self, speed_rpm, pvec, recorded, quads, changes, run_in, tol, x_final, stats) -> Simulation:
        omega = speed_rpm * math.pi / 30.0
        tau = np.concatenate([c * self.cycle_rad + self.grid_rad for c, _, _, _ in recorded])
        tau = tau - recorded[0][0] * self.cycle_rad  # recorded time starts at 0
        xs = np.concatenate([x for _, x, _, _ in recorded], axis=1)
        outs = np.concatenate([o for _, _, _, o in recorded], axis=1)
        time_s = tau / omega
        index = pd.Index(time_s, name="time_s")
        frames = {q: {} for q in _QUANTITIES}
        for i, (q, element) in enumerate(self.output_names):
            frames[q][element] = outs[i]
        frames = {q: pd.DataFrame(cols, index=index) for q, cols in frames.items()}
        free = self.eq.free_nodes
        n = len(free)
        ratios = self.network.speed_ratios()
        frames["node_angle_mrad"] = pd.DataFrame({nd: xs[i] for i, nd in enumerate(free)}, index=index)
        frames["node_speed_rpm"] = pd.DataFrame(
            {nd: (ratios[nd] * omega + xs[n + i]) * 30.0 / math.pi for i, nd in enumerate(free)}, index=index)
        if quads:
            total = np.sum(quads, axis=0)
            tv = {}
            for value, (kind, mesh) in zip(total, self.eq.quad_names):
                tv.setdefault(mesh, {})[kind.split("_")[0]] = float(value)
            variation = pd.DataFrame.from_dict(tv, orient="index")
        else:
            variation = pd.DataFrame(columns=["drive", "back"])
        names = self.eq.parameter_names
        return Simulation(speed_rpm=float(speed_rpm), backlash=self.lash, time_s=time_s,
                          crank_angle_deg=np.degrees(tau), frames=frames, contact_variation=variation,
                          cycle_change=changes, run_in_cycles=run_in, steady_state_tol=tol, final_state=x_final,
                          stats=stats, parameters=dict(zip(names, pvec.tolist())), cycles=len(recorded),
                          mesh_base_radii_mm={m.name: m.base_radii_mm for m in self.network.meshes.values()},
                          angle_offset_rad=float(recorded[0][0] * self.cycle_rad))


def _shape_peak(shape) -> float:
    """Largest |v(psi)| of a stiffness shape (1 for a user callable, whose factor is used as given)."""
    from .mesh import MeshStiffnessShape
    if isinstance(shape, MeshStiffnessShape):
        psi = np.linspace(0.0, 2.0 * np.pi, 1024, endpoint=False)
        return float(np.max(np.abs(shape.variation(psi)))) if shape.harmonics else 0.0
    psi = np.linspace(0.0, 2.0 * np.pi, 1024, endpoint=False)
    return float(np.max(np.abs(np.array([float(shape(v)) for v in psi]) - 1.0)))


def node_accelerations(network: TorsionalNetwork, sim: Simulation) -> pd.DataFrame:
    """Angular accelerations [rad/s^2] of the free nodes at the samples of ``sim`` (a simulation of ``network``),
    in the network's common sign convention (the nominal rotation has constant speed, so this is both the
    vibratory and the absolute acceleration). Evaluated from the equations of motion at the recorded states (the
    integrator's accuracy, no finite difference). Columns: free nodes; index ``time_s``."""
    eq = network.equations(lash=sim.backlash)
    key = ("accelerations", sim.backlash)
    n = len(eq.free_nodes)
    if key not in network._cache:
        i_speed = eq.parameter_names.index(SPEED_PARAMETER)
        acc = eq.rhs[n:] * eq.p[i_speed]
        definition = ca.Function("accelerations", [eq.tau, eq.x, eq.p], [acc]).serialize()
        network._cache[key] = compile_cache.compiled("accelerations", definition, lambda extra: ca.Function(
            "accelerations", [eq.tau, eq.x, eq.p], [acc], dict({"cse": True}, **extra)))[0]
    fun = network._cache[key]
    pvec = np.array([sim.parameters[k] for k in eq.parameter_names], dtype=float)
    pvec[eq.parameter_names.index(OFFSET_PARAMETER)] = 0.0
    omega = pvec[eq.parameter_names.index(SPEED_PARAMETER)]
    ratios = network.speed_ratios()
    x = np.vstack([sim.node_angle_mrad[nd].to_numpy() for nd in eq.free_nodes]
                  + [sim.node_speed_rpm[nd].to_numpy() * math.pi / 30.0 - ratios[nd] * omega
                     for nd in eq.free_nodes])
    tau = np.radians(sim.crank_angle_deg) + sim.angle_offset_rad
    acc = np.array(fun.map(tau.size)(tau[None, :], x, np.repeat(pvec[:, None], tau.size, 1)))
    return pd.DataFrame({nd: acc[i] for i, nd in enumerate(eq.free_nodes)}, index=pd.Index(sim.time_s, name="time_s"))


def simulator(network: TorsionalNetwork, **options) -> Simulator:
    """The network's cached :class:`Simulator` for these options (built on first use)."""
    key = ("simulator",) + tuple(sorted((k, repr(v)) for k, v in options.items()))
    cache = network._cache
    if key not in cache:
        cache[key] = Simulator(network, **options)
    return cache[key]


def simulate(network: TorsionalNetwork, speed_rpm: float, cycles: int = 10, *, backlash: bool = True,
             rtol: float = 1e-6, parameters: dict | None = None, run_in_cycles: int = 0,
             steady_state_tol: float | None = None, x0=None, steady_state: str = "run-in",
             shooting_tol: float | None = None, shooting_jacobian: str = "sensitivity",
             shooting_max_iter: int = 20, on_shooting_failure: str = "raise", reuse: bool = True,
             **options) -> Simulation:
    """Simulate a network (cached :class:`Simulator` with ``lash=backlash``, ``rtol`` and ``options``; see
    :meth:`Simulator.run` for the rest, including ``steady_state="shooting"``).

    ``reuse``: a run with the same arguments (speed, cycles, lash, tolerances, parameters, options; ``x0`` not
    given) on the same, unchanged network is computed once per session and the same :class:`Simulation` returned
    again (treat it as read-only); ``reuse=False`` always integrates (e.g. to time a run)."""
    sim = simulator(network, lash=backlash, rtol=rtol, **options)
    kwargs = dict(parameters=parameters, x0=x0, run_in_cycles=run_in_cycles, steady_state_tol=steady_state_tol,
                  steady_state=steady_state, shooting_tol=shooting_tol, shooting_jacobian=shooting_jacobian,
                  shooting_max_iter=shooting_max_iter, on_shooting_failure=on_shooting_failure)
    if not reuse or x0 is not None:
        return sim.run(speed_rpm, cycles, **kwargs)
    check_range("speed_rpm", speed_rpm, sim.min_speed_rpm, None, unit="rpm")  # before they key the cache
    cycles = check_int("cycles", cycles, 1, budget.MAX_CYCLES)
    key = ("run", id(sim), float(speed_rpm), cycles,
           repr(sorted((k, v) for k, v in kwargs.items() if k not in ("parameters", "x0"))),
           repr(sorted((parameters or {}).items())))
    runs = network._cache
    if key not in runs:
        runs[key] = sim.run(speed_rpm, cycles, **kwargs)
    return runs[key]


__all__ = ["INTEGRATORS", "Simulation", "Simulator", "simulator", "simulate", "node_accelerations",
           "PeriodicStateError"]
