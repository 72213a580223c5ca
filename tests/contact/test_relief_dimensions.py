"""Tip relief as drawing dimensions: start diameter and relief length from the start roll angle."""

import math

import pytest

import gearopt as go
from gearopt.contact.relief_dimensions import tip_relief_dimensions
from gearopt.errors import GearoptInputError


@pytest.fixture(scope="module")
def pair():
    # KHK's profile-shifted spur pair (z 12/24, m 3, x 0.6/0.36)
    return go.GearPair.from_profile_shifts(teeth=(12, 24), profile_shifts=(0.6, 0.36), module_mm=3.0,
                                           pressure_angle_deg=20.0, helix_angle_deg=0.0, face_width_mm=20.0)


def test_start_diameter_from_the_pressure_angle_at_the_point(pair):
    # involute: the roll angle at a point equals tan of the pressure angle there, cos(alpha_y) = d_b / d_y
    d_b = pair.geometry()["base_diameter_mm"][0]
    for roll in (20.0, 25.0, 30.0):
        dims = tip_relief_dimensions(pair, 1, roll)
        assert dims["start_diameter_mm"] == pytest.approx(d_b / math.cos(math.atan(math.radians(roll))), rel=1e-12)


def test_relief_from_sap_spans_the_whole_path_of_contact(pair):
    # from SAP to EAP on one gear is the length of the path of contact g_alpha (ISO 21771)
    g = pair.geometry()
    for gear in (1, 2):
        dims = tip_relief_dimensions(pair, gear, g["sap_roll_deg"][gear - 1], amount_um=8.0)
        assert dims["relief_length_mm"] == pytest.approx(g["length_of_path_of_contact_mm"], rel=1e-9)
        assert dims["amount_um"] == 8.0
        end = tip_relief_dimensions(pair, gear, g["eap_roll_deg"][gear - 1])
        assert end["relief_length_mm"] == pytest.approx(0.0, abs=1e-12)
        assert end["start_diameter_mm"] == pytest.approx(g["eap_diameter_mm"][gear - 1], rel=1e-12)


def test_start_outside_the_active_profile_is_named(pair):
    with pytest.raises(GearoptInputError, match="start_roll_deg=90"):
        tip_relief_dimensions(pair, 1, 90.0)
    with pytest.raises(GearoptInputError, match="gear=3"):
        tip_relief_dimensions(pair, 3, 20.0)
