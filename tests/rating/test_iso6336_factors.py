"""ISO 6336 factor kernels: closed forms and limits stated by the standards, ISO 1328-1 tolerances against a
published report, overrides, bad input and validity warnings (the published rating is in
tests/validation/test_iso6336_published.py)."""

import math
import warnings

import pytest

import gearopt as go
from gearopt.errors import GearoptInputError
from gearopt.rating import Lubricant, RatingValidityWarning, rate_iso6336
from gearopt.rating import accuracy, life_factors, load_factors as lf, lubrication as lub, size_factors as sf


def spur_pair(face_width_mm=30.0):
    return go.GearPair.from_profile_shifts(teeth=(38, 76), profile_shifts=(0.3, 0.1), module_mm=3.0,
                                           face_width_mm=face_width_mm)


def test_iso1328_formulas_at_range_means_give_the_tabulated_tolerances():
    # KISSsoft 03/2017 report "stage_03" (gfsReboucas/Drivetrain, @NREL_5MW/stage_03.rtf), section 7, ISO 1328-1:1995
    # grade 6: f_pt 14/17, f_falpha 18/22, f_Hbeta 18/19, F_beta 25/27 um for d 341.2/1350.5 mm, m_n 14, b 360 mm.
    # The standard tabulates its formulas at the geometric means of the ranges d 280-560 / 1000-1600, m 10-16,
    # b 250-400 mm and rounds to whole um.
    m = math.sqrt(10 * 16)
    b = math.sqrt(250 * 400)
    for d, expected in ((math.sqrt(280 * 560), (14, 18, 18, 25)), (math.sqrt(1000 * 1600), (17, 22, 19, 27))):
        got = (accuracy.single_pitch_tolerance_um(d, m, 6), accuracy.profile_form_tolerance_um(d, m, 6),
               accuracy.helix_slope_tolerance_um(d, b, 6), accuracy.total_helix_tolerance_um(d, b, 6))
        assert tuple(round(x) for x in got) == expected


def test_grade_step_is_sqrt2():
    assert accuracy.grade_scale(7) / accuracy.grade_scale(6) == pytest.approx(math.sqrt(2.0))
    with pytest.raises(GearoptInputError, match="accuracy_grade=13"):
        accuracy.grade_scale(13)


def test_dynamic_factor_limits_and_continuity():
    args = dict(line_load_N_per_mm=300.0, single_stiffness=14.0, f_pb_eff_um=8.0, f_falpha_eff_um=9.0,
                tip_relief_um=0.0, total_contact_ratio=1.6)
    assert lf.dynamic_factor(0.0, **args)["K_v"] == pytest.approx(1.0)        # at rest: no dynamic load
    main = lf.dynamic_factor(1.15, **args)["K_v"]
    sup = lf.dynamic_factor(1.5, **args)["K_v"]
    # ISO 6336-1 cl. 6.3.5: linear between the main resonance value at 1.15 and the supercritical one at 1.5
    assert lf.dynamic_factor(1.15 + 1e-9, **args)["K_v"] == pytest.approx(main, rel=1e-6)
    assert lf.dynamic_factor(1.325, **args)["K_v"] == pytest.approx(0.5 * (main + sup), rel=1e-9)
    c = lf.dynamic_coefficients(1.6)
    bp, bf = 14.0 * 8.0 / 300.0, 14.0 * 9.0 / 300.0
    assert sup == pytest.approx(0.47 * bp + 0.47 * bf + c["C_v7"])
    # Table 8's two columns nearly meet at eps_gamma = 2 (the constants of the left column are rounded: 0.34 vs
    # 0.57/1.7 = 0.335, 0.23 vs 0.218, 0.90 vs 0.84, 0.47 vs 0.46) -- a check on the transcribed coefficients
    lo, hi = lf.dynamic_coefficients(2.0), lf.dynamic_coefficients(2.0 + 1e-9)
    for k in ("C_v2", "C_v3", "C_v4", "C_v6"):
        assert float(lo[k]) == pytest.approx(float(hi[k]), rel=0.075), k


def test_face_load_factor_closed_forms():
    assert lf.face_load_factor_contact(0.0, 15.0, 400.0) == pytest.approx(1.0)
    # continuous at K_Hbeta = 2 (ISO 6336-1 cl. 7.6.1: 1 + x/2 = 2 = sqrt(2x) at x = 2)
    assert lf.face_load_factor_contact(2.0 * 400.0 / 15.0, 15.0, 400.0) == pytest.approx(2.0)
    assert lf.face_load_factor_contact(8.0 * 400.0 / 15.0, 15.0, 400.0) == pytest.approx(4.0)
    # K_Fbeta = K_Hbeta^N_F, N_F = r^2/(1 + r + r^2), r held at >= 3
    assert lf.face_load_factor_root(1.5, 2.0, 1.0) == pytest.approx(1.5 ** (9.0 / 13.0))


def test_transverse_load_factor_bounds():
    # perfect gears: the formula gives eps_gamma/2 * 0.9 < 1 and the factor is held at 1 (ISO 6336-1 cl. 8.3.3)
    r = lf.transverse_load_factors(1.6, 1.6, 0.9, 18.0, 0.0, 500.0)
    assert r["K_Halpha"] == 1.0 and r["K_Falpha"] == 1.0
    # huge deviation: held at eps_gamma/(eps_alpha Z_eps^2) and eps_gamma/(0.25 eps_alpha + 0.75)
    r = lf.transverse_load_factors(1.6, 1.6, 0.9, 18.0, 500.0, 50.0)
    assert r["K_Halpha"] == pytest.approx(1.6 / (1.6 * 0.81)) and r["K_Falpha"] == pytest.approx(1.6 / 1.15)


def test_life_factor_curves_at_the_standards_knots():
    for n, z in ((1e3, 1.6), (1e5, 1.6), (5e7, 1.0), (1e10, 0.85), (1e12, 0.85)):
        assert float(life_factors.life_factor_contact(n, "20MnCr5")) == pytest.approx(z)
    assert float(life_factors.life_factor_contact(1e12, "20MnCr5", long_life_factor=1.0)) == pytest.approx(1.0)
    for n, y in ((1e3, 2.5), (3e6, 1.0), (1e10, 0.85)):
        assert float(life_factors.life_factor_root(n, "20MnCr5")) == pytest.approx(y)
    assert float(life_factors.life_factor_root(1e4, "42CrMo4")) == pytest.approx(2.5)      # St/V curve
    assert float(life_factors.life_factor_contact(2e6, "31CrMoV9")) == pytest.approx(1.0)  # nitrided curve
    with pytest.raises(GearoptInputError, match="load_cycles=0.5"):
        life_factors.life_factor_contact(0.5, "20MnCr5")


def test_lubrication_factors_equal_one_at_the_reference_conditions():
    # ISO 6336-2 cl. 11: Z_L = 1 where (1.2 + 134/nu40)^2 = 4 (nu40 = 167.5), Z_v = 1 where 0.8 + 32/v = 4 (10 m/s),
    # Z_R = 1 for R_z10 = 3 um
    for s in (800.0, 1000.0, 1500.0):
        assert float(lub.lubricant_factor(167.5, s)) == pytest.approx(1.0)
        assert float(lub.velocity_factor(10.0, s)) == pytest.approx(1.0)
        assert float(lub.roughness_factor(3.0, 10.0, s)) == pytest.approx(1.0)
    with pytest.raises(GearoptInputError, match="viscosity_40C_mm2_s=0"):
        lub.lubricant_factor(0.0, 1500.0)
    with pytest.raises(GearoptInputError, match="flank_roughness_Rz_um=-1"):
        lub.roughness_factor(-1.0, 10.0, 1500.0)


def test_lubricant_viscosity_temperature_relation():
    oil = Lubricant(220.0, 19.0, 890.0, 80.0, 12)
    assert oil.kinematic_viscosity_mm2_s(40.0) == pytest.approx(220.0, rel=1e-9)
    assert oil.kinematic_viscosity_mm2_s(100.0) == pytest.approx(19.0, rel=1e-9)
    with pytest.raises(GearoptInputError, match="viscosity_100C_mm2_s"):
        Lubricant(100.0, 150.0, 890.0, 80.0, 12)


def test_notch_and_surface_factors_equal_one_for_the_test_gear():
    # the reference test gear (q_s = 2.5, R_z 10 um for V/Eh) defines Y_deltarelT = Y_RrelT = 1 (ISO 6336-3 cl. 13)
    assert float(sf.relative_notch_sensitivity(2.5, "20MnCr5")) == pytest.approx(1.0)
    assert float(sf.relative_surface_factor(10.0, "20MnCr5")) == pytest.approx(1.0, abs=2e-3)
    with pytest.warns(RatingValidityWarning, match="clause 13"):
        sf.relative_surface_factor(50.0, "20MnCr5")


def test_overrides_scale_the_stresses_as_the_formulas_say():
    pair = spur_pair()
    kw = dict(K_v=1.1, K_Hbeta=1.2, K_Halpha=1.05)
    a = rate_iso6336(pair, 300.0, 2500.0, **kw)
    b = rate_iso6336(pair, 300.0, 2500.0, **{**kw, "K_v": 1.1 * 1.21})
    assert a.factors["K_v"] == 1.1
    assert a.safety_factors["S_H"][0] / b.safety_factors["S_H"][0] == pytest.approx(1.1)   # sigma_H ~ sqrt(K_v)
    assert a.safety_factors["S_F"][1] / b.safety_factors["S_F"][1] == pytest.approx(1.21)  # sigma_F ~ K_v


def test_life_in_hours_equals_the_load_cycles_it_implies():
    pair = spur_pair()
    a = rate_iso6336(pair, 300.0, 2500.0, life_h=1000.0)
    b = rate_iso6336(pair, 300.0, 2500.0, load_cycles=(60 * 1000 * 2500.0, 60 * 1000 * 2500.0 * 38 / 76))
    for key in ("Z_NT", "Y_NT"):
        assert a.factors[key][0] == pytest.approx(float(b.factors[key][0]))
        assert a.factors[key][1] == pytest.approx(float(b.factors[key][1]))
    assert a.safety_factors["S_H"][1] > rate_iso6336(pair, 300.0, 2500.0).safety_factors["S_H"][1]


def test_table_has_one_row_per_factor_with_unit_and_clause():
    r = rate_iso6336(spur_pair(), 300.0, 2500.0)
    t = r.table
    assert {"factor", "gear_1", "gear_2", "unit", "clause"} <= set(t.columns)
    for key in ("K_v", "K_Hbeta", "K_Halpha", "K_Fbeta", "K_Falpha", "Z_NT", "Z_L", "Z_v", "Z_R", "Z_W", "Z_X",
                "Y_NT", "Y_deltarelT", "Y_RrelT", "Y_X", "S_H", "S_F", "S_B", "S_intS"):
        assert key in set(t["factor"]), key
    assert all(isinstance(x, float) and math.isfinite(x) for x in t["gear_1"])


@pytest.mark.parametrize("kwargs, match", [
    (dict(accuracy_grade=13), "accuracy_grade=13"),
    (dict(accuracy_grade=-1), "accuracy_grade=-1"),
    (dict(flank_roughness_Rz_um=0.0), "flank_roughness_Rz_um"),
    (dict(root_roughness_Rz_um=-2.0), "root_roughness_Rz_um"),
    (dict(load_cycles=0.5), "load_cycles"),
    (dict(driving_gear=3), "driving_gear=3"),
    (dict(lubricant=Lubricant(100.0, 11.0, 880.0, 140.0, 1)), "scuffing temperature"),
])
def test_bad_input_names_parameter_value_and_limit(kwargs, match):
    with pytest.raises(GearoptInputError, match=match):
        rate_iso6336(spur_pair(), 300.0, 2500.0, **kwargs)


def test_main_resonance_warns_naming_the_clause():
    # a light pinion at its resonance speed
    pair = spur_pair()
    r0 = rate_iso6336(pair, 300.0, 2500.0)
    n_e1 = r0.details["resonance_speed_rpm"]
    with pytest.warns(RatingValidityWarning, match="cl. 6.3.4"):
        r = rate_iso6336(pair, 300.0, n_e1)
    assert r.details["resonance_range"] == "main resonance"


def test_train_table_rows_equal_single_ratings():
    from gearopt.rating import iso6336_train_table

    train = go.load_default_train("spur")
    torques = {"crank-cam": 300.0, "cam-ac": 240.0}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        df = iso6336_train_table(train, torques, 2500.0, application_factor=1.25, accuracy_grades={"ac": 7})
    assert list(df["mesh"]) == ["crank-cam", "cam-ac"]
    pair = train.pairs["cam-ac"]
    ref = rate_iso6336(pair, 240.0, train.gear_speed_rpm("cam", 2500.0), application_factor=1.25,
                       accuracy_grade=(6, 7))
    row = df.set_index("mesh").loc["cam-ac"]
    assert row["S_H_1"] == pytest.approx(float(ref.safety_factors["S_H"][0]))
    assert row["K_v"] == pytest.approx(float(ref.factors["K_v"]))
    assert row["N_L_1"] == pytest.approx(1e10)
    with pytest.raises(GearoptInputError, match="unknown mesh"):
        iso6336_train_table(train, {"x-y": 1.0}, 2500.0)


def test_work_hardening_factor_limits_and_rating():
    # ISO 6336-2 cl. 12: Z_W = 1.2 at 130 HB and 1.0 at 470 HB for R_zH = 3 um; R_zH held to [3, 16]
    assert float(lub.work_hardening_factor(130.0, 3.0)) == pytest.approx(1.2)
    assert float(lub.work_hardening_factor(470.0, 1.0)) == pytest.approx(1.0)
    assert float(lub.work_hardening_factor(130.0, 16.0)) == pytest.approx(1.2 * (3 / 16) ** 0.15)
    # a case-carburised pinion hardens the through-hardened 42CrMo4 wheel (300 HV ~ 285 HB); the pinion keeps 1
    r = rate_iso6336(spur_pair(), 300.0, 2500.0, materials=("20MnCr5", "42CrMo4"))
    assert r.factors["Z_W"][0] == 1.0
    assert float(r.factors["Z_W"][1]) == pytest.approx(1.2 - (0.95 * 300.0 - 130.0) / 1700.0)  # R_zH at its floor


def test_tip_relief_beyond_the_effective_relief_warns_naming_the_standard():
    with pytest.warns(RatingValidityWarning, match="ISO/TS 6336-21"):
        r = rate_iso6336(spur_pair(), 50.0, 2500.0, tip_relief_um=80.0)
    assert any("X_Ca" in n for n in r.notes)
