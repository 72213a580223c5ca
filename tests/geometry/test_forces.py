"""The one axial-thrust function and the mesh force <-> torque conversions (gearopt.geometry.forces): the ISO 21771
identity F_t tan(beta) = F_tw tan(beta_w) = F_bt tan(beta_b), dual typing, and the same numbers as the formulas
they replaced at their former sites."""

import importlib
import math

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.dynamics import mesh as dyn_mesh
from gearopt.geometry.forces import axial_force_N, mesh_axial_force_N, mesh_torque_Nm, tangential_force_N
from gearopt.rating.contact_stress import nominal_tangential_force_N
from gearopt.units import RAD_PER_DEG

wo = importlib.import_module("gearopt.joints.walk_off")  # the module (gearopt.joints.walk_off is also a function)


@pytest.fixture(scope="module")
def helical_pair():
    return go.load_default_train("helical").pairs["crank-cam"]


def test_thrust_is_the_same_at_reference_working_and_base_circle(helical_pair):
    g = helical_pair.geometry()
    T = 173.0  # torque on gear 1 [N m]
    d, d_w, d_b = g["pitch_diameter_mm"][0], g["working_pitch_diameter_mm"][0], g["base_diameter_mm"][0]
    beta, beta_b = g["helix_angle_deg"], g["base_helix_angle_deg"]
    beta_w = math.degrees(math.atan(math.tan(math.radians(beta)) * d_w / d))
    reference = axial_force_N(tangential_force_N(T, d), beta)
    working = axial_force_N(tangential_force_N(T, d_w), beta_w)
    base = axial_force_N(tangential_force_N(T, d_b), beta_b)  # F_bt = 2000 T / d_b along the line of action
    closed_form = 2000.0 * T * math.tan(math.radians(beta)) / d
    assert reference == pytest.approx(closed_form, rel=1e-13)
    assert working == pytest.approx(closed_form, rel=1e-12)
    assert base == pytest.approx(closed_form, rel=1e-12)
    assert mesh_axial_force_N(T, d, beta) == pytest.approx(closed_form, rel=1e-13)
    assert axial_force_N(-5.0, beta) == -axial_force_N(5.0, beta)  # signed like the force
    assert axial_force_N(1234.0, 0.0) == 0.0  # spur


def test_torque_and_tangential_force_are_inverse():
    for T, d in ((1.0, 100.0), (173.0, 87.3), (-42.5, 250.0)):
        assert mesh_torque_Nm(tangential_force_N(T, d), 0.5 * d) == pytest.approx(T, rel=1e-14)
    assert mesh_torque_Nm(1000.0, 50.0) == pytest.approx(50.0, rel=1e-15)  # 1 kN at 50 mm


def test_dual_typed():
    f, b, r, t = ca.SX.sym("f"), ca.SX.sym("b"), ca.SX.sym("r"), ca.SX.sym("t")
    fun = ca.Function("forces", [f, b, r, t], [axial_force_N(f, b), mesh_torque_Nm(f, r), tangential_force_N(t, r),
                                               mesh_axial_force_N(t, r, b)])
    out = [float(v) for v in fun(4000.0, 6.0, 80.0, 150.0)]
    assert out == [axial_force_N(4000.0, 6.0), mesh_torque_Nm(4000.0, 80.0), tangential_force_N(150.0, 80.0),
                   pytest.approx(mesh_axial_force_N(150.0, 80.0, 6.0), rel=1e-15)]
    arr = np.array([1.0, -2.0, 3.0])
    np.testing.assert_array_equal(axial_force_N(arr, 6.0), arr * math.tan(6.0 * RAD_PER_DEG))


# ---- the former formulas, bit for bit where the operation order is the same --------------------------------------

@pytest.mark.parametrize("force, beta_b", [(4000.0, 5.63), (-123.4, 12.0), (0.0, 6.0), (987.6, 0.0)])
def test_dynamics_thrust_is_the_former_f_bt_tan_beta_b(force, beta_b):
    assert dyn_mesh.axial_force_N is axial_force_N
    assert axial_force_N(force, beta_b) == force * math.tan(beta_b * (math.pi / 180.0))


def test_walk_off_thrust_and_tangential_force_are_the_former_inline_formulas(helical_pair):
    train = go.load_default_train("helical")
    res = wo.walk_off(train, {"crank-cam": 180.0, "cam-ac": 40.0})
    for row in res.contributions:
        pair = train.pairs[row["mesh"]]
        T1 = {"crank-cam": 180.0, "cam-ac": 40.0}[row["mesh"]]
        d_w = pair.geometry()["working_pitch_diameter_mm"]
        assert row["tangential_force_N"] == 2000.0 * T1 / d_w[0]
        i = pair.names.index(row["gear"])
        s = res.rotation_sign[row["gear"]]
        f_theta = s * (-row["tangential_force_N"] if i == 0 else row["tangential_force_N"])
        h = wo.HANDS[train.helix_hands[row["gear"]]]
        assert row["axial_force_N"] == -h * math.tan(row["working_helix_angle_deg"] * RAD_PER_DEG) * f_theta
    d_ref, d_w = 90.0, 91.3
    assert wo.working_helix_angle_deg(6.0, d_ref, d_w) == \
        math.atan(math.tan(6.0 * RAD_PER_DEG) * d_w / d_ref) / RAD_PER_DEG
    assert wo.mesh_axial_force_N is mesh_axial_force_N
    assert mesh_axial_force_N(150.0, d_w, 6.0) == pytest.approx(2000.0 * 150.0 * math.tan(6.0 * RAD_PER_DEG) / d_w,
                                                                 rel=1e-15)


def test_rating_nominal_tangential_force_is_the_former_formula(helical_pair):
    g = helical_pair.geometry()
    for gear in (1, 2):
        assert nominal_tangential_force_N(helical_pair, 173.0, gear) == 2000.0 * 173.0 / g["pitch_diameter_mm"][gear - 1]


@pytest.mark.parametrize("force, r_mm", [(4000.0, 41.3), (-123.4, 77.77), (np.array([1.5, -2.5, 1e4]), 63.1)])
def test_mesh_torque_is_the_former_force_times_radius(force, r_mm):
    r_m = r_mm * 1e-3
    # the dynamics right-hand side, the joint element, simulation statistics, the main job's dynamic design torques
    np.testing.assert_array_equal(mesh_torque_Nm(force, r_mm), force * r_m)
    np.testing.assert_array_equal(mesh_torque_Nm(force * -1.0, r_mm), force * -1.0 * r_m)
    # the walk-off history and the scene's dynamic load case wrote (F r) 1e-3: the same to the last bits
    np.testing.assert_allclose(mesh_torque_Nm(force, r_mm), force * r_mm * 1e-3, rtol=4e-16, atol=0.0)


def test_failure_study_thrust_scale_is_the_former_tan_ratio():
    from gearopt.cases.timing_train import HELICAL_ALTERNATIVES

    scale = HELICAL_ALTERNATIVES["helical_helix_3deg"]["thrust_scale"]
    assert type(scale) is float and scale == math.tan(math.radians(3.0)) / math.tan(math.radians(6.0))
