"""LTCA outputs computed on request: root stress against ISO 6336-3 method B, flash temperature against the AGMA
925 form of Blok's formula, sliding velocity, and the requirement that nothing is computed unless asked for."""

import math

import numpy as np
import pytest

import gearopt as go
from gearopt.contact.ltca import ltca
from gearopt.errors import GearoptInputError
from gearopt.rating.root_stress import root_stress_iso6336


@pytest.fixture(scope="module")
def crank_cam():
    return go.load_default_train("spur").pairs["crank-cam"]


def test_max_root_stress_equals_iso_6336_3_method_b_at_the_outer_single_contact_point(crank_cam):
    # ISO 6336-3 method B puts the whole load at the outer point of single tooth contact; an unmodified LTCA with
    # constant stiffness carries the whole load there too, so its largest root stress over the cycle must equal
    # sigma_F0 (with ISO's own face width per gear; the LTCA spreads the load over the common 25 mm face)
    r = ltca(crank_cam, 300.0, stiffness=14.0, positions=400)
    iso = root_stress_iso6336(crank_cam, 300.0)
    for i, gear in enumerate(("gear1", "gear2")):
        expected = float(iso[gear]["sigma_F0_MPa"]) * float(iso[gear]["face_width_mm"]) / 25.0
        assert r.max_root_stress_MPa[i] == pytest.approx(expected, rel=5e-3)


def test_flash_temperature_matches_agma_925_form_and_vanishes_at_the_pitch_point(crank_cam):
    # AGMA 925 / docs/default-data.md sec. 3 identity: theta = 0.785 mu w |sqrt(v1) - sqrt(v2)| / (B_M sqrt(b_H)) (coherent
    # SI), evaluated here independently from the LTCA's own load, radii and speeds
    r = ltca(crank_cam, 300.0, speed_rpm=2500.0, friction_coefficient=0.06)
    lay = r.layout
    w = r.load_intensity_N_per_mm
    v1, v2 = r.rolling_velocity_m_s
    idx = np.unravel_index(np.argmax(r.flash_temperature_rise_K), w.shape)
    rho1, rho2 = lay.rho1_mm[idx] * 1e-3, lay.rho2_mm[idx] * 1e-3         # m
    e_r = 206e9 / (1 - 0.3 ** 2)                                          # E/(1-nu^2), Pa
    b_h = math.sqrt(8 * w[idx] * 1e3 * (rho1 * rho2 / (rho1 + rho2)) / (math.pi * e_r))  # m, Shigley eq. 3-73
    b_m = math.sqrt(50.0 * 7850.0 * 460.0)                                # W s^0.5/(m^2 K), 20MnCr5 data
    theta = (1.11 / math.sqrt(2)) * 0.06 * w[idx] * 1e3 * abs(math.sqrt(v1[idx]) - math.sqrt(v2[idx])) / (
        b_m * math.sqrt(b_h))
    assert r.flash_temperature_rise_K[idx] == pytest.approx(theta, rel=1e-6)
    assert 5.0 < r.flash_temperature_rise_K.max() < 60.0
    assert r.max_flash_temperature_C == pytest.approx(100.0 + r.flash_temperature_rise_K.max())
    # no sliding, no flash: the contact nearest the pitch point has the smallest rise of the loaded contacts
    pitch = crank_cam.geometry()["pitch_point_roll_length_mm"][0]
    near = np.argmin(np.where(lay.on_path, np.abs(lay.rho1_mm - pitch), np.inf))
    assert r.sliding_velocity_m_s.reshape(-1)[near] < 0.1
    assert r.flash_temperature_rise_K.reshape(-1)[near] < 0.05 * r.flash_temperature_rise_K.max()


def test_sliding_velocity_is_omega_times_distance_from_pitch_point(crank_cam):
    # kinematics: v_s = |omega1 rho1 - omega2 rho2| = (omega1 + omega2) |rho1 - rho1_C| on the line of action
    r = ltca(crank_cam, 300.0, speed_rpm=1800.0)
    w1 = 1800 * 2 * math.pi / 60
    w2 = w1 * 38 / 76
    pitch = crank_cam.geometry()["pitch_point_roll_length_mm"][0]
    on = r.layout.on_path
    expected = (w1 + w2) * np.abs(r.layout.rho1_mm - pitch) * 1e-3
    np.testing.assert_allclose(r.sliding_velocity_m_s[on], expected[on], rtol=1e-9, atol=1e-12)


def test_thermal_outputs_need_a_speed_and_are_not_computed_unless_asked(crank_cam):
    r = ltca(crank_cam, 300.0)
    assert "root_stress_MPa" not in vars(r) and "flash_temperature_rise_K" not in vars(r)
    with pytest.raises(GearoptInputError, match="speed_rpm"):
        r.max_flash_temperature_C
    r.max_root_stress_MPa
    assert "root_stress_MPa" in vars(r)
    with pytest.raises(GearoptInputError, match="speed_rpm"):
        ltca(crank_cam, 300.0, speed_rpm=-1.0)
