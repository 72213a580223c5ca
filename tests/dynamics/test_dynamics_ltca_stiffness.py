"""Mesh stiffness over the mesh cycle from the exact LTCA, and its use in the default timing model."""

import math

import numpy as np
import pytest

from gearopt.data import load_default_train
from gearopt.cases.timing_train import default_timing_model
from gearopt.dynamics.ltca_stiffness import ltca_mesh_stiffness
from gearopt.dynamics.mesh import MeshStiffnessShape
from gearopt.errors import GearoptInputError

MESHES = ["crank-cam", "cam-ac", "cam-fp", "crank-lpi", "lpi-lpg"]


def test_from_samples_reproduces_a_known_fourier_shape():
    # samples of a known trigonometric polynomial (in N/m): the unsmoothed fit returns its coefficients exactly
    psi = 2 * np.pi * np.arange(64) / 64
    k = 5e8 * (1.0 + 0.2 * np.cos(psi) + 0.1 * np.sin(3 * psi) - 0.05 * np.cos(5 * psi))
    shape = MeshStiffnessShape.from_samples(psi, k, harmonics=5, smoothing="none")
    np.testing.assert_allclose(shape.cos_coefficients, [0.2, 0, 0, 0, -0.05], atol=1e-12)
    np.testing.assert_allclose(shape.sin_coefficients, [0, 0, 0.1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(5e8 * shape.factor(psi), k, rtol=1e-12)
    with pytest.raises(GearoptInputError, match="equally spaced"):
        MeshStiffnessShape.from_samples(psi ** 1.1, k)


def test_constant_tooth_stiffness_gives_the_pair_count_wave():
    # closed form: a constant single-pair stiffness c' per face width makes the LTCA secant stiffness c' b times
    # the number of pairs in contact (1 or 2 for a spur pair), with mean c' b eps_alpha
    pair = load_default_train("spur").pairs["crank-cam"]
    geo = pair.geometry()
    b = float(np.min(geo["face_width_mm"])) if np.ndim(geo["face_width_mm"]) else float(geo["face_width_mm"])
    eps = float(geo["transverse_contact_ratio"])
    c = 14.0                                                       # N/(mm um)
    r = ltca_mesh_stiffness(pair, 300.0, stiffness=c, positions=1280)
    levels = r["stiffness_N_per_m"] / (c * b * 1e6)
    assert set(np.round(levels, 9)) == {1.0, 2.0}
    assert r["mean_stiffness_N_per_m"] == pytest.approx(c * b * eps * 1e6, rel=2e-3)
    np.testing.assert_array_equal(r["kinematic_te_um"], 0.0)        # unmodified flanks


def test_ltca_mean_stiffness_is_within_20_percent_of_iso():
    # the potential-energy tooth model (Sainsot 2004 fillet, Chen & Shao 2011) against ISO 6336-1 c_gamma_alpha b
    # (with the blank factor C_R of the webbed gears) at the data's design torques; measured +4 % .. +17 %
    model = default_timing_model("spur", mesh_stiffness="ltca")
    table = model.mesh_table
    ratio = table["mean_stiffness_N_per_m"] / table["iso6336_mean_stiffness_N_per_m"]
    assert ((ratio > 1.0) & (ratio < 1.2)).all(), ratio.to_dict()
    assert (table["stiffness_source"] == "ltca").all()
    # same damping ratio: c scales with sqrt(k)
    iso = default_timing_model("spur").mesh_table
    np.testing.assert_allclose(table["damping_N_s_per_m"] / iso["damping_N_s_per_m"], np.sqrt(ratio), rtol=1e-12)
    sim = model.simulate(2500.0, cycles=1, backlash=False, output_step_deg=4.0, jit=False)
    k = sim.mesh_stiffness_N_per_m["crank-cam"].to_numpy()
    lt = ltca_mesh_stiffness(model.train.pairs["crank-cam"], 300.0)
    assert np.mean(k) == pytest.approx(lt["mean_stiffness_N_per_m"], rel=0.02)
    assert np.ptp(k) > 0.3 * lt["mean_stiffness_N_per_m"]                          # the single/double-pair wave
    assert np.all(np.isfinite(sim.mesh_force_N.to_numpy()))
    with pytest.raises(GearoptInputError, match="mesh_stiffness"):
        default_timing_model("spur", mesh_stiffness="fem")
    with pytest.raises(GearoptInputError, match="torque_Nm"):
        ltca_mesh_stiffness(model.train.pairs["crank-cam"], 0.0)
    assert math.isfinite(lt["transverse_force_N"])
