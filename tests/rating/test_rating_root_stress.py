"""ISO 6336-3 method B root stress: the closed-form critical section against an independently generated tooth
(numeric rack generation), the unrolled Newton solve, the load-point generalisation against direct involute
geometry and against method B at the outer point of single contact, factors, errors and CasADi derivatives."""

import math

import casadi as ca
import numpy as np
import pytest

import gearopt as go
from gearopt.errors import GearoptInputError
from gearopt.rating import root_stress as rs
from gearopt.rating.tooth_profile import GeneratedTooth


def spur(z=(38, 76), x=(0.0, 0.0), b=25.0, m=3.0):
    return go.GearPair.from_profile_shifts(teeth=z, profile_shifts=x, module_mm=m, face_width_mm=b)


@pytest.mark.parametrize("z,x,rho", [(12, 0.5, 0.38), (17, -0.2, 0.38), (20, 0.0, 0.38), (38, 0.3124, 0.38),
                                     (76, 0.1118, 0.38), (200, 0.0, 0.38), (24, 0.6757, 0.25), (30, 0.0, 0.2)])
def test_critical_section_matches_the_generated_fillet(z, x, rho):
    # independent check: generate the trochoidal fillet numerically (tool tip circle enveloped as the rack rolls),
    # find the point whose tangent makes 30 deg with the centreline, measure chord, height and curvature there
    tooth = GeneratedTooth(z, 3.0, x, root_radius_coefficient=rho)
    ref = tooth.tangent_point(30.0)
    cs = rs.critical_section_iso6336(z, 3.0, x, root_radius_coefficient=rho)
    assert cs["s_Fn_mm"] == pytest.approx(ref["chord_mm"], rel=1e-7)
    assert cs["section_height_mm"] == pytest.approx(ref["height_mm"], rel=1e-9)
    assert cs["rho_F_mm"] == pytest.approx(ref["curvature_radius_mm"], rel=1e-5)  # finite-difference curvature


def test_generated_fillet_meets_the_involute_at_the_pair_root_form_circle():
    pair = spur(x=(0.3124, 0.1122))
    g = pair.geometry()
    for i, (z, x) in enumerate(zip(pair.teeth, pair.profile_shifts)):
        tooth = GeneratedTooth(z, 3.0, x)
        assert 2 * tooth.form_radius_mm() == pytest.approx(g["root_form_diameter_mm"][i], rel=1e-12)
        # continuity of the profile at the joint
        fx, fy = tooth.fillet_point(tooth.fillet_end_phi())
        ix, iy = tooth.involute_point(tooth.form_radius_mm())
        assert (float(fx), float(fy)) == pytest.approx((float(ix), float(iy)), abs=1e-9)
        # bottom of the fillet is the root circle
        bx, by = tooth.fillet_point(tooth.fillet_bottom_phi())
        assert math.hypot(float(bx), float(by)) == pytest.approx(0.5 * g["root_diameter_mm"][i], rel=1e-13)


def test_unrolled_newton_converges_over_the_design_range():
    # reference: ISO 6336-3's own fixed-point iteration theta <- 2G/z_n tan(theta) - H from pi/6, run to the limit
    worst = 0.0
    for z in (8, 10, 12, 17, 24, 38, 76, 150, 400):
        for x in np.linspace(-0.6, 1.2, 10):
            cs = rs.critical_section_iso6336(z, 1.0, x)
            G, H = cs["G"], cs["H"]
            theta = math.pi / 6
            for _ in range(2000):
                theta = 2 * G / z * math.tan(theta) + (-H)
            assert abs(2 * G / (z * math.cos(theta) ** 2)) < 1  # the fixed point attracts: ISO's iteration is valid
            worst = max(worst, abs(cs["theta_rad"] - theta))
            assert abs(cs["residual"]) < 1e-13
    assert worst < 1e-12


def _load_line_by_geometry(tooth, radius, section_height):
    """Load line of a normal force at the involute point of ``radius``: tangent to the base circle (the involute's
    normal), pointing towards the tooth centreline. Returns (h_F, alpha_F) from plane geometry alone."""
    px, py = (float(v) for v in tooth.involute_point(radius))
    # base-circle tangent point T with (P - T) . T = 0 on the side of the centreline
    d = math.hypot(px, py)
    ang_p = math.atan2(px, py)  # polar angle from the centreline (towards +x)
    for sign in (+1, -1):
        a = ang_p + sign * math.acos(tooth.r_b / d)
        tx, ty = tooth.r_b * math.sin(a), tooth.r_b * math.cos(a)
        dx, dy = tx - px, ty - py
        if dx < 0:  # heading towards the centreline (x decreasing)
            s = -px / dx
            y_int = py + s * dy
            alpha_f = math.atan2(abs(dy), abs(dx)) * (1 if dy < 0 else -1)
            return y_int - section_height, alpha_f
    raise AssertionError("no load line towards the centreline")


@pytest.mark.parametrize("z,x", [(20, 0.0), (38, 0.3124), (76, 0.1118), (24, 0.6757)])
def test_load_angle_and_moment_arm_match_plane_geometry(z, x):
    tooth = GeneratedTooth(z, 3.0, x)
    cs = rs.critical_section_iso6336(z, 3.0, x)
    for radius in np.linspace(tooth.form_radius_mm() + 0.2, tooth.r_a, 5):
        rho = math.sqrt(radius ** 2 - tooth.r_b ** 2)
        p = rs._load_point(cs, z, 3.0, x, 20.0, 0.38, tooth.r_b, rho)
        h_ref, a_ref = _load_line_by_geometry(tooth, radius, cs["section_height_mm"])
        assert p["h_F_mm"] == pytest.approx(h_ref, rel=1e-10, abs=1e-10)
        assert p["alpha_F_rad"] == pytest.approx(a_ref, abs=1e-12)


@pytest.mark.parametrize("helix", [0.0, 12.0])
def test_load_point_stress_reproduces_method_b_at_the_outer_single_contact(helix):
    pair = go.GearPair.from_profile_shifts(teeth=(24, 61), profile_shifts=(0.3, 0.1), module_mm=3.0,
                                           helix_angle_deg=helix, face_width_mm=(30.0, 28.0))
    T = 250.0
    r = rs.root_stress_iso6336(pair, T)
    ft = r["F_t_N"]
    for gear in (1, 2):
        d = r[f"gear{gear}"]
        w = ft / (d["face_width_mm"] * math.cos(math.radians(20.0)))
        vg = rs.virtual_gear(pair, gear)
        sigma = rs.root_stress_at_load_point(pair, gear, w,
                                             load_roll_length_mm=vg["outer_single_contact_roll_length_mm"])
        assert sigma * d["Y_beta"] == pytest.approx(d["sigma_F0_MPa"], rel=1e-12)
        via_diameter = rs.root_stress_at_load_point(pair, gear, w, load_diameter_mm=d["load_diameter_mm"])
        assert via_diameter == pytest.approx(sigma, rel=1e-10)


def test_spur_outer_single_contact_is_the_pair_hpstc():
    pair = spur(x=(0.3124, 0.1122))
    g = pair.geometry()
    for gear in (1, 2):
        vg = rs.virtual_gear(pair, gear)
        assert vg["outer_single_contact_roll_length_mm"] == pytest.approx(g["hpstc_roll_length_mm"][gear - 1],
                                                                          rel=1e-12)


def test_load_point_stress_is_vectorised_and_grows_towards_the_tip():
    pair = spur(x=(0.3124, 0.1122))
    g = pair.geometry()
    rolls = np.linspace(g["sap_roll_length_mm"][0], g["eap_roll_length_mm"][0], 25)
    sig = rs.root_stress_at_load_point(pair, 1, 100.0, load_roll_length_mm=rolls)
    assert sig.shape == rolls.shape
    loop = [rs.root_stress_at_load_point(pair, 1, 100.0, load_roll_length_mm=float(r)) for r in rolls]
    assert sig == pytest.approx(np.array(loop), rel=1e-14)
    assert np.all(np.diff(sig) > 0)
    # linear in the load
    assert rs.root_stress_at_load_point(pair, 1, 300.0, load_roll_length_mm=rolls) == pytest.approx(3 * sig)


def test_iso_factors():
    assert rs.helix_angle_factor_root(0.5, 12.0) == pytest.approx(1 - 0.5 * 12 / 120)
    assert rs.helix_angle_factor_root(1.7, 40.0) == pytest.approx(1 - 30 / 120)
    assert rs.rim_thickness_factor(None) == 1.0 and rs.rim_thickness_factor(1.3) == 1.0
    assert rs.rim_thickness_factor(0.8) == pytest.approx(1.6 * math.log(2.242 / 0.8))
    assert rs.rim_thickness_factor(1.2 - 1e-9) == pytest.approx(1.0, abs=1e-3)  # nearly continuous at 1.2
    assert rs.deep_tooth_factor(2.3) == 1.0
    assert rs.deep_tooth_factor(2.3, accuracy_grade=4) == pytest.approx(-0.666 * 2.3 + 2.366)
    assert rs.deep_tooth_factor(2.8, accuracy_grade=3) == 0.7
    with pytest.raises(GearoptInputError, match="rim_backup_ratio"):
        rs.rim_thickness_factor(0.4)


def test_rating_assembly_permissible_stress_and_safety():
    pair = spur(z=(20, 40), x=(0.2, 0.0), b=(30.0, 20.0))
    r = rs.root_stress_iso6336(pair, 150.0, K_A=1.25, K_Fbeta=1.1, life_factor=(1.2, 1.0), S_Fmin=1.4,
                               material=("20MnCr5", "42CrMo4"), rim_backup_ratio=(None, 0.9))
    g1, g2 = r["gear1"], r["gear2"]
    ft = 2000 * 150.0 / 60.0
    assert r["F_t_N"] == pytest.approx(ft)
    # wider gear: b at most the narrower face + one module each side
    assert g1["face_width_mm"] == pytest.approx(26.0) and g2["face_width_mm"] == pytest.approx(20.0)
    assert g1["sigma_F0_MPa"] == pytest.approx(ft / (26.0 * 3.0) * g1["Y_F"] * g1["Y_S"], rel=1e-14)
    assert g2["Y_B"] == pytest.approx(1.6 * math.log(2.242 / 0.9))
    assert g1["sigma_F_MPa"] == pytest.approx(g1["sigma_F0_MPa"] * 1.25 * 1.1, rel=1e-14)
    assert g1["sigma_FP_MPa"] == pytest.approx(500 * 2 * 1.2 / 1.4) and g2["sigma_FP_MPa"] == pytest.approx(630 / 1.4)
    assert g2["safety_factor"] == pytest.approx(315 * 2 / g2["sigma_F_MPa"], rel=1e-14)
    assert r["safety_factor_min"] == min(g1["safety_factor"], g2["safety_factor"])
    assert 1.0 <= g1["q_s"] < 8.0 and 1.0 <= g2["q_s"] < 8.0  # inside Y_S's fitted range


def test_more_teeth_and_positive_shift_lower_the_form_factor():
    # the trend of ISO 6336-3's Y_F graphs: Y_F falls with z and with x
    yf = [rs.root_stress_iso6336(spur(z=(z, 100)), 100.0)["gear1"]["Y_F"] for z in (17, 25, 40, 80)]
    assert np.all(np.diff(yf) < 0)
    yx = [rs.root_stress_iso6336(spur(z=(20, 40), x=(x, 0.0)), 100.0)["gear1"]["Y_F"] for x in (-0.2, 0.0, 0.3, 0.6)]
    assert np.all(np.diff(yx) < 0)


def test_bad_input_is_named():
    pair = spur()
    with pytest.raises(GearoptInputError, match="exactly one"):
        rs.root_stress_at_load_point(pair, 1, 10.0)
    with pytest.raises(GearoptInputError, match="gear"):
        rs.root_stress_at_load_point(pair, 3, 10.0, load_roll_length_mm=20.0)
    with pytest.raises(GearoptInputError, match="load_roll_length_mm"):
        rs.root_stress_at_load_point(pair, 1, 10.0, load_roll_length_mm=np.array([20.0, 500.0]))
    with pytest.raises(GearoptInputError, match="load_diameter_mm"):
        rs.root_stress_at_load_point(pair, 1, 10.0, load_diameter_mm=100.0)  # below the base circle 107.1
    with pytest.raises(GearoptInputError, match="load_N_per_mm"):
        rs.root_stress_at_load_point(pair, 1, -1.0, load_roll_length_mm=20.0)
    with pytest.raises(GearoptInputError, match="torque_Nm"):
        rs.root_stress_iso6336(pair, -5.0)


def test_symbolic_equals_numeric_and_derivatives_match_finite_differences():
    x1, T, rho = ca.SX.sym("x1"), ca.SX.sym("T"), ca.SX.sym("rho")

    def build(xv, Tv, rv):
        pair = go.GearPair.from_centre_distance(teeth=(38, 76), centre_distance_mm=172.2406, module_mm=3.0,
                                                face_width_mm=(30.0, 25.0), profile_shift1=xv)
        r = rs.root_stress_iso6336(pair, Tv, K_A=1.25)
        at = rs.root_stress_at_load_point(pair, 1, 100.0, load_roll_length_mm=rv)
        return ca.vertcat(r["gear1"]["sigma_F_MPa"], r["gear2"]["sigma_F_MPa"], r["gear1"]["safety_factor"],
                          r["gear2"]["Y_F"], r["gear1"]["Y_S"], at)

    expr = build(x1, T, rho)
    v = ca.vertcat(x1, T, rho)
    f = ca.Function("f", [v], [expr])
    jac = ca.Function("j", [v], [ca.jacobian(expr, v)])
    point = np.array([0.3124, 190.0, 25.0])
    numeric = np.array(ca.DM(build(*point)), dtype=float).ravel()
    assert np.array(f(point)).ravel() == pytest.approx(numeric, rel=1e-12)
    J = np.array(jac(point))
    for k, h in enumerate((1e-6, 1e-3, 1e-5)):
        e = np.zeros(3)
        e[k] = h
        fd = (np.array(f(point + e)) - np.array(f(point - e))).ravel() / (2 * h)
        assert J[:, k] == pytest.approx(fd, rel=2e-6, abs=1e-8)
    assert np.all(np.isfinite(J))


def test_virtual_roll_length_map():
    spur_pair = spur(x=(0.3124, 0.1122))
    rho = np.array([20.0, 25.0, 30.0])
    assert rs.virtual_roll_length_mm(spur_pair, 1, rho) == pytest.approx(rho, rel=1e-13)  # identity for spur
    pair = go.GearPair.from_profile_shifts(teeth=(24, 61), profile_shifts=(0.3, 0.1), module_mm=3.0,
                                           helix_angle_deg=12.0, face_width_mm=30.0)
    g = pair.geometry()
    for gear in (1, 2):
        i = gear - 1
        vg = rs.virtual_gear(pair, gear)
        rho_at = math.sqrt(g["tip_diameter_mm"][i] ** 2 - g["base_diameter_mm"][i] ** 2) / 2
        outer_t = rho_at - (g["transverse_contact_ratio"] - 1) * g["base_pitch_mm"]
        assert rs.virtual_roll_length_mm(pair, gear, rho_at) == pytest.approx(vg["tip_roll_length_mm"], rel=1e-13)
        assert rs.virtual_roll_length_mm(pair, gear, outer_t) == pytest.approx(
            vg["outer_single_contact_roll_length_mm"], rel=1e-12)
