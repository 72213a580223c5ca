"""Smooth periodic functions as truncated Fourier series, dual-typed and cheap to evaluate.

A measured or simulated periodic trace (cylinder pressure over the 720 deg cycle, an accessory torque over its shaft
revolution) becomes ``f(x) = a0 + sum_k [a_k cos(k w x) + b_k sin(k w x)]`` with ``w = 2 pi / period``. The
harmonics are generated from one ``cos``/``sin`` pair by the angle-addition recurrence, so a series of H harmonics
costs two trigonometric calls and about 8 H flops, and it is C-infinity in ``x`` (what CVODES wants). The fit takes
samples on a uniform grid (from an interpolant or a model) and keeps the first H FFT coefficients: this is the
least-squares best series of that length for the sampled function; the tests state the error against the raw data.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import numerics as nm
from ..errors import GearoptInputError


def harmonic_basis(phase_rad, harmonics: int):
    """``([cos k x], [sin k x])`` for ``k = 1..harmonics`` by the angle-addition recurrence (dual-typed).

    The recurrence's rounding error grows about linearly with k (below 1e-13 for k <= 200 in double precision).
    """
    c1 = nm.cos(phase_rad)
    s1 = nm.sin(phase_rad)
    cs, ss = [c1], [s1]
    ck, sk = c1, s1
    for _ in range(1, harmonics):
        ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
        cs.append(ck)
        ss.append(sk)
    return cs, ss


@dataclass(frozen=True)
class FourierSeries:
    """Truncated Fourier series over a period (units of ``x`` and ``f`` are the caller's).

    ``mean`` is ``a0``; ``cos_coefficients[k-1]``/``sin_coefficients[k-1]`` are ``a_k``/``b_k``.
    """

    period: float
    mean: float
    cos_coefficients: tuple
    sin_coefficients: tuple

    @property
    def harmonics(self) -> int:
        return len(self.cos_coefficients)

    @classmethod
    def fit_samples(cls, values, period: float, harmonics: int) -> FourierSeries:
        """Keep the first ``harmonics`` FFT coefficients of ``values`` sampled at ``x_j = j period / N``."""
        v = np.asarray(values, dtype=float).reshape(-1)
        n = v.size
        if harmonics < 1 or 2 * harmonics >= n:
            raise GearoptInputError(f"harmonics={harmonics} must be >= 1 and < samples/2 = {n / 2:g}")
        c = np.fft.rfft(v) / n
        a = 2.0 * c[1:harmonics + 1].real
        b = -2.0 * c[1:harmonics + 1].imag
        # coefficients at rounding level (below 1e-13 of the largest) are exact zeros: skipped when evaluating, and
        # trailing ones are dropped (a valve train with only 6th-order multiples costs only those terms)
        tiny = 1e-13 * max(float(np.max(np.abs(np.concatenate([a, b])))), abs(float(c[0].real)), 1e-300)
        a[np.abs(a) < tiny] = 0.0
        b[np.abs(b) < tiny] = 0.0
        nz = np.nonzero((a != 0.0) | (b != 0.0))[0]
        last = int(nz[-1]) + 1 if nz.size else 1
        return cls(period=float(period), mean=float(c[0].real),
                   cos_coefficients=tuple(float(x) for x in a[:last]),
                   sin_coefficients=tuple(float(x) for x in b[:last]))

    @classmethod
    def fit_function(cls, fun, period: float, harmonics: int, samples: int = 4096) -> FourierSeries:
        """Fit a vectorised numeric function of ``x`` over one period (``samples`` uniform points)."""
        x = np.arange(samples) * (period / samples)
        return cls.fit_samples(fun(x), period, harmonics)

    def phase_rad(self, x):
        return x * (2.0 * math.pi / self.period)

    def __call__(self, x):
        """Value at ``x`` (float, ndarray, CasADi SX/MX); any real ``x`` (periodic)."""
        cs, ss = harmonic_basis(self.phase_rad(x), self.harmonics)
        value = self.evaluate_basis(cs, ss)
        if isinstance(x, np.ndarray) and np.ndim(value) == 0:  # a constant series (every coefficient zero)
            return np.full(x.shape, float(value))
        return value

    def evaluate_basis(self, cs, ss):
        """Series value from a precomputed :func:`harmonic_basis` (share one basis between shifted series)."""
        total = self.mean
        for a, b, c, s in zip(self.cos_coefficients, self.sin_coefficients, cs, ss):
            if a != 0.0:
                total = total + a * c
            if b != 0.0:
                total = total + b * s
        return total

    def derivative(self, x):
        """d f / d x at ``x`` (dual-typed)."""
        cs, ss = harmonic_basis(self.phase_rad(x), self.harmonics)
        w = 2.0 * math.pi / self.period
        total = 0.0 * x
        for k, (a, b, c, s) in enumerate(zip(self.cos_coefficients, self.sin_coefficients, cs, ss), start=1):
            total = total + k * w * (b * c - a * s)
        return total

    def shifted(self, shift: float) -> FourierSeries:
        """The series of ``g(x) = f(x + shift)`` (coefficients rotated; same cost to evaluate)."""
        w = 2.0 * math.pi / self.period
        a_new, b_new = [], []
        for k, (a, b) in enumerate(zip(self.cos_coefficients, self.sin_coefficients), start=1):
            ck, sk = math.cos(k * w * shift), math.sin(k * w * shift)
            a_new.append(a * ck + b * sk)
            b_new.append(b * ck - a * sk)
        return FourierSeries(self.period, self.mean, tuple(a_new), tuple(b_new))

    def scaled(self, factor: float, offset: float = 0.0) -> FourierSeries:
        """The series of ``factor * f(x) + offset``."""
        return FourierSeries(self.period, self.mean * factor + offset,
                             tuple(factor * a for a in self.cos_coefficients),
                             tuple(factor * b for b in self.sin_coefficients))

    def extrema(self, samples: int = 14400) -> tuple[float, float, float, float]:
        """``(min, x_at_min, max, x_at_max)`` on a fine grid, refined by a parabola through the best 3 points."""
        x = np.arange(samples) * (self.period / samples)
        v = np.broadcast_to(np.asarray(self(x), dtype=float), x.shape)  # a constant series: one value everywhere
        out = []
        for i in (int(np.argmin(v)), int(np.argmax(v))):
            ym, y0, yp = v[i - 1], v[i], v[(i + 1) % samples]
            den = ym - 2.0 * y0 + yp
            t = 0.5 * (ym - yp) / den if den != 0.0 else 0.0
            h = self.period / samples
            xi = (x[i] + t * h) % self.period
            out += [float(self(xi)), float(xi)]
        return out[0], out[1], out[2], out[3]


__all__ = ["FourierSeries", "harmonic_basis"]
