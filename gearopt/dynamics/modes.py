"""Linear analysis of a torsional network: matrices, natural frequencies, mode shapes, damped modes, Campbell
diagram and forced response over speed.

The linearised network uses the mean mesh stiffness ``k_mean`` (no variation over the mesh phase, no lash: both
flanks in contact), the shafts' and meshes' viscous damping and the inertias; an acceleration-dependent external
torque (reciprocating masses) adds its cycle-mean inertia ``mean(m s'^2)`` to its node. In the common sign
convention of :mod:`gearopt.dynamics.network` a mesh adds ``k g g^T`` to the stiffness matrix with
``g = s1 (r_b1 e_1 + r_b2 e_2)`` [m/rad], so its deflection is ``g^T phi``. Free-free networks have a zero
eigenvalue per rigid-body motion (the speed-ratio vector of the network).

Forced response (harmonic balance of the linear time-invariant model): the external torques along the nominal
motion are expanded in a Fourier series over one excitation cycle (``cycle_deg``; engine orders ``k * 360 /
cycle_deg``), each harmonic solved from ``(K - w^2 M + i w C) X = T``; the dependence of the torques on the
vibration itself (e.g. the angle-dependent reciprocating inertia) and the mesh-stiffness variation are neglected.
Units: SI (kg m^2, N m/rad, N m s/rad, N/m, rad), frequencies Hz, speeds rpm.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from ..errors import GearoptInputError
from ..validation import check_range
from .buffered_call import BufferedFunction

_DEFAULT_SAMPLES = 720


def _parameter_values(net, parameters: dict | None, speed_rpm: float | None) -> dict:
    p = net.parameters()
    for k, v in (parameters or {}).items():
        if k not in p:
            raise GearoptInputError(f"unknown parameter {k!r}; known: {list(p)}")
        p[k] = float(v)
    p["speed_rad_s"] = (speed_rpm if speed_rpm is not None else 1000.0) * math.pi / 30.0
    return p


def _mean_effective_inertias(net, pvec: np.ndarray) -> np.ndarray:
    """Cycle-mean effective inertia of the free nodes [kg m^2] (adds mean m s'^2 of acceleration-dependent
    torques), at the nominal motion."""
    eq = net.equations(lash=False)
    n = len(eq.free_nodes)
    if not any(t.acceleration_dependent for t in net.torques.values()):
        return np.array([net.inertias[nd].inertia_kgm2 for nd in eq.free_nodes])
    tau = np.linspace(0.0, math.radians(net.cycle_deg), _DEFAULT_SAMPLES, endpoint=False)
    key = ("effective_inertias_map", tau.size)  # CasADi keeps a map only weakly: rebuilt on every call otherwise
    if key not in net._cache:
        net._cache[key] = eq.effective_inertias.map(tau.size, "serial")
    j = BufferedFunction(net._cache[key], [0, 1, 2], [0])(tau, np.zeros(2 * n * tau.size), np.tile(pvec, tau.size))[0]
    return np.ascontiguousarray(j).mean(axis=1)  # C order: the rounding of the sum as before


def linear_matrices(net, boundary: str = "network", parameters: dict | None = None,
                    speed_rpm: float | None = None) -> dict:
    """Mass ``M`` [kg m^2], stiffness ``K`` [N m/rad] and damping ``C`` [N m s/rad] matrices of the linearised
    network (module docstring) and the node order ``nodes``.

    ``boundary="network"``: the speed-boundary nodes are held (their rows and columns removed); ``"free"``: every
    node is free (free-free network). ``parameters``: overrides of :meth:`TorsionalNetwork.parameters` (mesh and
    shaft stiffness/damping); ``speed_rpm`` only matters for speed-dependent torque parameters (default 1000).
    """
    if boundary not in ("network", "free"):
        raise GearoptInputError(f"boundary={boundary!r} must be 'network' or 'free'")
    ratios = net.speed_ratios()
    p = _parameter_values(net, parameters, speed_rpm)
    nodes = list(net.inertias) if boundary == "free" else net.free_nodes
    if not nodes:
        raise GearoptInputError("no free node: every inertia is a speed boundary")
    index = {nd: i for i, nd in enumerate(nodes)}
    n = len(nodes)
    m = np.zeros((n, n))
    k = np.zeros((n, n))
    c = np.zeros((n, n))
    j_free = dict(zip(net.free_nodes, _mean_effective_inertias(net, np.array(list(p.values())))))
    for nd in nodes:
        m[index[nd], index[nd]] = j_free.get(nd, net.inertias[nd].inertia_kgm2)
        c[index[nd], index[nd]] += net.inertias[nd].damping_to_frame_Nms_per_rad

    def add(matrix, vec_idx, vec_val, value):
        for a, va in zip(vec_idx, vec_val):
            for b, vb in zip(vec_idx, vec_val):
                matrix[a, b] += value * va * vb

    for s in net.shafts.values():
        idx, val = [], []
        for nd, sign in ((s.node_a, 1.0), (s.node_b, -1.0)):
            if nd in index:
                idx.append(index[nd])
                val.append(sign)
        add(k, idx, val, p[f"{s.name}.stiffness_Nm_per_rad"])
        add(c, idx, val, p[f"{s.name}.damping_Nms_per_rad"])
    for msh in net.meshes.values():
        s1 = 1.0 if ratios[msh.gear_1] >= 0 else -1.0
        idx, val = [], []
        for nd, r in ((msh.gear_1, msh.base_radii_mm[0]), (msh.gear_2, msh.base_radii_mm[1])):
            if nd in index:
                idx.append(index[nd])
                val.append(s1 * r * 1e-3)
        add(k, idx, val, p[f"{msh.name}.stiffness_N_per_m"])
        add(c, idx, val, p[f"{msh.name}.damping_N_s_per_m"])
    return {"nodes": nodes, "M": m, "K": k, "C": c}


def natural_frequencies_Hz(net, boundary: str = "network", parameters: dict | None = None) -> np.ndarray:
    """Undamped natural frequencies [Hz] of the linearised network, ascending: ``sqrt(eig(K, M)) / (2 pi)``
    (symmetric-definite generalized eigenproblem). Free-free networks start with ~0 (rigid-body mode)."""
    import scipy.linalg   # here, not at module level: scipy.linalg takes 0.2 s to import

    mats = linear_matrices(net, boundary=boundary, parameters=parameters)
    lam = scipy.linalg.eigh(mats["K"], mats["M"], eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * math.pi)


def mode_shapes(net, boundary: str = "network", parameters: dict | None = None) -> pd.DataFrame:
    """Undamped mode shapes: one column per mode (``mode_1``, ...; angles normalised to a largest |value| of 1,
    that entry positive), rows the nodes; ``frequency_Hz`` is the first row."""
    import scipy.linalg

    mats = linear_matrices(net, boundary=boundary, parameters=parameters)
    lam, vec = scipy.linalg.eigh(mats["K"], mats["M"])
    freqs = np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * math.pi)
    cols = {}
    for i in range(len(lam)):
        v = vec[:, i]
        v = v / v[np.argmax(np.abs(v))]
        cols[f"mode_{i + 1}"] = np.concatenate([[freqs[i]], v])
    return pd.DataFrame(cols, index=["frequency_Hz"] + list(mats["nodes"]))


def damped_modes(net, boundary: str = "network", parameters: dict | None = None,
                 min_frequency_Hz: float = 1e-3) -> pd.DataFrame:
    """Oscillatory modes of the damped linear network from the state-space eigenvalues ``lambda`` of
    ``[[0, I], [-M^-1 K, -M^-1 C]]``: ``frequency_Hz`` = |lambda|/(2 pi) (undamped-equivalent), ``damped_frequency_Hz``
    = Im(lambda)/(2 pi), ``damping_ratio`` = -Re(lambda)/|lambda|. Real (overdamped) eigenvalues and rigid-body
    modes (below ``min_frequency_Hz``) are left out. Sorted by frequency."""
    mats = linear_matrices(net, boundary=boundary, parameters=parameters)
    m, k, c = mats["M"], mats["K"], mats["C"]
    n = m.shape[0]
    minv = np.linalg.inv(m)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ k, -minv @ c]])
    lam = np.linalg.eigvals(a)
    lam = lam[(lam.imag > 2.0 * math.pi * min_frequency_Hz)]
    mag = np.abs(lam)
    order = np.argsort(mag)
    return pd.DataFrame({"frequency_Hz": mag[order] / (2 * math.pi),
                         "damped_frequency_Hz": lam.imag[order] / (2 * math.pi),
                         "damping_ratio": -lam.real[order] / mag[order]})


def campbell_diagram(net, speeds_rpm, orders, boundary: str = "network", parameters: dict | None = None,
                     max_frequency_Hz: float | None = None) -> dict:
    """Campbell diagram data: the natural frequencies (speed-independent for this linear model) against the
    excitation frequencies ``order * n / 60`` of the given (engine) ``orders`` over ``speeds_rpm``.

    Returns ``{"lines": DataFrame(speed_rpm, order, frequency_Hz), "modes": DataFrame(mode, frequency_Hz),
    "crossings": DataFrame(mode, frequency_Hz, order, speed_rpm)}`` with every crossing ``speed = 60 f / order``
    inside the speed range (modes above ``max_frequency_Hz`` dropped; rigid-body modes below 1e-3 Hz dropped).
    """
    speeds = np.asarray(speeds_rpm, dtype=float).reshape(-1)
    orders = np.asarray(orders, dtype=float).reshape(-1)
    if speeds.size < 2 or np.any(speeds <= 0):
        raise GearoptInputError("speeds_rpm needs at least two positive speeds")
    if np.any(orders <= 0):
        raise GearoptInputError(f"orders must be positive, got {orders.tolist()}")
    freqs = natural_frequencies_Hz(net, boundary=boundary, parameters=parameters)
    keep = freqs > 1e-3
    if max_frequency_Hz is not None:
        keep &= freqs <= max_frequency_Hz
    modes = pd.DataFrame({"mode": np.nonzero(keep)[0] + 1, "frequency_Hz": freqs[keep]})
    lines = pd.DataFrame([{"speed_rpm": s, "order": o, "frequency_Hz": o * s / 60.0} for o in orders for s in speeds])
    rows = []
    for _, mode in modes.iterrows():
        for o in orders:
            n_cross = 60.0 * mode["frequency_Hz"] / o
            if speeds.min() <= n_cross <= speeds.max():
                rows.append({"mode": int(mode["mode"]), "frequency_Hz": mode["frequency_Hz"], "order": o,
                             "speed_rpm": n_cross})
    crossings = pd.DataFrame(rows, columns=["mode", "frequency_Hz", "order", "speed_rpm"])
    return {"lines": lines, "modes": modes, "crossings": crossings}


def _harmonics(net, pvec: np.ndarray, samples: int) -> np.ndarray:
    """Complex Fourier coefficients of the nominal external torques on the free nodes over one cycle:
    ``T(tau) = Re sum_k T_k exp(i k 2 pi tau / cycle)``, shape (harmonics, nodes)."""
    eq = net.equations(lash=False)
    tau = np.linspace(0.0, math.radians(net.cycle_deg), samples, endpoint=False)
    f = eq.nominal_torques.map(samples)
    torques = np.array(f(tau[None, :], np.repeat(pvec[:, None], samples, axis=1)))  # nodes x samples
    coeffs = np.fft.rfft(torques, axis=1).T / samples
    coeffs[1:] *= 2.0
    return coeffs


def forced_response(net, speeds_rpm, max_order: float = 24.0, parameters: dict | None = None,
                    samples: int = _DEFAULT_SAMPLES) -> dict:
    """Steady-state forced response of the linearised network over speed (harmonic balance, module docstring).

    For each speed [rpm] the nominal external torques are expanded up to engine order ``max_order`` (harmonic k of
    the cycle is order ``k 360 / cycle_deg``), each harmonic solved with the speed boundary held. Returns
    ``{"orders": DataFrame(speed_rpm, order, quantity, element, amplitude, phase_rad),
    "summary": DataFrame(speed_rpm, quantity, element, mean, max, min, peak_to_peak, rms_dynamic)}`` for
    ``mesh_force_N`` (dynamic mesh force along the line of action, k_mean delta + c delta_dot) and
    ``shaft_torque_Nm`` (in the shaft's sense of rotation), with amplitudes in N / N m; ``summary`` synthesises the
    periodic signal over one cycle from all harmonics (mean = static part by least squares, so a viscously coupled
    damper ring is allowed; NaN when the mean torques on a network without speed boundary do not balance).
    """
    speeds = np.atleast_1d(np.asarray(speeds_rpm, dtype=float))
    check_range("max_order", max_order, 0.0, None, low_inclusive=False)
    ratios = net.speed_ratios()
    rows, summary = [], []
    harmonic_order = 360.0 / net.cycle_deg
    kmax = int(math.floor(max_order / harmonic_order + 1e-9))
    if 2 * kmax + 1 > samples:
        raise GearoptInputError(f"samples={samples} too few for max_order={max_order} (need > {2 * kmax})")
    for speed in speeds:
        check_range("speed_rpm", speed, 0.0, None, low_inclusive=False, unit="rpm")
        mats = linear_matrices(net, parameters=parameters, speed_rpm=speed)
        p = _parameter_values(net, parameters, speed)
        pvec = np.array(list(p.values()))
        coeffs = _harmonics(net, pvec, samples)
        nodes = mats["nodes"]
        index = {nd: i for i, nd in enumerate(nodes)}
        omega = speed * math.pi / 30.0
        responses = {}
        # static part: least squares, since a node coupled only viscously (damper ring) has no static stiffness;
        # a residual means unbalanced mean torques on a free (unheld) network: no static state, mean reported NaN
        x0, *_ = np.linalg.lstsq(mats["K"], coeffs[0].real, rcond=None)
        scale = max(float(np.max(np.abs(coeffs[0].real))), 1e-300)
        if np.max(np.abs(mats["K"] @ x0 - coeffs[0].real)) > 1e-8 * scale:
            x0 = np.full(len(nodes), np.nan)
        xs = [x0.astype(complex)]
        for kh in range(1, kmax + 1):
            w = kh * harmonic_order * omega
            h = mats["K"] - w * w * mats["M"] + 1j * w * mats["C"]
            xs.append(np.linalg.solve(h, coeffs[kh]))
        for msh in net.meshes.values():
            s1 = 1.0 if ratios[msh.gear_1] >= 0 else -1.0
            g = np.zeros(len(nodes))
            for nd, r in ((msh.gear_1, msh.base_radii_mm[0]), (msh.gear_2, msh.base_radii_mm[1])):
                if nd in index:
                    g[index[nd]] = s1 * r * 1e-3
            kk, cc = p[f"{msh.name}.stiffness_N_per_m"], p[f"{msh.name}.damping_N_s_per_m"]
            responses[("mesh_force_N", msh.name)] = [
                (kk + 1j * kh * harmonic_order * omega * cc) * (g @ xs[kh]) for kh in range(kmax + 1)]
        for s in net.shafts.values():
            g = np.zeros(len(nodes))
            for nd, sign in ((s.node_a, 1.0), (s.node_b, -1.0)):
                if nd in index:
                    g[index[nd]] = sign
            sgn = 1.0 if ratios[s.node_a] >= 0 else -1.0
            kk, cc = p[f"{s.name}.stiffness_Nm_per_rad"], p[f"{s.name}.damping_Nms_per_rad"]
            responses[("shaft_torque_Nm", s.name)] = [
                sgn * (kk + 1j * kh * harmonic_order * omega * cc) * (g @ xs[kh]) for kh in range(kmax + 1)]
        phase = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
        for (quantity, element), amps in responses.items():
            for kh in range(1, kmax + 1):
                rows.append({"speed_rpm": speed, "order": kh * harmonic_order, "quantity": quantity,
                             "element": element, "amplitude": abs(amps[kh]), "phase_rad": float(np.angle(amps[kh]))})
            dynamic = sum((amps[kh] * np.exp(1j * kh * phase)).real for kh in range(1, kmax + 1))
            mean = float(amps[0].real)
            signal = mean + dynamic
            summary.append({"speed_rpm": speed, "quantity": quantity, "element": element, "mean": mean,
                            "max": float(np.max(signal)), "min": float(np.min(signal)),
                            "peak_to_peak": float(np.ptp(dynamic)), "rms_dynamic": float(np.sqrt(np.mean(dynamic ** 2)))})
    return {"orders": pd.DataFrame(rows), "summary": pd.DataFrame(summary)}


__all__ = ["linear_matrices", "natural_frequencies_Hz", "mode_shapes", "damped_modes", "campbell_diagram",
           "forced_response"]
