"""Modal excitation of Campbell crossings: a known harmonic torque on a two-mass chain."""

import numpy as np
import pandas as pd
import pytest

from gearopt import numerics as nm
from gearopt.dynamics import TorsionalNetwork
from gearopt.dynamics.modes import mode_shapes
from gearopt.dynamics.order_strength import crossing_excitation_Nm
from gearopt.errors import GearoptInputError


def test_modal_force_of_a_pure_order_3_torque():
    # held boundary -- k1 -- a -- k2 -- b, torque A sin(3 theta) on b: the order-3 harmonic is A on b alone, so the
    # modal force of mode m is A |phi_m(b)| (generalised force of modal superposition) and other orders give none
    net = TorsionalNetwork("chain", cycle_deg=720.0)
    net.add_inertia("ground", 1.0).add_inertia("a", 0.01).add_inertia("b", 0.02)
    net.add_shaft("ground", "a", 2.0e4).add_shaft("a", "b", 1.0e4)
    net.set_speed_boundary("ground")
    amplitude = 50.0
    net.add_torque("b", lambda t, angle, speed, A: A * nm.sin(3.0 * angle), parameters={"A": amplitude})
    # the undamped shapes in closed form: (k1 + k2 - w^2 j1) phi_a = k2 phi_b
    j1, j2, k1, k2 = 0.01, 0.02, 2.0e4, 1.0e4
    a, b, c = j1 * j2, j1 * k2 + j2 * (k1 + k2), k1 * k2
    w2 = np.sort(np.roots([a, -b, c]).real)
    phi_b = []
    for w in w2:
        ratio = k2 / (k1 + k2 - w * j1)                               # phi_a / phi_b
        phi_b.append(1.0 / max(1.0, abs(ratio)))                     # normalised to a largest |angle| of 1
    crossings = pd.DataFrame({"mode": [1, 2, 1, 2], "order": [3.0, 3.0, 1.5, 6.0], "speed_rpm": 1000.0})
    got = crossing_excitation_Nm(net, crossings)
    np.testing.assert_allclose(got[:2], amplitude * np.array(phi_b), rtol=1e-9)
    assert np.all(got[2:] < 1e-9 * amplitude)
    shapes = mode_shapes(net)
    np.testing.assert_allclose(np.abs(shapes.loc["b"]), phi_b, rtol=1e-9)
    with pytest.raises(GearoptInputError, match="order=0.25"):
        crossing_excitation_Nm(net, pd.DataFrame({"mode": [1], "order": [0.25], "speed_rpm": [1000.0]}))
