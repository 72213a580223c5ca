"""Partial engagement of face slices (gearopt.contact.layout): a helical pair's slice carries the part of its
contact-line segment that lies on the path of contact.

References, none of them ours: the length of a contact line on the plane of action follows from elementary geometry
(the line rho(y) = rho_0 + y tan(beta_b) clipped to the rectangle A..E x face width); its mean over one base pitch is
eps_alpha * b in the transverse projection (the total contact-line length of a helical pair, ISO 21771 / Niemann &
Winter vol. 2: L_mean = eps_alpha b / cos(beta_b) measured along the line); and a converged reference of the exact
LTCA itself at 641 slices.
"""

import dataclasses
import math

import numpy as np
import pytest

import gearopt as go
from gearopt.contact.layout import mesh_layout
from gearopt.contact.ltca import ltca
from gearopt.contact.microgeometry import Microgeometry


@pytest.fixture(scope="module")
def helical_pair():
    train = go.load_default_train("spur")
    return dataclasses.replace(train, helix_angle_deg=8.0).pairs["crank-cam"]


def _contact_line_length_mm(layout, pair) -> np.ndarray:
    """Face length of the contact lines on the path at every position, from the clipped line alone (no slices):
    pair k's line is rho(y) = rho_ref + k p_bt + (y + b/2) tan(beta_b) for a driving gear 1, on the path where
    A <= rho <= E, i.e. for y in an interval intersected with the face."""
    g = pair.geometry()
    A, E = float(g["sap_roll_length_mm"][0]), float(g["eap_roll_length_mm"][0])
    b, p_bt, tb = layout.face_width_mm, layout.base_pitch_mm, math.tan(layout.base_helix_angle_rad)
    rho_ref = layout.position_roll_deg * math.pi / 180.0 * 0.5 * layout.base_diameter_mm[0]
    total = np.zeros(layout.positions)
    for k in range(-5, 6):
        start = rho_ref + k * p_bt                      # rho at y = -b/2
        y_lo = np.clip((A - start) / tb - 0.5 * b, -0.5 * b, 0.5 * b)
        y_hi = np.clip((E - start) / tb - 0.5 * b, -0.5 * b, 0.5 * b)
        total += y_hi - y_lo
    return total


@pytest.mark.parametrize("slices", [1, 3, 7])
def test_engaged_face_length_is_the_contact_line_length_whatever_the_slices(helical_pair, slices):
    lay = mesh_layout(helical_pair, positions=97, slices=slices)
    engaged = lay.engaged_length_mm.sum(axis=(1, 2))
    np.testing.assert_allclose(engaged, _contact_line_length_mm(lay, helical_pair), rtol=0, atol=1e-9)
    assert np.all(lay.engaged_length_mm[lay.on_path] > 0.0)
    assert np.all(lay.engaged_length_mm <= lay.slice_width_mm + 1e-12)


def test_mean_contact_line_length_is_the_transverse_contact_ratio_times_the_face(helical_pair):
    lay = mesh_layout(helical_pair, positions=2000, slices=5)
    eps_alpha = float(helical_pair.geometry()["transverse_contact_ratio"])
    mean = lay.engaged_length_mm.sum(axis=(1, 2)).mean()
    assert mean == pytest.approx(eps_alpha * lay.face_width_mm, rel=1e-4)


def test_a_spring_sits_on_its_slice_and_on_the_path(helical_pair):
    """Each spring's contact point is the middle of its engaged part: inside its slice and on A..E."""
    lay = mesh_layout(helical_pair, positions=61, slices=7)
    g = helical_pair.geometry()
    A, E = float(g["sap_roll_length_mm"][0]), float(g["eap_roll_length_mm"][0])
    on = lay.on_path
    assert np.all(lay.rho1_mm[on] >= A - 1e-12) and np.all(lay.rho1_mm[on] <= E + 1e-12)
    offset = np.abs(lay.spring_y_mm - lay.slice_y_mm[None, None, :])
    assert np.all(offset <= 0.5 * lay.slice_width_mm + 1e-12)
    partial = on & (lay.engaged_length_mm < lay.slice_width_mm - 1e-9)
    assert partial.any() and np.all(offset[partial] > 0.0)      # a trimmed slice's point moves off its centre


def test_spur_slices_are_whole():
    spur = go.load_default_train("spur").pairs["crank-cam"]
    lay = mesh_layout(spur, positions=40, slices=5)
    np.testing.assert_array_equal(lay.engaged_length_mm, np.where(lay.on_path, lay.slice_width_mm, 0.0))
    np.testing.assert_array_equal(lay.spring_y_mm, np.broadcast_to(lay.slice_y_mm, lay.shape))


@pytest.mark.parametrize("torque_Nm", [100.0, 300.0])
def test_few_slices_give_the_converged_ppte_of_a_low_helix_pair(helical_pair, torque_Nm):
    """8 deg crank-cam with tip relief: 7 slices within 1 % of 641 (with slices switched on and off at their centres
    the error was 5.3 % at 300 N m), and the error falls as the slices are refined."""
    g = helical_pair.geometry()
    start = tuple(p + 0.6 * (e - p) for p, e in zip(g["pitch_point_roll_deg"], g["eap_roll_deg"]))
    mods = Microgeometry(tip_relief_um=(6.0, 6.0), tip_relief_start_roll_deg=start)
    ref = ltca(helical_pair, torque_Nm, microgeometry=mods, positions=320, slices=641).ppte_um
    err = {J: abs(ltca(helical_pair, torque_Nm, microgeometry=mods, positions=320, slices=J).ppte_um - ref) / ref
           for J in (7, 25)}
    assert err[7] < 0.01
    assert err[25] < 0.25 * err[7]


def test_a_layout_is_built_once_per_input_and_kept_read_only(helical_pair):
    """The layout cache (issue 29: the exact search evaluates one pair hundreds of times): the same inputs give the
    same layout; any changed input (a shift, the positions, the slices, the driving gear) another; the kept arrays
    cannot be changed by a caller; and the LTCA on a cached layout equals one on a freshly built layout."""
    from gearopt.contact import layout as layout_module

    a = mesh_layout(helical_pair, positions=48, slices=5)
    assert mesh_layout(helical_pair, positions=48, slices=5) is a
    shifted = dataclasses.replace(helical_pair, profile_shifts=(helical_pair.profile_shifts[0] + 1e-9,
                                                                helical_pair.profile_shifts[1]))
    for other in (mesh_layout(shifted, positions=48, slices=5), mesh_layout(helical_pair, positions=49, slices=5),
                  mesh_layout(helical_pair, positions=48, slices=7),
                  mesh_layout(helical_pair, positions=48, slices=5, driving_gear=2),
                  mesh_layout(helical_pair, positions=np.arange(48) / 48.0, slices=5)):
        assert other is not a
    with pytest.raises(ValueError):
        a.spring_N_per_um[0, 0, 0] = 1.0
    mods = Microgeometry(tip_relief_um=(8.0, 6.0), tip_relief_start_roll_deg=(24.0, 22.0))
    cached = ltca(helical_pair, 300.0, microgeometry=mods, positions=48, slices=5)
    layout_module._LAYOUTS.clear()
    fresh = ltca(helical_pair, 300.0, microgeometry=mods, positions=48, slices=5)
    np.testing.assert_array_equal(cached.transmission_error_um, fresh.transmission_error_um)
    np.testing.assert_array_equal(cached.contact_stress_MPa, fresh.contact_stress_MPa)
