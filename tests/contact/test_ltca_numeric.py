"""Exact numeric LTCA: analytic limits (constant stiffness), Harris' short-relief result, Hertz at the pitch point
against ISO 6336-2's nominal contact stress, load balance and slicing."""

import math

import numpy as np
import pytest

import gearopt as go
from gearopt.contact.ltca import ltca
from gearopt.contact.microgeometry import Microgeometry
from gearopt.errors import GearoptInputError

C_PRIME = 14.0  # N/(mm*um), constant single-pair stiffness for the analytic checks


@pytest.fixture(scope="module")
def spur():
    return go.GearPair.from_profile_shifts(teeth=(30, 60), profile_shifts=(0.0, 0.0), module_mm=3.0,
                                           face_width_mm=20.0)


def test_constant_stiffness_ppte_is_w_over_2c(spur):
    # single-pair zone: delta = w/c'; double-pair zone: w/(2c'); PPTE = w/(2c') for 1 < eps_alpha < 2
    r = ltca(spur, torque_Nm=200.0, stiffness=C_PRIME, positions=120)
    w = r.transverse_force_N / 20.0
    assert r.ppte_um == pytest.approx(w / (2 * C_PRIME), rel=1e-12)
    assert r.transmission_error_um.max() == pytest.approx(w / C_PRIME, rel=1e-12)
    # the fraction of the cycle with two pairs in contact is eps_alpha - 1
    eps = spur.geometry()["transverse_contact_ratio"]
    assert r.loaded_contact_ratio == pytest.approx(eps, abs=1.0 / 120)


def test_zero_load_gives_zero_rigid_body_te(spur):
    r = ltca(spur, torque_Nm=0.0, stiffness=C_PRIME, positions=20)
    assert np.all(r.transmission_error_um == 0.0)


def test_load_balance_and_no_tensile_loads(spur):
    mods = Microgeometry(tip_relief_um=(12.0, 8.0), tip_relief_start_roll_deg=(26.0, 24.0), lead_crown_um=(4.0, 0.0))
    r = ltca(spur, torque_Nm=300.0, stiffness=C_PRIME, microgeometry=mods, positions=50, slices=15)
    assert np.all(r.load_intensity_N_per_mm >= 0.0)
    np.testing.assert_allclose(r.load_sharing.sum(axis=1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(r.load_intensity_N_per_mm.sum(axis=(1, 2)) * 20.0 / 15, r.transverse_force_N,
                               rtol=1e-12)


@pytest.mark.parametrize("driving_gear", [1, 2])
def test_harris_short_linear_relief_cancels_ppte_at_design_load(spur, driving_gear):
    # Harris (1958): linear tip relief over the double-contact zones, of depth equal to the single-pair deflection
    # w/c' at the design load, makes the static TE constant at that load (constant stiffness).
    g = spur.geometry()
    torque = 200.0 if driving_gear == 1 else 400.0  # same base-circle force (z2 = 2 z1)
    w = torque * 1000.0 / (0.5 * g["base_diameter_mm"][driving_gear - 1]) / 20.0
    amount = w / C_PRIME
    mods = Microgeometry(tip_relief_um=(amount, amount), tip_relief_start_roll_deg=g["hpstc_roll_deg"])
    r = ltca(spur, torque_Nm=torque, stiffness=C_PRIME, microgeometry=mods, positions=100,
             driving_gear=driving_gear)
    assert r.ppte_um < 1e-9
    # away from the design load the PPTE returns (Harris map minimum)
    assert ltca(spur, torque_Nm=0.5 * torque, stiffness=C_PRIME, microgeometry=mods, positions=100,
                driving_gear=driving_gear).ppte_um > 0.2 * amount


def test_pitch_point_hertz_stress_equals_iso_6336_2_nominal(spur):
    # ISO 6336-2: sigma_H0 = Z_H Z_E sqrt(F_t/(d1 b) (u+1)/u) at the pitch point of a spur pair with the whole load
    # on one pair (Z_eps = Z_B = 1); Z_E = sqrt(1/(pi 2(1-nu^2)/E)), Z_H = sqrt(2 cos(alpha_wt)/(cos^2 alpha sin alpha_wt))
    g = spur.geometry()
    torque = 250.0
    r = ltca(spur, torque_Nm=torque, stiffness=C_PRIME, positions=400)
    d1, b, u = g["pitch_diameter_mm"][0], 20.0, 2.0
    ft = torque * 1000.0 / (0.5 * d1)
    alpha, alpha_w = math.radians(20.0), math.radians(g["working_pressure_angle_deg"])
    z_e = math.sqrt(1.0 / (math.pi * 2 * (1 - 0.3**2) / 206000.0))
    z_h = math.sqrt(2 * math.cos(alpha_w) / (math.cos(alpha) ** 2 * math.sin(alpha_w)))
    sigma_iso = z_h * z_e * math.sqrt(ft / (d1 * b) * (u + 1) / u)
    # find the position where the loaded pair is at the pitch point, in the single-contact zone
    c_rho = g["pitch_point_roll_length_mm"][0]
    i, k = np.unravel_index(np.argmin(np.abs(r.roll_length_1_mm - c_rho)), r.roll_length_1_mm.shape)
    assert abs(r.roll_length_1_mm[i, k] - c_rho) < 0.05
    assert r.load_sharing[i, k] == pytest.approx(1.0)
    assert r.contact_stress_MPa[i, k, 0] == pytest.approx(sigma_iso, rel=2e-3)


def test_one_slice_for_plain_spur_more_for_lead_modifications(spur):
    assert ltca(spur, 100.0, stiffness=C_PRIME, positions=10).load_intensity_N_per_mm.shape[2] == 1
    mods = Microgeometry(lead_crown_um=(5.0, 0.0))
    assert ltca(spur, 100.0, stiffness=C_PRIME, positions=10, microgeometry=mods).load_intensity_N_per_mm.shape[2] > 1


def test_helical_overlap_smooths_te():
    # with an integer overlap ratio and constant stiffness the total contact-line length is constant: PPTE -> 0
    kw = dict(teeth=(30, 60), profile_shifts=(0.0, 0.0), module_mm=3.0)
    beta = 20.0
    b = math.pi * 3.0 / math.sin(math.radians(beta))  # eps_beta = 1
    hel = go.GearPair.from_profile_shifts(helix_angle_deg=beta, face_width_mm=b, **kw)
    coarse = ltca(hel, 300.0, stiffness=C_PRIME, positions=60, slices=40).ppte_um
    fine = ltca(hel, 300.0, stiffness=C_PRIME, positions=60, slices=400).ppte_um
    spur_ppte = ltca(go.GearPair.from_profile_shifts(face_width_mm=b, **kw), 300.0, stiffness=C_PRIME,
                     positions=60).ppte_um
    assert coarse < 0.01 * spur_ppte and fine < 0.01 * spur_ppte
    # a non-integer overlap ratio leaves a ripple; the sliced result converges as the slices are refined
    hel2 = go.GearPair.from_profile_shifts(helix_angle_deg=beta, face_width_mm=0.6 * b, **kw)
    ref = ltca(hel2, 300.0, stiffness=C_PRIME, positions=60, slices=2000).ppte_um
    errors = [abs(ltca(hel2, 300.0, stiffness=C_PRIME, positions=60, slices=n).ppte_um - ref) for n in (5, 50, 500)]
    assert ref > 0.05 * spur_ppte and errors[2] < errors[0] and errors[2] < 0.01 * ref


def test_bad_inputs_named(spur):
    with pytest.raises(GearoptInputError, match="torque_Nm=-1"):
        ltca(spur, -1.0, stiffness=C_PRIME)
    with pytest.raises(GearoptInputError, match="driving_gear=3"):
        ltca(spur, 1.0, driving_gear=3, stiffness=C_PRIME)
    with pytest.raises(GearoptInputError, match="stiffness='soft'"):
        ltca(spur, 1.0, stiffness="soft")
    with pytest.raises(GearoptInputError, match="needs a start"):
        Microgeometry(tip_relief_um=(5.0, 0.0))


@pytest.mark.parametrize("helix_deg, lead_crown_um", [(0.0, 0.0), (0.0, 6.0), (12.0, 0.0)])
def test_several_torques_at_once_are_each_torques_own_ltca_to_the_last_bit(helix_deg, lead_crown_um):
    """``ltca_torques`` shares the layout, gaps and load curves between torques: every output must be that of the
    torque's own ``ltca`` call exactly (spur one-slice, spur with lead crowning (sliced), helical), including the
    flash temperature and root stress computed from them, and a torque whose load reaches past a gap the others
    leave open."""
    from gearopt.contact.ltca import ltca_torques

    pair = go.GearPair.from_profile_shifts(teeth=(30, 60), profile_shifts=(0.2, -0.1), module_mm=3.0,
                                           face_width_mm=20.0, helix_angle_deg=helix_deg)
    mods = Microgeometry(tip_relief_um=(15.0, 10.0), tip_relief_start_diameter_mm=(94.5, 184.0),
                         lead_crown_um=(lead_crown_um, 0.0))
    torques = [20.0, 250.0, 900.0]
    kw = dict(microgeometry=mods, speed_rpm=3000.0, positions=60)
    together = ltca_torques(pair, torques, **kw)
    assert len(together) == 3
    for t, r in zip(torques, together):
        alone = ltca(pair, t, **kw)
        for name in ("transmission_error_um", "load_sharing", "load_intensity_N_per_mm", "contact_stress_MPa",
                     "loaded_pairs", "flash_temperature_rise_K"):
            np.testing.assert_array_equal(getattr(r, name), getattr(alone, name), err_msg=f"{name} at {t} N m")
        assert r.max_root_stress_MPa == alone.max_root_stress_MPa
        assert r.transverse_force_N == alone.transverse_force_N
    # the torques differ in what they load: the light one leaves relieved contact open that the heavy one closes
    assert together[0].loaded_contact_ratio < together[2].loaded_contact_ratio
    # and each approach solves its own force balance, checked by a bracketing root finder on the layout's springs
    from scipy.optimize import brentq

    lay = together[0].layout
    gap, spring = lay.gaps_um(mods), lay.spring_N_per_um
    for r in together:
        for p in range(0, lay.positions, 7):
            on = lay.on_path[p]
            e, c = gap[p][on], spring[p][on]
            ref = brentq(lambda d: float(np.sum(c * np.maximum(d - e, 0.0))) - r.transverse_force_N,
                         e.min(), e.max() + r.transverse_force_N / c.sum() + 1e-6, xtol=1e-13)
            assert r.transmission_error_um[p] == pytest.approx(ref, rel=1e-10, abs=1e-10)


def test_several_torques_name_the_bad_one(spur):
    from gearopt.contact.ltca import ltca_torques

    import casadi as ca

    with pytest.raises(GearoptInputError, match=r"torques_Nm\[1\]=-5"):
        ltca_torques(spur, [100.0, -5.0])
    with pytest.raises(GearoptInputError, match=r"torques_Nm\[1\]"):
        ltca_torques(spur, [100.0, "high"])
    with pytest.raises(GearoptInputError, match=r"torques_Nm\[2\].*NaN"):
        ltca_torques(spur, np.array([100.0, 200.0, np.nan]))
    with pytest.raises(GearoptInputError, match="torques_Nm"):
        ltca_torques(spur, ca.MX.sym("T", 2))
    with pytest.raises(GearoptInputError, match="torque_Nm=-1"):      # ltca keeps naming its own parameter
        ltca(spur, -1.0)
    assert ltca_torques(spur, []) == []
    # arrays and CasADi numbers are torques too, in their order
    by_list = ltca_torques(spur, [100.0, 200.0])
    for given in (np.array([[100.0], [200.0]]), ca.DM([100.0, 200.0]), (100.0, 200.0)):
        assert [r.ppte_um for r in ltca_torques(spur, given)] == [r.ppte_um for r in by_list]
