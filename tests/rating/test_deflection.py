"""Shaft-deflection misalignment: the closed-form beam slopes against a numerical solution of the beam equation
(converged reference), and ISO 6336-1's f_sh formula against its own limits."""

import math

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

import gearopt as go
from gearopt.errors import GearoptInputError
from gearopt.rating import deflection as df


def _numeric_slope(force, span, a, EI, n=20001):
    """Slope at x = a of a beam on supports at 0 and span with a point load F at a (a may lie outside the span):
    integrate w'' = M/EI twice on a fine grid and fix the two constants with w(0) = w(span) = 0."""
    lo, hi = min(0.0, a), max(span, a)
    x = np.linspace(lo, hi, n)
    r_right = force * a / span            # reactions from statics (force along +w)
    r_left = force - r_right
    moment = (-r_left * np.clip(x - 0.0, 0, None) - r_right * np.clip(x - span, 0, None)
              + force * np.clip(x - a, 0, None))
    # ``moment`` is minus the sagging moment; a load along +w bends the beam concave towards +w: w'' = moment/EI
    curv = moment / EI
    slope0 = cumulative_trapezoid(curv, x, initial=0.0)
    w0 = cumulative_trapezoid(slope0, x, initial=0.0)
    w_at = lambda xq: np.interp(xq, x, w0)  # noqa: E731
    # w = w0 + c1 + c2 x with w(0) = w(span) = 0
    c2 = -(w_at(span) - w_at(0.0)) / span
    return float(np.interp(a, x, slope0) + c2)


@pytest.mark.parametrize("a", [30.0, 100.0, 170.0, 240.0, -40.0])
def test_beam_slope_against_numerical_beam(a):
    force, span, E, d = 5000.0, 200.0, 206000.0, 40.0
    inertia = math.pi * d ** 4 / 64
    closed = df.beam_slope_at_load_rad(force, span, a, E, inertia)
    numeric = _numeric_slope(force, span, a, E * inertia)
    assert closed == pytest.approx(numeric, rel=1e-5, abs=1e-10)


def test_symmetric_arrangement_has_no_bending_misalignment():
    pair = go.GearPair.from_profile_shifts(teeth=(38, 76), profile_shifts=(0.3, 0.1), module_mm=3.0,
                                           face_width_mm=30.0)
    shafts = (df.ShaftSupport(150.0, 75.0, 40.0), df.ShaftSupport(150.0, 75.0, 50.0))
    r = df.beam_shaft_misalignment_um(pair, 300.0, shafts)
    assert r["bending_um"] == pytest.approx(0.0, abs=1e-9)
    assert r["torsion_um"] > 0.0
    off = df.beam_shaft_misalignment_um(pair, 300.0, (df.ShaftSupport(150.0, 40.0, 40.0), shafts[1]))
    assert off["bending_um"] > 0.0
    # bending scales with the torque (linear elasticity)
    off2 = df.beam_shaft_misalignment_um(pair, 600.0, (df.ShaftSupport(150.0, 40.0, 40.0), shafts[1]))
    assert off2["f_sh_um"] == pytest.approx(2.0 * off["f_sh_um"])


def test_iso_f_sh_limits():
    # ISO 6336-1 cl. 7.6.4: without a bearing offset term, gamma = (|1 - 0.3| + 0.3)(b/d1)^2 = (b/d1)^2
    assert df.iso6336_shaft_misalignment_um(400.0, 100.0, 50.0) == pytest.approx(0.023 * 0.25 * 400.0)
    # arrangement a (K' = 0.48 stiff) with offset s adds K' l s/d1^2 inside the absolute value
    got = df.iso6336_shaft_misalignment_um(400.0, 100.0, 50.0, arrangement="a", bearing_span_mm=200.0,
                                           offset_mm=20.0, shaft_diameter_mm=80.0)
    k = 0.48 * 200.0 * 20.0 / 100.0 ** 2 * (100.0 / 80.0) ** 4
    assert got == pytest.approx(0.023 * (abs(1 + k - 0.3) + 0.3) * 0.25 * 400.0)
    with pytest.raises(GearoptInputError, match="arrangement"):
        df.pinion_offset_constant("z", 100.0, 80.0)
