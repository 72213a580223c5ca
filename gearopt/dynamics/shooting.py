"""Periodic steady state of a :class:`~gearopt.dynamics.simulate.Simulator` by single shooting: Newton (CasADi
``rootfinder`` with the Jacobian from CVODES forward sensitivities) or chord iterations with the linear model's
monodromy matrix on ``Phi(x) - x = 0`` over one cycle, and the typed error when no periodic state is found
(:class:`PeriodicStateError`, the rattling lash model).

:class:`Shooting` is a mixin of :class:`~gearopt.dynamics.simulate.Simulator`, which owns the integrator settings
and the network it reads.
"""

from __future__ import annotations

import math
import time

import casadi as ca
import numpy as np

from ..errors import GearoptInputError, SolveError
from ..validation import check_range
from .network import ANGLE_UNIT_RAD, OFFSET_PARAMETER, NetworkEquations, TorsionalNetwork

SHOOTING_HINT = ("with backlash the response may be non-periodic (chaotic rattle) and has no periodic state at the "
                 "cycle period: use steady_state='run-in' (steady_state_tol, max_run_in_cycles) and report the "
                 "cycle-to-cycle change, or start the shooting from a run-in state (run_in_cycles)")


class PeriodicStateError(SolveError):
    """The shooting method found no periodic steady state (``result`` holds the last iterate's residual,
    ``status`` the iteration's return status)."""

    def __init__(self, message: str, *, status: str = "", hint: str = "", result=None):
        super().__init__(f"{message} [status: {status}]" if status else message, hint=hint, result=result)
        self.status = status


class Shooting:
    """The periodic-state methods of :class:`~gearopt.dynamics.simulate.Simulator` (mixin; the parameter vector and
    the static start state come from :class:`~gearopt.dynamics.integrator_build.IntegratorBuild`)."""

    network: TorsionalNetwork
    eq: NetworkEquations
    method: str
    rtol: float
    atol: float
    options: dict
    cycle_rad: float
    _dae: dict
    _shooting_cache: dict

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
                from scipy.linalg import lu_factor as scipy_lu_factor   # here: scipy.linalg takes 0.2 s to import
                from scipy.linalg import lu_solve as scipy_lu_solve

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
                                     status="integrator_error", hint=SHOOTING_HINT) from exc
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
                hint=SHOOTING_HINT, result=result)
        return result


__all__ = ["PeriodicStateError", "Shooting", "SHOOTING_HINT"]
