"""The pair geometry is one typed record, computed once per pair and shared by the models that read it."""

from __future__ import annotations

import itertools
import os
import sys

from dataclasses import replace

import casadi as ca
import pytest

import gearopt as go
from gearopt.geometry.record import PairGeometry

GEOMETRY_DIR = os.path.dirname(go.geometry.__file__)


_FRESH = itertools.count()


def _fresh_pair() -> go.GearPair:
    # a pair no test has built yet (equal numeric pairs share one geometry record per process): the crank-cam
    # pair with a face width of its own
    pair = go.load_default_train("spur").pairs["crank-cam"]
    return replace(pair, face_width_mm=tuple(b + 1e-6 * (1 + next(_FRESH)) for b in pair.face_width_mm))


def _geometry_calls(fn) -> int:
    """Number of Python function calls into gearopt/geometry/ made while ``fn`` runs."""
    count = 0

    def profiler(frame, event, arg):
        nonlocal count
        if event == "call" and frame.f_code.co_filename.startswith(GEOMETRY_DIR):
            count += 1

    sys.setprofile(profiler)
    try:
        fn()
    finally:
        sys.setprofile(None)
    return count


def test_one_ltca_computes_the_geometry_about_once():
    # acceptance of the architecture issue: at most 1.5x the calls of one fresh pair.geometry()
    pair = _fresh_pair()
    one = _geometry_calls(pair.geometry)
    pair = _fresh_pair()
    during = _geometry_calls(lambda: go.ltca(pair, torque_Nm=300.0, speed_rpm=2500.0).max_flash_temperature_C)
    assert one > 50
    assert during <= 1.5 * one


def test_record_is_computed_once_and_typed():
    pair = _fresh_pair()
    g = pair.geometry()
    assert isinstance(g, PairGeometry)
    assert pair.geometry() is g
    assert g.centre_distance_mm == g["centre_distance_mm"]
    assert isinstance(g.tip_diameter_mm, tuple) and isinstance(g.tip_diameter_mm[0], float)
    assert dict(g)["transverse_contact_ratio"] == g.transverse_contact_ratio
    assert list(g)[:2] == ["teeth", "names"] and len(g) == len(dict(g.items()))
    with pytest.raises(Exception):
        g.centre_distance_mm = 1.0  # frozen


def test_misspelled_names_fail_at_once_with_the_valid_names():
    g = _fresh_pair().geometry()
    with pytest.raises(AttributeError, match=r"did you mean centre_distance_mm.*Valid names: teeth, names"):
        g.center_distance_mm
    with pytest.raises(KeyError, match="tip_diameter_mm"):
        g["tip_diameters_mm"]
    assert "tip_diameters_mm" not in g and g.get("tip_diameters_mm") is None


def test_symbolic_pair_gives_a_record_of_expressions():
    x1 = ca.SX.sym("x1")
    pair = go.GearPair.from_centre_distance(teeth=(38, 76), centre_distance_mm=172.24, module_mm=3.0,
                                            profile_shift1=x1)
    g = pair.geometry()
    assert isinstance(g, PairGeometry)
    assert isinstance(g.tip_thickness_mm[0], ca.SX) and ca.depends_on(g.tip_thickness_mm[0], x1)
    value = ca.Function("f", [x1], [g.transverse_contact_ratio])(0.2)
    numeric = go.GearPair.from_centre_distance(teeth=(38, 76), centre_distance_mm=172.24, module_mm=3.0,
                                               profile_shift1=0.2).geometry()
    assert float(value) == pytest.approx(numeric.transverse_contact_ratio, rel=1e-12)
