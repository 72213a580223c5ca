"""Scene quantities with computed ISO 6336 factors: maximising contact_safety_factor over the face width drives the
width to its upper bound, the scene's values equal rate_iso6336 of the numeric pair, and the scuffing limits hold."""

from dataclasses import replace

import pytest

import gearopt as go
from gearopt.design.scene import DesignVariable, Limit, LoadCase, Objective, Scene
from gearopt.rating import rate_iso6336

MESH = "crank-cam"


def test_scene_safety_factor_quantities_equal_the_rating():
    train = go.load_default_train("spur")
    opts = {"accuracy_grade": 6, "life_h": 10000.0}
    scene = Scene("face width", train=train, load_cases=[LoadCase("rated", 300.0, speed_rpm=2500.0)],
                  variables=[DesignVariable("face_width_mm", MESH, 10.0, 24.0)],
                  objectives=[Objective("contact_safety_factor", MESH, sense="max")],
                  limits=[Limit("root_safety_factor", MESH, lower=1.0),
                          Limit("scuffing_safety_factor_integral", MESH, lower=1.0),
                          Limit("scuffing_safety_factor_flash", MESH, lower=1.0)],
                  iso6336_options=opts)
    built = scene.build()
    assert any(k.startswith("iso6336_rating:") for k in built.built)
    result = built.solve()
    b = result.values[f"{MESH}.face_width_mm"]
    assert b == pytest.approx(24.0, abs=1e-5)            # S_H grows with the face width
    q = result.quantities.set_index("quantity")
    pair = replace(train.pairs[MESH], face_width_mm=(b, b))
    speed = train.gear_speed_rpm(train.pairs[MESH].names[0], 2500.0)  # the scene's driving gear is gear 1
    ref = rate_iso6336(pair, 300.0, speed, **opts)
    assert float(q.loc["contact_safety_factor", "value"]) == pytest.approx(min(map(float, ref.safety_factors["S_H"])),
                                                                           rel=1e-6)
    limits = result.quantities[result.quantities["role"] == "limit"]
    assert (limits["margin"] > -1e-6).all()
