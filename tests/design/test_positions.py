"""The refinement's sample points (:mod:`gearopt.design.positions`): the TE's peaks and troughs of a signal whose
extremes are known in closed form, with their neighbours on the periodic grid."""

import numpy as np

from gearopt.design.positions import extreme_fractions, new_fractions


def test_extremes_of_a_two_harmonic_te_are_its_analytic_peaks_and_troughs():
    # te = sin(x) + 0.5 sin(2x), x = 2 pi f: te' = 0 where cos x + cos 2x = 0, i.e. cos x = 1/2 or -1: the maximum at
    # f = 1/6, the minimum at 5/6 (and a stationary point at 1/2, mid-range): no other extreme in the top or bottom
    # quarter of the range
    n = 1280
    f = np.arange(n) / n
    te = np.sin(2 * np.pi * f) + 0.5 * np.sin(4 * np.pi * f)
    out = extreme_fractions(te, f, neighbours=2)
    peak, trough = f[np.argmax(te)], f[np.argmin(te)]
    assert abs(peak - 1 / 6) < 1.0 / n and abs(trough - 5 / 6) < 1.0 / n
    assert out[:5] == tuple(f[(np.argmax(te) + k) % n] for k in range(-2, 3))       # the global maximum first
    assert out[5:10] == tuple(f[(np.argmin(te) + k) % n] for k in range(-2, 3))     # then the global minimum
    assert len(out) == 10 and len(set(out)) == 10


def test_local_extremes_in_the_band_follow_most_extreme_first_and_wrap_the_period():
    # three peaks of heights 1.0, 0.9 and 0.2 (the last outside the top quarter of the range), one at the period's
    # end: the two in the band are returned, highest first, the grid wrapping around 0
    n = 100
    f = np.arange(n) / n
    te = np.zeros(n)
    te[[99, 40, 70]] = [1.0, 0.9, 0.2]
    te[[10]] = -1.0
    out = extreme_fractions(te, f, per_side=3, neighbours=1)
    assert out[:3] == (f[98], f[99], f[0])          # the global maximum, wrapping the period
    assert f[40] in out and f[70] not in out
    assert out.index(f[40]) > out.index(f[99])
    assert new_fractions(np.array(out), [f[40], 0.555, 0.555]) == [0.555]
