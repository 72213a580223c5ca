"""The walk-off demand as a scene quantity through a free helix angle: ``axial_utilisation`` is |F_a| / F_cap (the
inverse of ``axial_margin``, from walk_off's thrust and the joint's capacity), 0 and smooth at a helix angle of 0;
a margin limit at or below 0 holds for every design and constrains nothing."""

import dataclasses

import numpy as np
import pytest

import gearopt as go
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.joints import joint_capacity
from gearopt.joints.walk_off import walk_off

TORQUES = {"crank-cam": 300.0, "cam-ac": 240.0, "cam-fp": 150.0}


def _scene(limits, objective_sense="max", upper=8.0):
    case = LoadCase("over", TORQUES, speed_rpm=3000.0)
    return Scene("thrust", train=go.load_default_train("spur"), data=go.load_system(), load_cases=[case],
                 variables=[DesignVariable("helix_angle_deg", "train", lower=0.0, upper=upper, init=3.0)],
                 objectives=[Objective("transverse_contact_ratio", "crank-cam", sense=objective_sense)],
                 limits=limits)


def test_axial_utilisation_is_the_thrust_over_the_capacity():
    built = _scene([Limit("axial_utilisation", "cam", upper=1.0), Limit("axial_margin", "cam", lower=1.0)]).build()
    cap = joint_capacity(go.load_system(), "cam", speed_rpm=3000.0).axial_capacity_N
    for beta in (0.0, 2.0, 6.0):
        table = built.quantities_at({"train.helix_angle_deg": beta})
        value = table.query("quantity == 'axial_utilisation'")["value"].iloc[0]
        thrust = walk_off(dataclasses.replace(go.load_default_train("spur"), helix_angle_deg=beta),
                          TORQUES).axial_force_N["cam"]
        assert value == pytest.approx(abs(float(thrust)) / cap, rel=1e-9, abs=1e-15)
        if beta > 0:
            margin = table.query("quantity == 'axial_margin'")["value"].iloc[0]
            assert value * margin == pytest.approx(1.0, rel=1e-9) and 0.0 < value < 0.05
        else:
            assert value == 0.0


def test_an_upper_limit_on_axial_utilisation_caps_the_helix_angle():
    # the contact ratio grows with the helix angle: the optimum sits where the thrust meets the limit
    free = _scene([]).build().solve()
    assert free.values["train.helix_angle_deg"] == pytest.approx(8.0, abs=1e-4)
    capped = _scene([Limit("axial_utilisation", "cam", upper=0.004)]).build().solve()
    u = capped.quantities.query("quantity == 'axial_utilisation'")["value"].iloc[0]
    assert u == pytest.approx(0.004, rel=1e-5) and 0.5 < capped.values["train.helix_angle_deg"] < 7.5


def test_a_margin_limit_at_or_below_zero_constrains_nothing():
    # cap/|F| >= -1 holds for every design; squared it would read |F| <= cap, the old behaviour -- it must not bind
    loose = _scene([Limit("axial_margin", "cam", lower=-1e6)]).build().solve()
    assert loose.values["train.helix_angle_deg"] == pytest.approx(8.0, abs=1e-4)
    row = loose.quantities.query("quantity == 'axial_margin'").iloc[0]
    assert np.isfinite(row["value"]) and row["margin"] > 0
