"""Numeric pairs with the same defining values share one geometry record (computed once per process)."""

from dataclasses import replace

import pytest

from gearopt.geometry.pair import GearPair


def pair(x1=0.3, face=20.0):
    return GearPair.from_profile_shifts((38, 76), (x1, 0.1), 2.5, face_width_mm=face)


def test_equal_pairs_built_separately_share_their_geometry_record():
    a, b = pair(), pair()
    assert a is not b and a.geometry() is b.geometry()
    assert replace(a, names=a.names).geometry() is a.geometry()


def test_a_pair_that_differs_in_any_value_gets_its_own_geometry():
    a = pair()
    for other in (pair(x1=0.31), pair(face=21.0), replace(a, names=("crank", "cam"))):
        assert other.geometry() is not a.geometry()
    assert pair(face=21.0).geometry()["face_width_mm"] != a.geometry()["face_width_mm"]
    # the shared record holds the same numbers a fresh computation gives
    fresh = pair()._geometry
    for key in ("transverse_contact_ratio", "centre_distance_mm", "tip_diameter_mm"):
        assert a.geometry()[key] == pytest.approx(fresh[key], rel=1e-15)


def test_a_pair_pickles_its_values_not_its_cached_geometry():
    # pickles key cached models (gearopt.studies.epsilon): a pair used since must pickle as it did before, and
    # unpickle to the same geometry
    import pickle

    a = pair()
    before = pickle.dumps(a)
    a.geometry()
    assert pickle.dumps(a) == before
    b = pickle.loads(before)
    assert b == a and b.geometry()["transverse_contact_ratio"] == a.geometry()["transverse_contact_ratio"]
