"""A Fourier series without harmonics (every coefficient zero) is a constant: evaluating it on an array gives an array,
and its extrema are the constant. Regression: a zero valve-train torque amplitude in the engine data made
``AccessoryTorque.camshaft`` (and so ``gearopt dynamics``) end in an ``IndexError`` in ``FourierSeries.extrema``."""

from __future__ import annotations

import numpy as np

from gearopt.data import load_system, system_from_data
from gearopt.engine import AccessoryTorque
from gearopt.engine.fourier import FourierSeries


def test_constant_series_on_arrays_and_extrema():
    s = FourierSeries(period=2.0 * np.pi, mean=3.5, cos_coefficients=(0.0, 0.0), sin_coefficients=(0.0, 0.0))
    x = np.linspace(0.0, 7.0, 11)
    v = s(x)
    assert isinstance(v, np.ndarray) and v.shape == x.shape and np.all(v == 3.5)
    assert s(1.0) == 3.5  # a number stays a number
    lo, _, hi, _ = s.extrema()
    assert lo == hi == 3.5


def test_zero_valve_train_amplitude_gives_the_constant_mean_torque():
    data = load_system().data
    data["engine"]["camshaft"]["valve_train_torque_amplitude_Nm"] = 0.0
    mean = float(data["engine"]["camshaft"]["valve_train_torque_mean_Nm"])
    valve = AccessoryTorque.camshaft(system_from_data(data))
    assert valve.max_Nm == valve.min_Nm == valve.mean_Nm == mean
    assert np.allclose(valve.torque_Nm(np.linspace(0.0, 6.0, 7)), mean)


def test_zero_valve_train_amplitude_timing_model_simulates():
    from gearopt.cases.timing_train import default_timing_model

    data = load_system().data
    data["engine"]["camshaft"]["valve_train_torque_amplitude_Nm"] = 0.0
    model = default_timing_model("spur", system=system_from_data(data))
    sim = model.simulate(1500.0, 1, backlash=False, rtol=1e-4, jit=False, output_step_deg=2.0)
    assert np.all(np.isfinite(sim.mesh_force_N.to_numpy()))
