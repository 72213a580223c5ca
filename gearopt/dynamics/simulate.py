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

Each cycle calls the integrator and the output function through :mod:`~gearopt.dynamics.buffered_call` (numpy
arrays handed to CasADi as they are: converting the 46 x 2880 states and the outputs of a cycle of the default
train to and from ``casadi.DM`` cost more than the integrator's own function evaluations); the run's
``Simulation.stats`` split its time into integrator calls, output evaluations and the integrator's function
evaluations, and :attr:`Simulator.last_cycle_stats` holds the CVODES statistics of the last cycle.

Modules: :mod:`~gearopt.dynamics.integrator_build` (settings, integrator and output functions, static state),
:mod:`~gearopt.dynamics.shooting` (periodic state by shooting), :mod:`~gearopt.dynamics.simulation` (the result
record); this module runs the cycles and holds the entry points, and re-exports the public names of the others.
"""

from __future__ import annotations

import math
import time

import casadi as ca
import numpy as np
import pandas as pd

from .. import compile_cache
from ..errors import GearoptInputError
from ..validation import check_int, check_range
from . import budget
from .buffered_call import BufferedFunction
from .integrator_build import INTEGRATORS, IntegratorBuild
from .network import OFFSET_PARAMETER, SPEED_PARAMETER, TorsionalNetwork
from .shooting import PeriodicStateError, Shooting
from .simulation import QUANTITIES, Simulation

#: CasADi integrator statistics that time function evaluations: right-hand side, Jacobian, quadratures (CVODES;
#: IDAS and the fixed-step integrators report what they have).
EVALUATION_TIMERS = ("t_wall_daeF", "t_wall_jacF", "t_wall_quadF")
#: The same evaluations in process CPU time (what they cost when other processes share the cores).
EVALUATION_CPU_TIMERS = ("t_proc_daeF", "t_proc_jacF", "t_proc_quadF")


class Simulator(IntegratorBuild, Shooting):
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
    ``output_functions=False`` builds the integrator alone (for a caller that evaluates its own outputs on the states,
    as the friction joints' sequential integration does; :meth:`run` then refuses).
    ``last_cycle_stats``: the integrator statistics (CasADi's, e.g. ``nsteps``, ``nfevals``, ``t_wall_daeF``) of the
    last cycle :meth:`run` integrated.
    """

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
        if self.output_function is None:
            raise GearoptInputError("this simulator was built with output_functions=False: it has no outputs to "
                                    "record; build it with output_functions=True to run it")
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
        # numpy in and out without DM conversions (buffered_call module docstring); one memory per run
        integrate = BufferedFunction(self.integrator, ["x0", "p"], ["xf", "qf"] if self.contact_quadratures
                                     else ["xf"])
        outputs = BufferedFunction(self.output_function, [0, 1, 2], [0])
        checks = BufferedFunction(self.check_function, [0, 1, 2], [0])
        max_num_steps = self.options.get("max_num_steps", 0)
        evaluation_time, t_integrator, t_outputs = 0.0, 0.0, 0.0
        evaluation_cpu, cpu_integrator = 0.0, 0.0
        if steady_state == "shooting":
            x_start = x
            for c in range(run_in_cycles):
                p = pvec.copy()
                p[i_off] = c * self.cycle_rad
                with budget.step_limit_errors(max_num_steps):
                    x = integrate(x, p)[0][:, -1].copy()
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
        nsteps, t_loop, cpu_loop = [], time.perf_counter(), time.process_time()
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
            t0, c0 = time.perf_counter(), time.process_time()
            with budget.step_limit_errors(max_num_steps):
                res = integrate(x, p)
            t1, cpu_integrator = time.perf_counter(), cpu_integrator + time.process_time() - c0
            xs = res[0]
            stats = integrate.stats()
            self.last_cycle_stats = stats
            nsteps.append(stats.get("nsteps", stats.get("n_step", 0)))
            evaluation_time += sum(float(stats.get(k, 0.0)) for k in EVALUATION_TIMERS)
            evaluation_cpu += sum(float(stats.get(k, 0.0)) for k in EVALUATION_CPU_TIMERS)
            pmat = np.tile(p, self.n_out)  # p repeated per output point, column-major
            if recording:  # the recorded cycle's outputs hold the checked quantities: evaluate once
                outs = outputs(self.grid_rad, xs, pmat)[0]
                check = outs[self._check_rows]
            else:
                check = checks(self.grid_rad, xs, pmat)[0]
            t_integrator, t_outputs = t_integrator + t1 - t0, t_outputs + time.perf_counter() - t1
            if previous is not None and check.size:
                scale = max(float(np.max(np.abs(check))), 1e-9)
                changes.append(float(np.max(np.abs(check - previous)) / scale))
            elif check.size:
                changes.append(float("nan"))
            previous = check
            if recording:
                recorded.append((cycle, xs, p, outs))
                if self.contact_quadratures:
                    quads.append(res[1][:, -1].copy())
            else:
                run_in_done += 1
            x = xs[:, -1].copy()
            cycle += 1
            if not math.isfinite(float(np.max(np.abs(x)))):
                raise GearoptInputError(f"simulation diverged at cycle {cycle} (speed {speed_rpm} rpm): check the "
                                        f"parameters (negative stiffness? unbounded free system?)")
        stats = {"integration_time_s": time.perf_counter() - t_loop, "cycles_integrated": cycle,
                 "steps_per_cycle": nsteps, "integrator_time_s": t_integrator, "output_time_s": t_outputs,
                 "function_evaluation_time_s": evaluation_time,
                 "integration_cpu_time_s": time.process_time() - cpu_loop, "integrator_cpu_time_s": cpu_integrator,
                 "function_evaluation_cpu_time_s": evaluation_cpu, "build_time_s": self.build_time_s,
                 "method": self.method, "rtol": self.rtol, "atol": self.atol, "max_step_deg": self.max_step_deg}
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
        groups: dict = {q: ([], []) for q in QUANTITIES}
        for i, (q, element) in enumerate(self.output_names):
            groups[q][0].append(i)
            groups[q][1].append(element)
        # one 2-D block per quantity (a dict of columns would be stacked into one by pandas, column by column)
        frames = {q: pd.DataFrame(outs[rows].T, index=index, columns=cols) if rows else pd.DataFrame({}, index=index)
                  for q, (rows, cols) in groups.items()}
        free = self.eq.free_nodes
        n = len(free)
        ratios = self.network.speed_ratios()
        frames["node_angle_mrad"] = pd.DataFrame(xs[:n].T, index=index, columns=list(free))
        ratio = np.array([ratios[nd] for nd in free])
        frames["node_speed_rpm"] = pd.DataFrame(((ratio[:, None] * omega + xs[n:]) * 30.0 / math.pi).T,
                                                index=index, columns=list(free))
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


#: Samples per call of the acceleration function in :func:`node_accelerations`.
ACCELERATION_CHUNK = 2048


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
    # a map over fixed chunks, kept with the network: CasADi holds a map only weakly and building one over all the
    # samples of a long run took 0.2 s (28 800 samples), more than evaluating it
    key_map = ("accelerations_map", sim.backlash, ACCELERATION_CHUNK)
    if key_map not in network._cache:
        network._cache[key_map] = fun.map(ACCELERATION_CHUNK, "serial")
    chunk = BufferedFunction(network._cache[key_map], [0, 1, 2], [0])
    size, pad = tau.size, -tau.size % ACCELERATION_CHUNK
    tau, x = np.concatenate([tau, np.repeat(tau[-1:], pad)]), np.hstack([x, np.repeat(x[:, -1:], pad, axis=1)])
    ptile = np.tile(pvec, ACCELERATION_CHUNK)
    acc = np.hstack([chunk(tau[i:i + ACCELERATION_CHUNK], x[:, i:i + ACCELERATION_CHUNK], ptile)[0]
                     for i in range(0, tau.size, ACCELERATION_CHUNK)])[:, :size]
    return pd.DataFrame(acc.T, index=pd.Index(sim.time_s, name="time_s"), columns=list(eq.free_nodes))


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
