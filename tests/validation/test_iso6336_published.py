"""rate_iso6336 against a published report computed to ISO 6336:2006 method B and ISO/TR 13989:2000.

Source: KISSsoft Release 03/2017 report "stage_03" (helical gear pair, "CALCULATION OF A HELICAL GEAR PAIR",
calculation method ISO 6336:2006 Method B, scuffing to ISO TR 13989:2000), file ``@NREL_5MW/stage_03.rtf`` of the
public repository gfsReboucas/Drivetrain (NTNU, 26.02.2020). Inputs and printed results are quoted below as facts.

Inputs: m_n 14 mm, alpha_n 20 deg, beta 10 deg, z 24/95, x 0.48/0.6691, a 861 mm, b 360/360 mm, rack 1.25/0.38/1.0,
P 5000 kW at n1 1165.9 rpm (pinion driving), K_A 1.25, life 175 200 h, accuracy grade 6 (f_pb 13.1/15.9 um,
f_falpha 18/22 um), bores 179.10/1193.32 mm, gear body C_R with b_s/b 0.25 and s_R/m_n 5, K_Hbeta given as 1.150,
18CrNiMo7-6 case carburised (sigma_Hlim 1500, sigma_Flim 430 MPa, "normal" quality: Z_NT, Y_NT >= 0.85),
R_a flank 0.6 um, R_z flank 4.8 um, R_z root 20 um, oil 220/19 mm^2/s, 0.890 kg/dm^3, 80 C, oil bath, mineral,
FZG A/8.3/90 stage 14, tip relief "none (only running-in)", B_M 13.780 N/(mm s^0.5 K).

The report's K_v (1.092) follows from method B with B_k = 1, i.e. the design tip relief C_a = 0 in K_v; its
scuffing uses C_a = 2.0 um, the running-in amount -- as rate_iso6336 does with tip_relief_um=0.
"""

import dataclasses
import math
import warnings

import pytest

import gearopt as go
from gearopt.rating import Lubricant, rate_iso6336
from gearopt.rating.materials import material


@pytest.fixture(scope="module")
def report_case():
    base = material("20MnCr5")
    b_m = 13.780  # the report's thermal contact coefficient; lambda chosen so that sqrt(lambda rho c) matches it
    mat = dataclasses.replace(base, name="18CrNiMo7-6", sigma_Hlim_MPa=1500.0, sigma_Flim_MPa=430.0,
                              E_MPa=206000.0, poisson_ratio=0.3,
                              thermal_conductivity_W_mK=b_m ** 2 / (base.density_kg_m3 * base.specific_heat_J_kgK
                                                                    * 1e-6))
    pair = go.GearPair.from_profile_shifts(teeth=(24, 95), profile_shifts=(0.48, 0.6691), module_mm=14.0,
                                           helix_angle_deg=10.0, face_width_mm=360.0)
    torque = 5000e3 / (1165.9 * math.pi / 30.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # x1 < x2 stiffness validity note (the report's geometry)
        r = rate_iso6336(pair, torque, 1165.9, application_factor=1.25, materials=mat,
                         lubricant=Lubricant(220.0, 19.0, 890.0, 80.0, 14), flank_roughness_Ra_um=0.6,
                         flank_roughness_Rz_um=4.8, root_roughness_Rz_um=20.0, life_h=175200.0,
                         deviations_um={"f_pb": (13.1, 15.9), "f_falpha": (18.0, 22.0)}, solid_blanks=False,
                         web_thickness_mm=90.0, rim_thickness_mm=70.0, bore_diameters_mm=(179.10, 1193.32),
                         K_Hbeta=1.15)
    return r


def test_load_factors_match_the_report(report_case):
    f = report_case.factors
    d = report_case.details
    assert d["resonance_ratio"] == pytest.approx(0.410, abs=0.005)       # report: N = 0.410, subcritical
    assert d["resonance_range"] == "subcritical"
    assert d["reduced_mass_kg_per_mm"] == pytest.approx(0.36503, rel=0.015)  # report m_red (density differs)
    assert d["y_alpha_um"] == pytest.approx(1.2, abs=0.05)                # report y_p = y_a = 1.2 um
    assert d["y_f_um"] == pytest.approx(1.6, abs=0.06)                    # report y_f = 1.6 um
    assert d["running_in_tip_relief_um"] == pytest.approx(2.0, abs=0.01)  # report C_a = 2.0 um (running-in)
    assert f["K_v"] == pytest.approx(1.092, abs=0.002)
    assert f["K_Fbeta"] == pytest.approx(1.136, abs=0.001)
    assert f["K_Halpha"] == pytest.approx(1.069, abs=0.001)
    assert f["K_Falpha"] == pytest.approx(1.069, abs=0.001)


def test_strength_factors_match_the_report(report_case):
    f = report_case.factors
    assert report_case.load_cycles[0] / 1e6 == pytest.approx(12255.788, rel=1e-4)
    assert report_case.load_cycles[1] / 1e6 == pytest.approx(3096.199, rel=1e-4)
    expected = {"Z_NT": (0.850, 0.881), "Z_L": (1.020, 1.020), "Z_v": (1.022, 1.022), "Z_R": (1.007, 1.007),
                "Z_W": (1.000, 1.000), "Z_X": (1.000, 1.000), "Y_NT": (0.850, 0.870), "Y_deltarelT": (1.001, 1.005),
                "Y_RrelT": (0.957, 0.957), "Y_X": (0.910, 0.910), "Y_F": (1.18, 1.24), "Y_S": (2.28, 2.35)}
    for key, (g1, g2) in expected.items():
        tol = 0.01 if key in ("Y_F", "Y_S") else 0.0006  # Y_F, Y_S printed to 2 decimals
        assert f[key][0] == pytest.approx(g1, abs=tol), key
        assert f[key][1] == pytest.approx(g2, abs=tol), key


def test_safety_factors_match_the_report(report_case):
    s = report_case.safety_factors
    assert s["S_H"][0] == pytest.approx(1.81, abs=0.006) and s["S_H"][1] == pytest.approx(1.88, abs=0.006)
    assert s["S_F"][0] == pytest.approx(3.26, abs=0.006) and s["S_F"][1] == pytest.approx(3.09, abs=0.006)
    assert report_case.stresses["sigma_HG_MPa"][0] == pytest.approx(1338.30, rel=2e-3)
    assert report_case.stresses["sigma_FG_MPa"][1] == pytest.approx(654.72, rel=2e-3)


def test_integral_temperature_scuffing_matches_the_report(report_case):
    sc = report_case.scuffing
    assert sc["K_Bgamma"] == pytest.approx(1.274, abs=0.001)
    assert sc["X_M"] == pytest.approx(50.058, rel=2e-3)
    assert sc["X_BE"] == pytest.approx(0.230, abs=0.001)
    assert sc["X_eps"] == pytest.approx(0.263, abs=0.001)
    assert sc["X_Ca"] == pytest.approx(1.095, abs=0.001)
    assert sc["C_eff_um"] == pytest.approx(44.74, rel=2e-3)
    assert sc["mu_mC"] == pytest.approx(0.030, abs=0.0005)
    assert sc["dynamic_viscosity_mPa_s"] == pytest.approx(30.09, rel=5e-3)
    assert sc["theta_int_C"] == pytest.approx(115.75, rel=0.01)
    # theta_Sint from the FZG torque is [M] (recalled coefficients): within the 2-3 % accepted for ISO/TR 13989
    assert sc["theta_Sint_C"] == pytest.approx(455.17, rel=0.03)
    assert report_case.safety_factors["S_intS"] == pytest.approx(3.932, rel=0.03)


def test_flash_temperature_scuffing_parts_match_the_report(report_case):
    sc = report_case.scuffing
    assert sc["theta_S_C"] == pytest.approx(451.98, abs=0.3)   # scuffing temperature of FZG stage 14
    assert sc["theta_M_C"] - 80.0 == pytest.approx(0.47 * sc["theta_flm_C"], rel=1e-12)
    # the report's S_B = 4.156 (theta_B 169.5 C); ours is higher: its flash temperature at E is 75.3 K against
    # ~67 K here (the report's mu_m = 0.041 versus 0.038 with rho_redC; gap documented in docs/rating.md)
    assert 4.156 < report_case.safety_factors["S_B"] < 4.156 * 1.15
