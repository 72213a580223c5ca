"""Parametric sensitivities of a solved NLP from its KKT system: how the optimum moves when a parameter moves.

At a local optimum ``(x*, λ*)`` of ``min f(x, p) s.t. lbg <= g(x, p) <= ubg`` with the strongly active constraints
``A`` (nonzero multipliers) linearly independent and second-order sufficiency holding, the optimum is a
differentiable function of ``p`` (Fiacco 1976, "Sensitivity analysis for nonlinear programming using penalty
methods", Math. Programming 10, Theorem 2.1; Fiacco 1983, *Introduction to Sensitivity and Stability Analysis in
Nonlinear Programming*, sec. 3.2)::

    [ ∇²ₓₓL   J_Aᵀ ] [ dx*/dp  ]     [ ∇²ₓₚL ]
    [ J_A     0    ] [ dλ_A/dp ] = - [ ∂g_A/∂p ]        L = f + λᵀg,

and the optimal value moves by the partial derivative of the Lagrangian (the envelope theorem):
``df*/dp = ∂f/∂p + λ*ᵀ ∂g/∂p``. Every derivative here is CasADi's (exact Hessians and Jacobians of the NLP as
the solver saw it, variable bounds included as rows of ``g``). Weakly active constraints (at a bound with a zero
multiplier) are treated as inactive: at such a point the derivative is one-sided and the one given is that of the
side where the constraint stays inactive. A singular KKT matrix is solved in the least-squares sense.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ..errors import GearoptInputError


@dataclass
class KKTSensitivity:
    """Derivatives at a solved point of a :class:`casadi.Opti`: ``df_dp`` (optimal objective, as the solver
    minimised it), ``dx_dp`` (solver variables, shape ``(nx, np)``), the point ``x``, ``p``, the active row
    indices ``active`` and the residual of the KKT solve ``residual`` (0 for a regular point)."""

    df_dp: np.ndarray
    dx_dp: np.ndarray
    x: np.ndarray
    p: np.ndarray
    active: np.ndarray
    residual: float
    parameters: ca.MX | None = None
    """The parameter symbols differentiated with respect to (None: ``opti.p``)."""

    def expression_derivative(self, opti: ca.Opti, expr) -> np.ndarray:
        """``d expr(x*(p), p)/dp`` (rows: the elements of ``expr``)."""
        params = opti.p if self.parameters is None else self.parameters
        mx = ca.vec(ca.MX(expr))
        fn = ca.Function("dexpr", [opti.x, params], [ca.jacobian(mx, opti.x), ca.jacobian(mx, params)])
        jx, jp = (np.asarray(a.full(), dtype=float) for a in fn(self.x, self.p))
        return jx @ self.dx_dp + jp


def kkt_sensitivity(opti: ca.Opti, *, active_tol: float = 1e-9, parameters=None) -> KKTSensitivity:
    """KKT sensitivities of the last successful solve of ``opti`` (see the module docstring).

    Args:
        opti: a solved :class:`casadi.Opti` (``Problem.opti`` after ``Problem.solve``) with parameters.
        active_tol: a row is active when its multiplier's magnitude exceeds this (the solver's scaled units).
        parameters: the parameter symbols (a list, in the order of the result's columns); default ``opti.p``,
            which holds only the parameters the NLP uses. A declared parameter no objective or constraint uses
            (a datum of a quantity only reported) gets zero optimal-value and design derivatives, and its
            column in :meth:`KKTSensitivity.expression_derivative` is the quantity's partial derivative.
    """
    params = opti.p if parameters is None else ca.vertcat(*parameters)
    if params.numel() == 0:
        raise GearoptInputError("the NLP has no parameters: nothing to differentiate with respect to")
    x = _column(opti.debug.value(opti.x))
    p = _column(opti.debug.value(params))
    lam = _column(opti.debug.value(opti.lam_g)) if opti.ng else np.zeros(0)
    lam_sym = ca.MX.sym("lam", opti.ng)
    lag = opti.f + ca.dot(lam_sym, opti.g)
    grad_x = ca.gradient(lag, opti.x)
    fn = ca.Function("kkt", [opti.x, params, lam_sym],
                     [ca.jacobian(grad_x, opti.x), ca.jacobian(grad_x, params), ca.jacobian(opti.g, opti.x),
                      ca.jacobian(opti.g, params), ca.gradient(lag, params)])
    hxx, hxp, jx, jp, dl_dp = (np.asarray(a.full(), dtype=float) for a in fn(x, p, lam))
    active = np.flatnonzero(np.abs(lam) > active_tol)
    nx, na = x.size, active.size
    kkt = np.zeros((nx + na, nx + na))
    kkt[:nx, :nx] = hxx
    kkt[:nx, nx:] = jx[active].T
    kkt[nx:, :nx] = jx[active]
    rhs = -np.vstack([hxp, jp[active]])
    sol, *_ = np.linalg.lstsq(kkt, rhs, rcond=None)
    residual = float(np.linalg.norm(kkt @ sol - rhs) / max(np.linalg.norm(rhs), 1e-300))
    return KKTSensitivity(df_dp=dl_dp.ravel(), dx_dp=sol[:nx], x=x, p=p, active=active, residual=residual,
                          parameters=None if parameters is None else params)


def _column(v) -> np.ndarray:
    return np.atleast_1d(np.asarray(v, dtype=float)).ravel()


__all__ = ["KKTSensitivity", "kkt_sensitivity"]
