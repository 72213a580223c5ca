"""Walk-off: helical axial thrust per gear (sign from hand, role and rotation), joint torques and slip margins.

Independent checks: the direction of the axial force is compared with the normal of a numerically built involute
helicoid (finite-difference surface tangents, no use of the formula under test); Newton's third law per mesh;
the power balance of the quasi-static train; working-circle and reference-circle forms agree."""

import math

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.errors import GearoptInputError
from gearopt.joints.walk_off import (
    joint_margins,
    margin_history,
    mesh_axial_force_N,
    press_fit_slip_utilisation,
    quasi_static_mesh_torques_Nm,
    walk_off,
    working_helix_angle_deg,
)

HELICAL = go.load_default_train("helical")
SPUR = go.load_default_train("spur")
LOADS = {"cam": 50.0, "ac": 120.0, "fp": 90.0, "lpg": 3.5}


def _helicoid_point(t, z, r_b, beta_b, hand):
    """Involute helicoid of base radius r_b: the transverse involute (unwound from angle 0) turned by
    phi(z) = hand * z tan(beta_b) / r_b -- a right-hand helix advances along +z while turning counter-clockwise."""
    x, y = r_b * (math.cos(t) + t * math.sin(t)), r_b * (math.sin(t) - t * math.cos(t))
    phi = hand * z * math.tan(beta_b) / r_b
    return np.array([x * math.cos(phi) - y * math.sin(phi), x * math.sin(phi) + y * math.cos(phi), z])


@pytest.mark.parametrize("hand", [1.0, -1.0])
@pytest.mark.parametrize("t, z", [(0.35, 0.0), (0.5, 7.0), (0.2, -4.0)])
def test_axial_to_torque_ratio_matches_helicoid_normal(hand, t, z):
    # A contact force is normal to the flank. For either sense of the normal, F_z / M_z must equal the walk-off
    # model's -h tan(beta)/r (on any cylinder: tan(beta)/r = tan(beta_b)/r_b, the lead is common).
    r_b, beta_b, h = 50.0, math.radians(6.0), 1e-6
    p = _helicoid_point(t, z, r_b, beta_b, hand)
    p_t = (_helicoid_point(t + h, z, r_b, beta_b, hand) - _helicoid_point(t - h, z, r_b, beta_b, hand)) / (2 * h)
    p_z = (_helicoid_point(t, z + h, r_b, beta_b, hand) - _helicoid_point(t, z - h, r_b, beta_b, hand)) / (2 * h)
    n = np.cross(p_t, p_z)
    m_z = np.cross(p, n)[2]  # torque about +z of a force along n applied at p
    ratio_geometry = n[2] / m_z
    # model: F_z = -h tan(beta_w) F_theta with F_theta = M_z / r_w  ->  F_z / M_z = -h tan(beta_b)/r_b
    assert ratio_geometry == pytest.approx(-hand * math.tan(beta_b) / r_b, rel=1e-6)


def test_model_contributions_have_the_helicoid_ratio():
    r = walk_off(HELICAL, {"crank-cam": 200.0, "cam-ac": 80.0, "cam-fp": -30.0, "crank-lpi": 5.0, "lpi-lpg": 3.0})
    beta = math.radians(6.0)
    for row in r.contributions:
        g = row["gear"]
        pair = next(p for p in HELICAL.pairs.values() if g in p.names)
        d_ref = pair.geometry()["pitch_diameter_mm"][pair.names.index(g)]
        torque_z = r.rotation_sign[g] * row["mesh_torque_on_gear_Nm"]  # about +z
        h = 1.0 if HELICAL.helix_hands[g] == "right" else -1.0
        assert row["axial_force_N"] == pytest.approx(-h * 2000.0 * math.tan(beta) / d_ref * torque_z, rel=1e-12)


def test_newton_third_law_per_mesh_and_for_the_train():
    r = walk_off(HELICAL, {"crank-cam": 200.0, "cam-ac": 80.0, "cam-fp": 60.0, "crank-lpi": 5.0, "lpi-lpg": 3.0})
    per_mesh = {}
    for row in r.contributions:
        per_mesh.setdefault(row["mesh"], []).append(row)
    for mesh, (g1, g2) in per_mesh.items():
        assert g1["axial_force_N"] == pytest.approx(-g2["axial_force_N"], rel=1e-12), mesh
        # magnitude F_t tan(beta_w) at the working pitch circle (the brief's definition)
        assert abs(g1["axial_force_N"]) == pytest.approx(
            abs(g1["tangential_force_N"]) * math.tan(math.radians(g1["working_helix_angle_deg"])), rel=1e-12)
    assert sum(r.axial_force_N.values()) == pytest.approx(0.0, abs=1e-9)


def test_reference_and_working_circle_forms_agree():
    pair = HELICAL.pairs["crank-cam"]
    g = pair.geometry()
    T = 150.0
    beta_w = working_helix_angle_deg(6.0, g["pitch_diameter_mm"][0], g["working_pitch_diameter_mm"][0])
    assert beta_w > 6.0  # positive shift sum: the working circle is larger
    assert mesh_axial_force_N(T, g["working_pitch_diameter_mm"][0], beta_w) == pytest.approx(
        mesh_axial_force_N(T, g["pitch_diameter_mm"][0], 6.0), rel=1e-12)


def test_spur_train_has_no_axial_force():
    torques = quasi_static_mesh_torques_Nm(SPUR, LOADS)
    r = walk_off(SPUR, torques)
    assert all(v == 0.0 for v in r.axial_force_N.values())
    assert r.joint_torque_Nm["cam"] == pytest.approx(50.0)


def test_signs_flip_with_rotation_hand_and_torque():
    torques = quasi_static_mesh_torques_Nm(HELICAL, LOADS)
    base = walk_off(HELICAL, torques).axial_force_N
    ccw = walk_off(HELICAL, torques, root_rotation="ccw").axial_force_N
    neg = walk_off(HELICAL, {k: -v for k, v in torques.items()}).axial_force_N
    left = go.GearTrain(gears=HELICAL.gears, meshes=HELICAL.meshes, rack=HELICAL.rack, helix_angle_deg=6.0,
                        root_mesh=HELICAL.root_mesh, root_gear=HELICAL.root_gear, root_hand="left")
    other_hand = walk_off(left, torques).axial_force_N
    for g in base:
        assert ccw[g] == pytest.approx(-base[g]) and neg[g] == pytest.approx(-base[g])
        assert other_hand[g] == pytest.approx(-base[g], rel=1e-9, abs=1e-9)


def test_cam_gear_thrust_follows_its_camshaft_torque_not_the_accessory_loads():
    # all cam-gear meshes share its hand and helix: net thrust = 2000 tan(beta) (T_joint + J alpha) / d
    d_cam = HELICAL.pairs["crank-cam"].geometry()["pitch_diameter_mm"][1]
    k = 2000.0 * math.tan(math.radians(6.0)) / d_cam
    a = walk_off(HELICAL, quasi_static_mesh_torques_Nm(HELICAL, LOADS))
    b = walk_off(HELICAL, quasi_static_mesh_torques_Nm(HELICAL, {**LOADS, "ac": -50.0, "fp": 400.0}))
    assert a.joint_torque_Nm["cam"] == pytest.approx(50.0) and b.joint_torque_Nm["cam"] == pytest.approx(50.0)
    assert abs(a.axial_force_N["cam"]) == pytest.approx(k * 50.0, rel=1e-12)
    assert b.axial_force_N["cam"] == pytest.approx(a.axial_force_N["cam"], rel=1e-12)
    # the cam gear's own inertia torque (torsional vibration) adds to the thrust; the joint torque excludes it
    # (the crank supplies 120 N m more at the cam = 60 N m at the crank, which accelerates the cam gear)
    quasi = quasi_static_mesh_torques_Nm(HELICAL, LOADS)
    assert quasi["crank-cam"] == pytest.approx((50.0 + 2 * 120.0 + 90.0) / 2)
    c = walk_off(HELICAL, quasi | {"crank-cam": quasi["crank-cam"] + 60.0}, inertia_torques_Nm={"cam": 120.0})
    assert c.joint_torque_Nm["cam"] == pytest.approx(50.0)
    assert abs(c.axial_force_N["cam"]) == pytest.approx(k * (50.0 + 120.0), rel=1e-12)


def test_quasi_static_train_power_balance():
    # no losses, no inertia: the joints' powers sum to zero -> sum T_joint |n_gear / n_crank| = 0
    torques = quasi_static_mesh_torques_Nm(HELICAL, LOADS)
    r = walk_off(HELICAL, torques)
    power = sum(r.joint_torque_Nm[g] * abs(HELICAL.speed_ratios[g]) for g in HELICAL.gears)
    assert power == pytest.approx(0.0, abs=1e-9)
    for g, load in LOADS.items():
        assert r.joint_torque_Nm[g] == pytest.approx(load)
    assert r.joint_torque_Nm["lpi"] == pytest.approx(0.0, abs=1e-12)  # the idler passes its torque through


def test_margins_inf_at_zero_demand_and_history():
    m = joint_margins("press_fit", 100.0, 0.0, 800.0, 40000.0)
    assert m["axial_margin"] == math.inf and m["torque_margin"] == pytest.approx(8.0)
    assert m["combined_margin"] == pytest.approx(8.0)
    m0 = joint_margins("press_fit", 0.0, 0.0, 800.0, 40000.0)
    assert m0["torque_margin"] == math.inf and m0["combined_margin"] == math.inf
    # press fit: friction-force resultant (a 3-4-5 triangle)
    assert press_fit_slip_utilisation(480.0, 24000.0, 800.0, 40000.0) == pytest.approx(math.hypot(0.6, 0.6))
    t = np.array([100.0, -300.0, 200.0, 0.0])
    f = 0.1 * t
    h = margin_history("press_fit", t, f, 800.0, 40000.0)
    assert h["min_torque_margin"] == pytest.approx(800.0 / 300.0) and h["argmin_torque_margin"] == 1
    assert h["combined_margin"][3] == math.inf
    for i in range(4):
        assert h["combined_margin"][i] == pytest.approx(joint_margins("press_fit", t[i], f[i], 800.0, 40000.0)
                                                        ["combined_margin"])
    tap = joint_margins("taper_nut", 500.0, 10000.0, 1000.0, 40000.0)
    assert tap["slip_utilisation"] == pytest.approx(0.75)


def test_history_arrays_through_the_train():
    n = 50
    theta = np.linspace(0, 4 * np.pi, n)
    torques = {"crank-cam": 150 + 100 * np.sin(theta), "cam-ac": 240 * np.cos(theta), "cam-fp": 90 + 0 * theta}
    r = walk_off(HELICAL, torques)
    assert r.axial_force_N["cam"].shape == (n,)
    for i in (0, 17, 49):
        ri = walk_off(HELICAL, {k: float(v[i]) for k, v in torques.items()})
        assert r.axial_force_N["cam"][i] == pytest.approx(ri.axial_force_N["cam"])
        assert r.joint_torque_Nm["crank"][i] == pytest.approx(ri.joint_torque_Nm["crank"])


def test_errors():
    with pytest.raises(GearoptInputError, match="unknown meshes"):
        walk_off(HELICAL, {"crank-fp": 1.0})
    with pytest.raises(GearoptInputError, match="root_rotation"):
        walk_off(HELICAL, {}, root_rotation="clockwise")
    with pytest.raises(GearoptInputError, match="unknown gears"):
        walk_off(HELICAL, {}, inertia_torques_Nm={"flywheel": 1.0})
    with pytest.raises(GearoptInputError, match="joint_type"):
        joint_margins("spline", 1.0, 1.0, 1.0, 1.0)


def test_casadi_derivatives_of_thrust_and_utilisation():
    x = ca.SX.sym("x", 4)  # crank-cam, cam-ac, cam-fp torques, helix angle
    tr = go.GearTrain(gears=HELICAL.gears, meshes=HELICAL.meshes, rack=HELICAL.rack, helix_angle_deg=x[3],
                      root_mesh=HELICAL.root_mesh, root_gear=HELICAL.root_gear, root_hand="right")
    r = walk_off(tr, {"crank-cam": x[0], "cam-ac": x[1], "cam-fp": x[2]})
    u = press_fit_slip_utilisation(r.joint_torque_Nm["cam"], r.axial_force_N["cam"], 858.2, 40868.0)
    out = ca.vertcat(r.axial_force_N["cam"], r.axial_force_N["crank"], u ** 2)
    f = ca.Function("f", [x], [out])
    J = np.array(ca.Function("J", [x], [ca.jacobian(out, x)])([300.0, 240.0, 150.0, 6.0]))

    def num(v):
        t = go.GearTrain(gears=HELICAL.gears, meshes=HELICAL.meshes, rack=HELICAL.rack, helix_angle_deg=v[3],
                         root_mesh=HELICAL.root_mesh, root_gear=HELICAL.root_gear, root_hand="right")
        w = walk_off(t, {"crank-cam": v[0], "cam-ac": v[1], "cam-fp": v[2]})
        uu = press_fit_slip_utilisation(w.joint_torque_Nm["cam"], w.axial_force_N["cam"], 858.2, 40868.0)
        return np.array([w.axial_force_N["cam"], w.axial_force_N["crank"], uu ** 2], dtype=float)

    x0 = np.array([300.0, 240.0, 150.0, 6.0])
    assert np.allclose(np.array(f(x0)).ravel(), num(x0), rtol=1e-9)
    for k in range(4):
        h = 1e-5 * max(abs(x0[k]), 1.0)
        e = np.zeros(4)
        e[k] = h
        assert np.allclose(J[:, k], (num(x0 + e) - num(x0 - e)) / (2 * h), rtol=1e-5, atol=1e-8), k
