"""GearPair: analytic limits, round trips, symbolic = numeric, derivatives, checks and error messages.

Published worked examples (KHK, ISO/TR 6336-30, ...) are in tests/validation/test_geometry_published.py.
"""

import math

import casadi as ca
import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import gearopt as go
from gearopt.geometry import PairTolerances, iso_tr_4467_shift_limits, shift_split_iso_tr_4467
from gearopt.errors import GearoptInputError, GeometryError


def spur(z1=20, z2=40, x=(0.0, 0.0), **kw):
    return go.GearPair.from_profile_shifts(teeth=(z1, z2), profile_shifts=x, module_mm=kw.pop("module_mm", 2.0),
                                           pressure_angle_deg=20.0, helix_angle_deg=kw.pop("helix_angle_deg", 0.0),
                                           face_width_mm=20.0, **kw)


def test_standard_spur_pair_analytic():
    # unshifted spur pair: a = m(z1+z2)/2, alpha_w = alpha, d_a = m(z+2), d_f = m(z-2.5), s = pi m / 2
    g = spur().geometry()
    assert g["centre_distance_mm"] == pytest.approx(60.0, abs=1e-12)
    assert g["working_pressure_angle_deg"] == pytest.approx(20.0, abs=1e-10)
    assert g["tip_diameter_mm"] == pytest.approx((44.0, 84.0))
    assert g["root_diameter_mm"] == pytest.approx((35.0, 75.0))
    assert g["tooth_thickness_mm"][0] == pytest.approx(math.pi, abs=1e-12)
    assert g["tip_shortening"] == pytest.approx(0.0, abs=1e-12)
    # contact ratio by the textbook formula for standard gears (Shigley eq. 13-8 form written with radii)
    rb = [10 * 2 * math.cos(math.radians(20)), 20 * 2 * math.cos(math.radians(20))]
    ra = [22.0, 42.0]
    lab = math.sqrt(ra[0] ** 2 - rb[0] ** 2) + math.sqrt(ra[1] ** 2 - rb[1] ** 2) - 60 * math.sin(math.radians(20))
    assert g["transverse_contact_ratio"] == pytest.approx(lab / (math.pi * 2 * math.cos(math.radians(20))))


def test_rack_limit_of_undercut_is_17_teeth():
    # KHK: theoretical minimum number of teeth without undercut for alpha 20 deg: z = 2/sin^2(20) = 17.1
    # Our basic rack (h_fP 1.25, rho_fP 0.38) has its straight flank end 1.25 - 0.38 (1 - sin 20) = 0.99997 m below
    # the datum; with a sharp-tipped rack of addendum 1.0 the classical x_min = 1 - z sin^2(alpha)/2 results.
    h_ff = 1.25 - 0.38 * (1 - math.sin(math.radians(20)))
    g = spur(17, 40).geometry()
    assert g["undercut_limit_profile_shift"][0] == pytest.approx(h_ff - 17 * math.sin(math.radians(20)) ** 2 / 2)
    sharp = spur(17, 40, dedendum_coefficient=1.0, root_radius_coefficient=0.0).geometry()
    assert sharp["undercut_limit_profile_shift"][0] == pytest.approx(1 - 17 * math.sin(math.radians(20)) ** 2 / 2)
    assert g["undercut_limit_profile_shift"][0] > 0 > spur(18, 40).geometry()["undercut_limit_profile_shift"][0]


def test_path_points_are_ordered_and_consistent():
    g = spur(24, 60, (0.2, 0.1)).geometry()
    a, b, c, d, e = (g[f"{k}_roll_length_mm"][0] for k in ("sap", "lpstc", "pitch_point", "hpstc", "eap"))
    assert a < b < c < d < e
    assert e - a == pytest.approx(g["length_of_path_of_contact_mm"])
    assert d - a == pytest.approx(g["base_pitch_mm"]) and e - b == pytest.approx(g["base_pitch_mm"])
    # the pitch point lies on the working pitch circle of both gears
    assert g["pitch_point_diameter_mm"] == pytest.approx(g["working_pitch_diameter_mm"])
    # gear 2's SAP is met where gear 1's tip (EAP) is
    assert g["eap_diameter_mm"][0] == pytest.approx(g["tip_diameter_mm"][0])
    assert g["eap_diameter_mm"][1] == pytest.approx(g["tip_diameter_mm"][1])


@settings(max_examples=60, deadline=None)
@given(z1=st.integers(14, 60), z2=st.integers(14, 120), x1=st.floats(-0.3, 0.8), x2=st.floats(-0.3, 0.8),
       beta=st.sampled_from([0.0, 8.0, 15.0, 30.0]))
def test_round_trip_shifts_centre_distance_shifts(z1, z2, x1, x2, beta):
    # (very negative sums with few teeth have no working pressure angle: GeometryError, tested elsewhere)
    assume(x1 + x2 >= -0.4)
    p = go.GearPair.from_profile_shifts(teeth=(z1, z2), profile_shifts=(x1, x2), module_mm=3.0,
                                        helix_angle_deg=beta, face_width_mm=20.0)
    a = p.geometry()["centre_distance_mm"]
    q = go.GearPair.from_centre_distance(teeth=(z1, z2), centre_distance_mm=a, module_mm=3.0, helix_angle_deg=beta,
                                         face_width_mm=20.0, profile_shift1=x1)
    assert q.geometry()["profile_shifts"][1] == pytest.approx(x2, abs=1e-10)
    assert q.geometry()["working_pressure_angle_deg"] == pytest.approx(p.geometry()["working_pressure_angle_deg"],
                                                                        abs=1e-9)


@settings(max_examples=40, deadline=None)
@given(z1=st.integers(14, 60), z2=st.integers(14, 120), x1=st.floats(-0.3, 0.8), x2=st.floats(-0.3, 0.8))
def test_zero_backlash_at_nominal_and_tip_shortening_keeps_clearance(z1, z2, x1, x2):
    # x1 + x2 must keep the working pressure angle above 0: limit -0.0205 (z1 + z2) >= -0.573 for z1 + z2 >= 28
    assume(x1 + x2 > -0.5)
    g = spur(z1, z2, (x1, x2)).geometry()
    assert g["normal_backlash_min_mm"] == pytest.approx(0.0, abs=1e-10)
    # with tip shortening k the bottom clearance is the basic-rack clearance (h_fP - h_aP) m_n on both gears
    assert g["bottom_clearance_mm"] == pytest.approx((0.25 * 2.0, 0.25 * 2.0), abs=1e-10)
    assert g["tip_shortening"] >= -1e-12  # x1 + x2 >= y always (the shortening is never negative)


def test_backlash_linearised_agrees_for_small_changes():
    # ISO/TR 10064-2: j_bn ~ 2 Delta_a sin(alpha_wt) cos(beta_b) - (E_sn1 + E_sn2) cos(alpha_n) for small changes
    p = go.GearPair.from_profile_shifts(teeth=(25, 50), profile_shifts=(0.2, 0.1), module_mm=3.0,
                                        helix_angle_deg=12.0, face_width_mm=20.0)
    g0 = p.geometry()
    tol = PairTolerances(centre_distance_allowance_mm=(0.01, 0.03),
                            tooth_thickness_upper_allowance_um=(-40.0, -50.0),
                            tooth_thickness_lower_allowance_um=(-80.0, -90.0))
    g = p.with_options(tolerances=tol).geometry()
    aw, bb, an = (math.radians(g0[k]) for k in ("working_pressure_angle_deg", "base_helix_angle_deg",
                                                 "pressure_angle_deg"))
    lin_min = 2 * 0.01 * math.sin(aw) * math.cos(bb) + 0.090 * math.cos(an)
    lin_max = 2 * 0.03 * math.sin(aw) * math.cos(bb) + 0.170 * math.cos(an)
    assert g["normal_backlash_min_mm"] == pytest.approx(lin_min, rel=2e-3)
    assert g["normal_backlash_max_mm"] == pytest.approx(lin_max, rel=2e-3)
    # worst-case contact ratio: larger centre distance lowers it
    assert g["worst_case_transverse_contact_ratio"] < g0["transverse_contact_ratio"]


def test_helical_transverse_relations():
    g = spur(20, 40, helix_angle_deg=30.0, module_mm=3.0).geometry()
    assert g["transverse_module_mm"] == pytest.approx(3.0 / math.cos(math.radians(30)))
    assert math.tan(math.radians(g["transverse_pressure_angle_deg"])) == pytest.approx(
        math.tan(math.radians(20)) / math.cos(math.radians(30)))
    assert g["overlap_contact_ratio"] == pytest.approx(20 * math.sin(math.radians(30)) / (math.pi * 3.0))
    assert g["total_contact_ratio"] == pytest.approx(g["transverse_contact_ratio"] + g["overlap_contact_ratio"])
    # base pitch in the normal plane = transverse base pitch times cos(beta_b)
    assert g["normal_base_pitch_mm"] == pytest.approx(g["base_pitch_mm"] * math.cos(
        math.radians(g["base_helix_angle_deg"])))


SYMBOLIC_KEYS = ["centre_distance_mm", "working_pressure_angle_deg", "tip_diameter_mm", "tip_thickness_mm",
                 "transverse_contact_ratio", "worst_case_transverse_contact_ratio", "sap_roll_deg", "hpstc_roll_deg",
                 "normal_backlash_min_mm", "specific_sliding_root", "overlap_contact_ratio"]


def _flat(g, keys):
    out = []
    for k in keys:
        v = g[k]
        out.extend(v if isinstance(v, tuple) else [v])
    return out


def _symbolic_pair():
    x = ca.SX.sym("x", 2)
    m = ca.SX.sym("m")
    b = ca.SX.sym("b")
    beta = ca.SX.sym("beta")
    tol = PairTolerances(centre_distance_allowance_mm=(-0.02, 0.03),
                            tooth_thickness_upper_allowance_um=(-30.0, -30.0),
                            tooth_thickness_lower_allowance_um=(-70.0, -70.0),
                            tip_diameter_allowance_mm=((-0.1, 0.0), (-0.1, 0.0)))
    p = go.GearPair.from_profile_shifts(teeth=(23, 61), profile_shifts=(x[0], x[1]), module_mm=m,
                                        helix_angle_deg=beta, face_width_mm=b, tolerances=tol)
    f = ca.Function("g", [ca.vertcat(x, m, b, beta)], [ca.vertcat(*_flat(p.geometry(), SYMBOLIC_KEYS))])
    return f, tol


def test_symbolic_equals_numeric():
    f, tol = _symbolic_pair()
    for args in ([0.3, 0.1, 3.0, 25.0, 0.0], [-0.2, 0.5, 2.5, 30.0, 12.0], [0.6, 0.6, 4.0, 18.0, 20.0]):
        x1, x2, m, b, beta = args
        num = go.GearPair.from_profile_shifts(teeth=(23, 61), profile_shifts=(x1, x2), module_mm=m,
                                              helix_angle_deg=beta, face_width_mm=b, tolerances=tol).geometry()
        np.testing.assert_allclose(np.array(f(args)).ravel(), _flat(num, SYMBOLIC_KEYS), rtol=1e-11, atol=1e-11)


def test_geometry_derivatives_match_finite_differences():
    f, _ = _symbolic_pair()
    z = ca.SX.sym("z", 5)
    jac = ca.Function("J", [z], [ca.jacobian(f(z), z)])
    x0 = np.array([0.25, 0.15, 3.0, 25.0, 10.0])
    J = np.array(jac(x0))
    h = 1e-6
    for j in range(5):
        e = np.zeros(5)
        e[j] = h * max(1.0, abs(x0[j]))
        fd = (np.array(f(x0 + e)) - np.array(f(x0 - e))).ravel() / (2 * e[j])
        np.testing.assert_allclose(J[:, j], fd, rtol=1e-5, atol=1e-6)


def test_from_centre_distance_symbolic_centre_distance_and_split():
    a = ca.SX.sym("a")
    lam = ca.SX.sym("lam")
    p = go.GearPair.from_centre_distance(teeth=(38, 76), centre_distance_mm=a, module_mm=3.0, shift_split=lam)
    g = p.geometry()
    f = ca.Function("f", [a, lam], [g["profile_shifts"][0], g["sum_profile_shift"]])
    num = go.GearPair.from_centre_distance(teeth=(38, 76), centre_distance_mm=172.24, module_mm=3.0,
                                           shift_split=0.6).geometry()
    x1, sx = (float(v) for v in f(172.24, 0.6))
    assert x1 == pytest.approx(num["profile_shifts"][0], abs=1e-12)
    assert sx == pytest.approx(num["sum_profile_shift"], abs=1e-12)


def test_iso_tr_4467_split_formula():
    # thesis Eq. 3.6: x1 = lambda (z2 - z1)/(z1 + z2) + sum_x z1/(z1 + z2)
    x1, x2 = shift_split_iso_tr_4467((38, 76), 0.4242, 0.5)
    assert x1 == pytest.approx(0.5 * 38 / 114 + 0.4242 * 38 / 114)
    assert x1 + x2 == pytest.approx(0.4242)


def test_iso_tr_4467_limits_thesis_equations():
    assert iso_tr_4467_shift_limits(38) == pytest.approx(((20 - 38) / 60, 0.88))
    assert iso_tr_4467_shift_limits(15) == pytest.approx((0.0375 * 5, 0.65))
    assert iso_tr_4467_shift_limits(76) == (-0.5, 1.0)


# --- checks and errors ---------------------------------------------------------------------------------------------

def test_check_names_pointed_tip_with_limit():
    p = spur(12, 24, (1.2, 0.36), module_mm=3.0)
    with pytest.raises(GeometryError, match=r"profile_shift x1=1\.2000 exceeds the pointed-tooth limit .*z=12") as e:
        p.check(iso_tr_4467_limits=False)
    # the reported limit is where the tip thickness equals 0.2 m_n
    lim = float(str(e.value).split("x1 <= ")[1].split(";")[0])
    # ... with the pair's tip shortening k held fixed (centre distance moved accordingly)
    k = p.geometry()["tip_shortening"]
    q = p.with_options(profile_shifts=(lim, 0.36), centre_distance_mm=54.0 + 3.0 * (lim + 0.36 - k))
    assert q.geometry()["tip_shortening"] == pytest.approx(k, abs=1e-9)
    assert q.geometry()["tip_thickness_mm"][0] == pytest.approx(0.2 * 3.0, abs=1e-4)


def test_check_undercut_and_interference():
    p = spur(12, 24, (0.0, 0.0), module_mm=3.0)  # standard 12-tooth pinion: undercut and interference
    with pytest.raises(GeometryError) as e:
        p.check()
    msg = str(e.value)
    assert "below the undercut limit" in msg and "tip/root interference on gear 1" in msg


def test_check_passes_for_sound_pair_and_contact_ratio_limit_reported():
    p = spur(30, 60, (0.2, 0.0))
    p.check()
    with pytest.raises(GeometryError, match=r"transverse_contact_ratio=1\.\d+ is below the limit 1\.9"):
        p.check(min_contact_ratio=1.9)


def test_unreachable_centre_distance_is_named():
    with pytest.raises(GeometryError, match=r"centre_distance_mm=50\.0000 is unreachable"):
        go.GearPair.from_centre_distance(teeth=(20, 40), centre_distance_mm=50.0, module_mm=2.0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(module_mm=-1.0), "module_mm=-1"),
    (dict(module_mm=2.0, pressure_angle_deg=50.0), "pressure_angle_deg=50"),
    (dict(module_mm=2.0, helix_angle_deg=47.0), "helix_angle_deg=47"),
    (dict(module_mm=2.0, face_width_mm=0.0), r"face_width_mm\[0\]=0"),
])
def test_bad_scalar_inputs_are_named(kwargs, match):
    with pytest.raises(GearoptInputError, match=match):
        go.GearPair.from_profile_shifts(teeth=(20, 40), profile_shifts=(0, 0), **kwargs)


def test_bad_teeth_and_options_are_named():
    with pytest.raises(GearoptInputError, match=r"teeth\[0\]=3 is below the limit 5"):
        go.GearPair.from_profile_shifts(teeth=(3, 40), profile_shifts=(0, 0), module_mm=2.0)
    with pytest.raises(GearoptInputError, match=r"teeth\[1\]=40\.5 must be an integer"):
        go.GearPair.from_profile_shifts(teeth=(20, 40.5), profile_shifts=(0, 0), module_mm=2.0)
    with pytest.raises(GearoptInputError, match="unknown option"):
        go.GearPair.from_profile_shifts(teeth=(20, 40), profile_shifts=(0, 0), module_mm=2.0, tip_shorten=False)
    with pytest.raises(GeometryError, match="sum of profile shifts"):
        go.GearPair.from_profile_shifts(teeth=(20, 40), profile_shifts=(-2.5, -2.5), module_mm=2.0)


def test_symbolic_pair_check_refuses_and_constraints_are_expressions():
    x = ca.SX.sym("x")
    p = go.GearPair.from_profile_shifts(teeth=(20, 40), profile_shifts=(x, 0.0), module_mm=2.0)
    with pytest.raises(GearoptInputError, match="constraints"):
        p.check()
    cons = p.constraints()
    assert all(isinstance(cons[k], ca.SX) for k in ("undercut_margin_1", "tip_thickness_margin_1_mm",
                                                    "contact_ratio_margin", "interference_margin_2_mm"))
    f = ca.Function("f", [x], [cons["undercut_margin_1"]])
    h_ff = 1.25 - 0.38 * (1 - math.sin(math.radians(20)))
    assert float(f(0.3)) == pytest.approx(0.3 - (h_ff - 20 * math.sin(math.radians(20)) ** 2 / 2))


def test_symbolic_tip_diameters_drive_contact_ratio_and_tip_thickness():
    da = ca.SX.sym("da", 2)
    p = go.GearPair.from_profile_shifts(teeth=(30, 60), profile_shifts=(0.2, 0.0), module_mm=3.0,
                                        tip_diameters_mm=(da[0], da[1]))
    g = p.geometry()
    f = ca.Function("f", [da], [g["transverse_contact_ratio"], g["tip_thickness_mm"][0]])
    num = go.GearPair.from_profile_shifts(teeth=(30, 60), profile_shifts=(0.2, 0.0), module_mm=3.0,
                                          tip_diameters_mm=(96.5, 185.0)).geometry()
    eps, s_a = (float(v) for v in f([96.5, 185.0]))
    assert eps == pytest.approx(num["transverse_contact_ratio"], abs=1e-12)
    assert s_a == pytest.approx(num["tip_thickness_mm"][0], abs=1e-12)
    # a smaller tip shortens the path of contact by the change of its roll length (d rho_a / d d_a = d_a/(4 rho_a))
    rho_a = math.sqrt(96.5**2 - num["base_diameter_mm"][0] ** 2) / 2
    d_eps = float(ca.Function("d", [da], [ca.jacobian(g["transverse_contact_ratio"], da)])([96.5, 185.0])[0])
    assert d_eps == pytest.approx(96.5 / (4 * rho_a) / num["base_pitch_mm"], rel=1e-9)
