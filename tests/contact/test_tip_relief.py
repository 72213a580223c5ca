"""Tip-relief physics (thesis section 3.9.1): Hertz half-width against published elastic coefficients, the approach
formulas against quadrature of the textbook line-contact stress field, tooth deflection limits, the pair deflection
against ISO 6336-1's single stiffness, the pi/(2z) term of Eq. 3.36, symbolic = numeric, derivatives, Table 3.7."""

import math

import casadi as ca
import numpy as np
import pytest
from scipy.integrate import quad

import gearopt as go
from gearopt.contact import tip_relief as tr
from gearopt.errors import GearoptInputError
from gearopt.geometry import involute as inv

E = 206000.0
NU = 0.3
K_PAIR = 2.0 * (1.0 - NU ** 2) / (math.pi * E)  # 2(1-nu^2)/(pi E) [mm per N/mm]


def spur(z1=38, z2=76, x=(0.0, 0.0), b=25.0, m=3.0):
    return go.GearPair.from_profile_shifts(teeth=(z1, z2), profile_shifts=x, module_mm=m, face_width_mm=b)


def torque_for_load(pair, w_N_per_mm, driving_gear=1):
    g = pair.geometry()
    return w_N_per_mm * min(g["face_width_mm"]) * 0.5 * g["base_diameter_mm"][driving_gear - 1] / 1000.0


# ----------------------------------------------------------------------------------------------------------------
# Hertz half-width
# ----------------------------------------------------------------------------------------------------------------

def test_half_width_matches_closed_form_and_iso_elastic_factor():
    w, r1, r2 = 150.0, 19.5, 39.0
    b = tr.hertz_half_width_mm(w, r1, r2, E, NU)
    r_eq = r1 * r2 / (r1 + r2)
    # closed form b = sqrt(8 w R (1-nu^2)/(pi E)) (Shigley, contact of cylinders, equal materials)
    assert b == pytest.approx(math.sqrt(8 * w * r_eq * (1 - NU ** 2) / (math.pi * E)), rel=1e-14)
    # ISO 6336-2: p_H = Z_E sqrt(w/R) with the published elasticity factor Z_E = 189.8 sqrt(N/mm^2) for steel/steel
    # (E 206000 MPa, nu 0.3); Hertz: p_max = 2 w/(pi b). Z_E is printed to 4 digits.
    assert 2 * w / (math.pi * b) == pytest.approx(189.8 * math.sqrt(w / r_eq), rel=3e-4)


def test_half_width_in_us_units_matches_shigley_elastic_coefficient():
    # Shigley's MED, Table 14-8: elastic coefficient C_p = 2300 sqrt(psi) for steel/steel (E 30 Mpsi, nu 0.30),
    # sigma_C = C_p sqrt(w/R) = p_max of the cylinder contact. The formula is unit-consistent (lbf/in, in, psi).
    w, r1, r2 = 2000.0, 0.9, 2.1
    b = tr.hertz_half_width_mm(w, r1, r2, 30e6, 0.30)
    r_eq = r1 * r2 / (r1 + r2)
    assert 2 * w / (math.pi * b) == pytest.approx(2300.0 * math.sqrt(w / r_eq), rel=5e-3)  # C_p given to 2 digits


def test_half_width_dissimilar_materials_and_symmetry():
    b12 = tr.hertz_half_width_mm(100.0, 10.0, 30.0, (206000.0, 110000.0), (0.3, 0.34))
    b21 = tr.hertz_half_width_mm(100.0, 30.0, 10.0, (110000.0, 206000.0), (0.34, 0.3))
    assert b12 == pytest.approx(b21, rel=1e-14)
    assert b12 > tr.hertz_half_width_mm(100.0, 10.0, 30.0)  # the softer body widens the band


# ----------------------------------------------------------------------------------------------------------------
# approach / compression: quadrature of the textbook stress field
# ----------------------------------------------------------------------------------------------------------------

def _axis_stresses(depth, b, p0, nu):
    """Stresses on the load axis below a Hertz line contact (Shigley's MED, 'Contact stresses', cylinders;
    Johnson 1985 ch. 4): x along the cylinder axis (plane strain), y across the band, z = depth."""
    t = depth / b
    s = math.sqrt(1.0 + t * t)
    return -2 * nu * p0 * (s - t), -p0 * ((1 + 2 * t * t) / s - 2 * t), -p0 / s


def _axial_strain(sx, sy, sz, e, nu):
    return (sz - nu * (sx + sy)) / e


def _half_plane_compression_mm(w, b, depth, e=E, nu=NU):
    p0 = 2 * w / (math.pi * b)
    return -quad(lambda z: _axial_strain(*_axis_stresses(z, b, p0, nu), e, nu), 0.0, depth, limit=200,
                 points=[b, 10 * b])[0]


def _disc_centre_approach_mm(w, b, radius, e=E, nu=NU):
    """Half the diametral compression of a disc between two Hertz contacts: both half-plane fields plus the uniform
    in-plane tension w/(pi R) that frees the boundary (disc solution, Timoshenko & Goodier), integrated to the centre."""
    p0 = 2 * w / (math.pi * b)
    s0 = w / (math.pi * radius)

    def strain(z):
        top = _axis_stresses(z, b, p0, nu)
        bottom = _axis_stresses(2 * radius - z, b, p0, nu)
        sx, sy, sz = (top[k] + bottom[k] for k in range(3))
        return _axial_strain(sx + 2 * nu * s0, sy + s0, sz + s0, e, nu)

    return -quad(strain, 0.0, radius, limit=200, points=[b, 10 * b])[0]


@pytest.mark.parametrize("depth_over_b", [20.0, 50.0])
def test_weber_compression_equals_integrated_strain(depth_over_b):
    w, b = 120.0, 0.1
    depth = depth_over_b * b
    numeric_um = 1000 * _half_plane_compression_mm(w, b, depth)
    assert tr.hertz_compression_weber_um(w, b, depth, E, NU) == pytest.approx(numeric_um, rel=1e-3)


def test_cylinder_approach_equals_integrated_disc_strain():
    w, r1, r2 = 150.0, 19.5, 39.0
    b = tr.hertz_half_width_mm(w, r1, r2, E, NU)
    numeric_um = 1000 * (_disc_centre_approach_mm(w, b, r1) + _disc_centre_approach_mm(w, b, r2))
    assert tr.hertz_approach_cylinders_um(w, r1, r2, E, NU) == pytest.approx(numeric_um, rel=1e-3)
    # the brief's closed form: 2w(1-nu^2)/(pi E) (ln(4 rho1/b) + ln(4 rho2/b) - 1)
    closed = 1000 * K_PAIR * w * (math.log(4 * r1 / b) + math.log(4 * r2 / b) - 1)
    assert tr.hertz_approach_cylinders_um(w, r1, r2, E, NU) == pytest.approx(closed, rel=1e-12)


def test_load_sensitivity_of_the_approach_and_thesis_eq_3_28():
    # Elasticity fixes d(delta/w)/d ln(w) = -2(1-nu^2)/(pi E) for the two flanks of a line contact (b ~ sqrt(w)),
    # whatever the far geometry. Weber's and the cylinders' forms have it; thesis Eq. 3.28 has 0.39 of it.
    pair = spur()
    slopes = {}
    for model in tr.HERTZ_MODELS:
        vals = []
        for w in (50.0, 200.0):
            p = tr.min_tip_relief_um(pair, torque_for_load(pair, w), parts=True, hertz_model=model)
            vals.append(p["hertz_deformation_um"][0] / 1000 / w)
        slopes[model] = (vals[1] - vals[0]) / math.log(4.0)
    assert slopes["weber"] == pytest.approx(-K_PAIR, rel=1e-9)
    assert slopes["cylinders"] == pytest.approx(-K_PAIR, rel=1e-9)
    assert slopes["thesis"] == pytest.approx(-0.39 * K_PAIR, rel=1e-9)


def test_thesis_eq_3_28_is_close_to_one_flank_of_weber():
    # The printed bracket 1.27 + 0.78 ln(m/b) vs Weber's ONE-body bracket ln(2h/b) - nu/(2(1-nu)) with h = pi m/4
    m = 3.0
    for m_over_b in (20.0, 50.0, 100.0):
        b = m / m_over_b
        one_flank = tr.hertz_compression_weber_um(100.0, b, math.pi * m / 4, E, NU)
        assert tr.hertz_approach_thesis_um(100.0, b, m, E, NU) == pytest.approx(one_flank, rel=0.12)
        # ... and about half the two-flank approach (Weber, both teeth at that depth)
        assert tr.hertz_approach_thesis_um(100.0, b, m, E, NU) < 0.6 * 2 * one_flank


# ----------------------------------------------------------------------------------------------------------------
# tooth deflection (Markovic & Vrcan fit)
# ----------------------------------------------------------------------------------------------------------------

def test_tooth_deflection_is_linear_in_load_compliance_and_inverse_face_width():
    pair = spur()
    T = torque_for_load(pair, 100.0)
    base = tr.min_tip_relief_um(pair, T, parts=True)["tooth_deflection_um"]
    double_load = tr.min_tip_relief_um(pair, 2 * T, parts=True)["tooth_deflection_um"]
    stiffer = tr.min_tip_relief_um(pair, T, E_MPa=2 * E, parts=True)["tooth_deflection_um"]
    wider = tr.min_tip_relief_um(spur(b=50.0), T, parts=True)["tooth_deflection_um"]
    nu0 = tr.min_tip_relief_um(pair, T, poisson=0.0, parts=True)["tooth_deflection_um"]
    for i in range(2):
        assert double_load[i] == pytest.approx(2 * base[i], rel=1e-12)
        assert stiffer[i] == pytest.approx(base[i] / 2, rel=1e-12)
        assert wider[i] == pytest.approx(base[i] / 2, rel=1e-12)
        assert nu0[i] == pytest.approx(base[i] / (1 - NU ** 2), rel=1e-12)  # plane strain (1 - nu^2)


def _pitch_tooth_compliance(z, m=3.0, with_body=True):
    pair = spur(z, z, b=20.0, m=m)
    p = tr.min_tip_relief_um(pair, torque_for_load(pair, 100.0), parts=True)
    delta = p["tooth_deflection_um"][0]
    if not with_body:  # remove the gear-body term D of Eq. 3.33
        delta -= 1000 * 100.0 * (1 - NU ** 2) / E * tr.markovic_vrcan_coefficients(z, 0.0, m)[3]
    return delta


def test_more_teeth_give_a_stiffer_tooth():
    teeth = [17, 20, 24, 30, 38, 50, 76, 100, 150, 200]
    tooth_only = [_pitch_tooth_compliance(z, with_body=False) for z in teeth]
    assert all(a > b for a, b in zip(tooth_only, tooth_only[1:]))
    # with the gear-body term D = -1.06 + 0.638 ln(m z), which grows with the gear, the total still falls up to z ~ 40
    total = [_pitch_tooth_compliance(z) for z in teeth[:5]]
    assert all(a > b for a, b in zip(total, total[1:]))


def test_deflection_grows_towards_the_tip():
    pair = spur(24, 60, x=(0.2, 0.1))
    T = torque_for_load(pair, 100.0)
    d = {cp: tr.min_tip_relief_um(pair, T, parts=True, contact_point=cp) for cp in tr.CONTACT_POINTS}
    for i in range(2):
        assert d["pitch"]["tooth_deflection_um"][i] < d["hpstc"]["tooth_deflection_um"][i] \
            < d["tip"]["tooth_deflection_um"][i]
        assert d["pitch"]["load_height_modules"][i] < d["hpstc"]["load_height_modules"][i] \
            < d["tip"]["load_height_modules"][i]


# ISO 6336-1 Method B coefficients C1..C9 of q' [mm um/N] (docs/default-data.md sec. 1.1, [V])
_ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)


def _iso_single_stiffness(z1, z2, x1=0.0, x2=0.0):
    c = _ISO_C
    q = c[0] + c[1] / z1 + c[2] / z2 + c[3] * x1 + c[4] * x1 / z1 + c[5] * x2 + c[6] * x2 / z2 + c[7] * x1 ** 2 \
        + c[8] * x2 ** 2
    c_th = 1.0 / q
    return c_th, c_th * 0.8 * 0.975  # c'_th; c' = c'_th C_M C_R C_B (solid discs, h_fP = 1.25 m, alpha 20 deg)


@pytest.mark.parametrize("z1,z2", [(20, 20), (24, 24), (20, 40), (38, 76)])
def test_pair_deflection_at_pitch_point_is_of_iso_single_stiffness_order(z1, z2):
    # Total deflection of one loaded pair at the pitch point (Hertz + both teeth) = C_t1 + C_t2 vs ISO 6336-1's
    # w/c'. ISO's own theoretical c'_th and measured-corrected c' = 0.78 c'_th bracket real spur gears; we accept
    # the band [0.85 w/c'_th, 1.15 w/c'] (15 % beyond each end for the Method B fit's scatter). w = 150 N/mm keeps
    # F_t/b above ISO's 100 N/mm light-load threshold.
    pair = spur(z1, z2, b=20.0)
    w = 150.0
    ct = tr.min_tip_relief_um(pair, torque_for_load(pair, w))
    total = ct[0] + ct[1]
    c_th, c_iso = _iso_single_stiffness(z1, z2)
    assert 0.85 * w / c_th <= total <= 1.15 * w / c_iso
    # the split: C_t1 + C_t2 = delta_b1 + delta_b2 + delta_H
    p = tr.min_tip_relief_um(pair, torque_for_load(pair, w), parts=True)
    assert total == pytest.approx(sum(p["tooth_deflection_um"]) + p["hertz_deformation_um"][0], rel=1e-12)


# ----------------------------------------------------------------------------------------------------------------
# the pi/(2z) term of Eq. 3.36
# ----------------------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("z,x", [(17, 0.0), (38, 0.3124), (76, 0.1122)])
def test_half_tooth_angle_reproduces_the_iso_tooth_thickness(z, x):
    m, alpha = 3.0, math.radians(20.0)
    s_iso = inv.transverse_tooth_thickness_reference(m, x, alpha)  # ISO 21771: m (pi/2 + 2 x tan alpha)
    r = 0.5 * m * z
    psi = tr.base_half_tooth_angle_rad(z, x)
    assert 2 * r * (psi - inv_val(alpha)) == pytest.approx(s_iso, rel=1e-12)
    # the thesis' Eq. 3.36 describes a tooth 2 x m tan(alpha) thick at the reference circle: pi m/2 is missing
    phi = tr.thesis_base_half_tooth_angle_rad(z, x)
    assert 2 * r * (phi - inv_val(alpha)) == pytest.approx(2 * x * m * math.tan(alpha), abs=1e-12)
    assert psi - phi == pytest.approx(math.pi / (2 * z), rel=1e-12)


def inv_val(alpha):
    return math.tan(alpha) - alpha


def test_pi_over_2z_changes_the_deflection_and_puts_the_flank_on_the_right_side():
    z, x, m = 17, 0.0, 3.0
    d = m * z
    d_b, d_f, d_a = d * math.cos(math.radians(20)), d - 2 * m * 1.25, d + 2 * m
    rho_ref = 0.5 * d * math.sin(math.radians(20))
    rho_tip = 0.5 * math.sqrt(d_a ** 2 - d_b ** 2)
    right = tr.load_point_geometry(rho_ref, d_b, d_f, m, tr.base_half_tooth_angle_rad(z, x))
    wrong = tr.load_point_geometry(rho_ref, d_b, d_f, m, tr.thesis_base_half_tooth_angle_rad(z, x))
    # load height and tooth deflection move by ~3 % at z = 17
    db_right = tr.tooth_deflection_um(100.0, z, m, x, right["load_height_modules"])
    db_wrong = tr.tooth_deflection_um(100.0, z, m, x, wrong["load_height_modules"])
    assert abs(db_wrong / db_right - 1) > 0.02
    # the Weber depth (contact to tooth centreline) is the half tooth thickness / cos(omega) with pi/(2z) ...
    assert right["centreline_depth_mm"] * math.cos(right["load_angle_rad"]) == pytest.approx(
        0.5 * d * math.sin(math.pi / (2 * z)), rel=1e-12)
    # ... and zero at the reference circle, negative (flank beyond the centreline) at the tip without it
    assert wrong["centreline_depth_mm"] == pytest.approx(0.0, abs=1e-12)
    assert tr.load_point_geometry(rho_tip, d_b, d_f, m, tr.thesis_base_half_tooth_angle_rad(z, x))[
        "centreline_depth_mm"] < 0 < tr.load_point_geometry(rho_tip, d_b, d_f, m,
                                                             tr.base_half_tooth_angle_rad(z, x))["centreline_depth_mm"]


def test_min_tip_relief_uses_the_iso_half_tooth_angle():
    # the Weber depth at the pitch point must come from the ISO 21771 thickness on the working pitch circle
    pair = spur(38, 76, x=(0.3124, 0.1122))
    g = pair.geometry()
    p = tr.min_tip_relief_um(pair, 150.0, parts=True)
    alpha_t = math.radians(g["transverse_pressure_angle_deg"])
    for i in range(2):
        d_w = g["working_pitch_diameter_mm"][i]
        s_w = inv.transverse_tooth_thickness_at(d_w, g["pitch_diameter_mm"][i], g["base_diameter_mm"][i],
                                                g["transverse_tooth_thickness_mm"][i], alpha_t)
        omega = math.tan(math.radians(g["working_pressure_angle_deg"])) - (
            g["transverse_tooth_thickness_mm"][i] / g["pitch_diameter_mm"][i] + inv_val(alpha_t))
        assert p["centreline_depth_mm"][i] * math.cos(omega) == pytest.approx(0.5 * d_w * math.sin(s_w / d_w),
                                                                              rel=1e-10)


# ----------------------------------------------------------------------------------------------------------------
# load convention, symbolic = numeric, derivatives
# ----------------------------------------------------------------------------------------------------------------

def test_normal_load_from_torque_on_either_gear():
    pair = spur(38, 76, x=(0.3124, 0.1122), b=(30.0, 25.0))
    g = pair.geometry()
    T1 = 190.0
    w1 = tr.normal_load_per_width_N_per_mm(pair, T1, driving_gear=1)
    # F_tw on the working pitch radius over cos(alpha_wt), per common face width
    f_tw = T1 * 1000 / (0.5 * g["working_pitch_diameter_mm"][0])
    assert w1 == pytest.approx(f_tw / math.cos(math.radians(g["working_pressure_angle_deg"])) / 25.0, rel=1e-12)
    # the same mesh force seen from the driven gear's torque
    T2 = T1 * 76 / 38
    assert tr.normal_load_per_width_N_per_mm(pair, T2, driving_gear=2) == pytest.approx(w1, rel=1e-12)
    assert tr.min_tip_relief_um(pair, T2, driving_gear=2) == pytest.approx(tr.min_tip_relief_um(pair, T1), rel=1e-12)


def _symbolic_relief(contact_point, hertz_model):
    x1, T = ca.SX.sym("x1"), ca.SX.sym("T")
    pair = go.GearPair.from_centre_distance(teeth=(38, 76), centre_distance_mm=172.2406, module_mm=3.0,
                                            face_width_mm=(30.0, 25.0), profile_shift1=x1)
    ct = tr.min_tip_relief_um(pair, T, contact_point=contact_point, hertz_model=hertz_model)
    f = ca.Function("f", [x1, T], [ca.vertcat(*ct)])
    jac = ca.Function("j", [x1, T], [ca.jacobian(ca.vertcat(*ct), ca.vertcat(x1, T))])
    return f, jac


@pytest.mark.parametrize("contact_point", tr.CONTACT_POINTS)
@pytest.mark.parametrize("hertz_model", tr.HERTZ_MODELS)
def test_symbolic_equals_numeric_and_derivatives_match_finite_differences(contact_point, hertz_model):
    f, jac = _symbolic_relief(contact_point, hertz_model)
    x1, T = 0.3124, 190.0
    pair = go.GearPair.from_centre_distance(teeth=(38, 76), centre_distance_mm=172.2406, module_mm=3.0,
                                            face_width_mm=(30.0, 25.0), profile_shift1=x1)
    numeric = np.array(tr.min_tip_relief_um(pair, T, contact_point=contact_point, hertz_model=hertz_model))
    assert np.array(f(x1, T)).ravel() == pytest.approx(numeric, rel=1e-12)
    J = np.array(jac(x1, T))
    hx, hT = 1e-6, 1e-4
    fd_x = (np.array(f(x1 + hx, T)) - np.array(f(x1 - hx, T))).ravel() / (2 * hx)
    fd_T = (np.array(f(x1, T + hT)) - np.array(f(x1, T - hT))).ravel() / (2 * hT)
    assert J[:, 0] == pytest.approx(fd_x, rel=1e-6, abs=1e-8)
    assert J[:, 1] == pytest.approx(fd_T, rel=1e-6, abs=1e-10)
    assert np.all(np.abs(J[:, 1]) > 0) and np.all(np.isfinite(J))


def test_symbolic_load_stays_finite_at_zero_torque():
    # the half-width is floored inside the logarithms, so an NLP iterate at zero load gives a finite value (0)
    f, jac = _symbolic_relief("pitch", "weber")
    assert np.all(np.isfinite(np.array(f(0.3124, 0.0))))
    assert np.array(f(0.3124, 0.0)).ravel() == pytest.approx([0.0, 0.0], abs=1e-9)


# ----------------------------------------------------------------------------------------------------------------
# errors
# ----------------------------------------------------------------------------------------------------------------

def test_bad_input_raises_named_errors():
    pair = spur()
    with pytest.raises(GearoptInputError, match="torque_Nm"):
        tr.min_tip_relief_um(pair, -5.0)
    with pytest.raises(GearoptInputError, match="contact_point"):
        tr.min_tip_relief_um(pair, 100.0, contact_point="root")
    with pytest.raises(GearoptInputError, match="hertz_model"):
        tr.min_tip_relief_um(pair, 100.0, hertz_model="palmgren")
    with pytest.raises(GearoptInputError, match="driving_gear"):
        tr.min_tip_relief_um(pair, 100.0, driving_gear=3)
    with pytest.raises(GearoptInputError, match="poisson"):
        tr.min_tip_relief_um(pair, 100.0, poisson=0.5)
    helical = go.GearPair.from_profile_shifts(teeth=(38, 76), profile_shifts=(0.0, 0.0), module_mm=3.0,
                                              helix_angle_deg=10.0)
    with pytest.raises(GearoptInputError, match="helix_angle_deg"):
        tr.min_tip_relief_um(helical, 100.0)


# ----------------------------------------------------------------------------------------------------------------
# thesis Table 3.7 analogue (normalised in the thesis: compare shape and ordering only)
# ----------------------------------------------------------------------------------------------------------------

def _accessory_torques_Nm():
    """Torque on each mesh's driving gear from the packaged engine data's peak accessory torques ([E] estimates):
    AC and FP loads carried back to the cam gear, valve train + both on the crank-cam mesh, lube pump through LPI."""
    train = go.load_default_train("spur")
    e = go.load_default_data()["engine"]
    z = {name: spec.teeth for name, spec in train.gears.items()}
    t = {"cam-ac": e["air_compressor"]["torque_peak_Nm"] * z["cam"] / z["ac"],
         "cam-fp": e["fuel_pump"]["torque_peak_Nm"] * z["cam"] / z["fp"]}
    cam = e["camshaft"]["valve_train_torque_mean_Nm"] + e["camshaft"]["valve_train_torque_amplitude_Nm"]
    t["crank-cam"] = (cam + t["cam-ac"] + t["cam-fp"]) * z["crank"] / z["cam"]
    t["lpi-lpg"] = e["lube_pump"]["torque_mean_Nm"] * z["lpi"] / z["lpg"]
    t["crank-lpi"] = t["lpi-lpg"] * z["crank"] / z["lpi"]
    return train, t


def test_table_has_thesis_columns_and_consistent_values():
    train, torques = _accessory_torques_Nm()
    table = tr.min_tip_relief_table(train, torques)
    assert list(table["mesh"]) == list(train.pairs)
    for col in ("hertz_deformation_um", "elastic_deformation_1_um", "elastic_deformation_2_um",
                "min_tip_relief_1_um", "min_tip_relief_2_um", "normal_load_per_width_N_per_mm", "torque_Nm"):
        assert col in table.columns and np.all(table[col] > 0)
    row = table.set_index("mesh").loc["crank-cam"]
    direct = tr.min_tip_relief_um(train.pairs["crank-cam"], torques["crank-cam"])
    assert (row["min_tip_relief_1_um"], row["min_tip_relief_2_um"]) == pytest.approx(direct, rel=1e-12)
    assert row["min_tip_relief_1_um"] == pytest.approx(row["elastic_deformation_1_um"]
                                                       + 0.5 * row["hertz_deformation_um"], rel=1e-12)
    with pytest.raises(GearoptInputError, match="unknown mesh"):
        tr.min_tip_relief_table(train, {"crank-fp": 10.0})


def test_table_shape_follows_thesis_table_3_7():
    # Thesis Table 3.7 (normalised): Hertz deformation crank-cam 1.0 > cam-AC 0.97 > cam-FP 0.57 >> crank-LPI 0.088,
    # LPI-LPG 0.068; the largest elastic deformation is the cam gear's in crank-cam; the governing tip relief per gear
    # ranks cam 1.0 > crank 0.50 > AC 0.27 > FP 0.19 > LPI 0.052 > LPG 0.025. Our torques are estimates, so only
    # this ordering is compared.
    train, torques = _accessory_torques_Nm()
    table = tr.min_tip_relief_table(train, torques).set_index("mesh")
    hertz = table["hertz_deformation_um"] / table["hertz_deformation_um"].max()
    assert hertz["crank-cam"] == 1.0 and hertz["crank-cam"] > hertz["cam-ac"] > hertz["cam-fp"]
    assert max(hertz["crank-lpi"], hertz["lpi-lpg"]) < 0.1 < hertz["cam-fp"]
    elastic = table[["elastic_deformation_1_um", "elastic_deformation_2_um"]]
    assert elastic.stack().idxmax() == ("crank-cam", "elastic_deformation_2_um")
    governing = tr.governing_tip_relief_um(table.reset_index())
    assert sorted(governing, key=governing.get, reverse=True) == ["cam", "crank", "ac", "fp", "lpi", "lpg"]
