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


def test_scene_rating_takes_each_gears_own_grade_and_material_on_a_renamed_pair(tmp_path):
    """Any train: on the packaged minimal pair renamed (sun_gear/drum_gear) with the second gear at ISO 1328 grade 8,
    a scene with the data rates with grades (6, 8) and the gears' materials, as the verdict's rating table does."""
    import re

    from gearopt.data import default_data_path, load_system
    from gearopt.design.requirements import rating_table

    text = (default_data_path().parent / "minimal_train.toml").read_text(encoding="utf-8")
    for old, new in {"pinion": "sun_gear", "wheel": "drum_gear"}.items():
        text = re.sub(rf"\b{old}\b", new, text)
    first = text.index("accuracy_grade_iso1328 = 6")
    second = text.index("accuracy_grade_iso1328 = 6", first + 1)
    text = text[:second] + "accuracy_grade_iso1328 = 8" + text[second + len("accuracy_grade_iso1328 = 6"):]
    path = tmp_path / "renamed.toml"
    path.write_text(text, encoding="utf-8")
    system = load_system(path)
    kind = next(iter(system.trains))
    train = system.train(kind)
    mesh = next(iter(train.pairs))
    assert train.pairs[mesh].names == ("sun_gear", "drum_gear")
    b = float(train.pairs[mesh].face_width_mm[0])
    scene = Scene("rated", train=train, load_cases=[LoadCase("rated", 100.0, speed_rpm=1500.0)],
                  variables=[DesignVariable("face_width_mm", mesh, b - 1.0, b + 1.0, init=b)],
                  objectives=[Objective("contact_safety_factor", mesh, sense="max")],
                  limits=[Limit("root_safety_factor", mesh, lower=0.5)], data=system)
    built = scene.build()
    q = built.quantities_at(built.initial_values()).set_index("quantity")
    table = rating_table(system, train, {mesh: 100.0}, 1500.0, application_factor=1.0).set_index("mesh")
    ref = rate_iso6336(train.pairs[mesh], 100.0, table.loc[mesh, "speed_1_rpm"], accuracy_grade=(6, 8),
                       materials=("20MnCr5", "20MnCr5"))
    same = rate_iso6336(train.pairs[mesh], 100.0, table.loc[mesh, "speed_1_rpm"], accuracy_grade=6)
    for quantity, key in (("contact_safety_factor", "S_H"), ("root_safety_factor", "S_F")):
        expected = min(table.loc[mesh, f"{key}_1"], table.loc[mesh, f"{key}_2"])
        assert float(q.loc[quantity, "value"]) == pytest.approx(expected, rel=1e-9)
        assert expected == pytest.approx(min(map(float, ref.safety_factors[key])), rel=1e-9)
        assert abs(expected / min(map(float, same.safety_factors[key])) - 1.0) > 1e-4    # the grade matters


def test_a_scene_without_scuffing_quantities_rates_without_scuffing_and_the_same_safeties():
    """``rate_iso6336(scuffing=False)`` gives the same S_H and S_F as the full rating and no S_B; a scene rates
    with scuffing only where a scuffing quantity asks for it (at that mesh and load case)."""
    train = go.load_default_train("spur")
    pair = train.pairs[MESH]
    full = rate_iso6336(pair, 300.0, 2500.0, accuracy_grade=6)
    lean = rate_iso6336(pair, 300.0, 2500.0, accuracy_grade=6, scuffing=False)
    for key in ("S_H", "S_F"):
        assert [float(x) for x in lean.safety_factors[key]] == [float(x) for x in full.safety_factors[key]]
    assert "S_B" not in lean.safety_factors and "S_B" in full.safety_factors
    scene = Scene("mixed", train=train, load_cases=[LoadCase("a", 300.0, speed_rpm=2500.0),
                                                    LoadCase("b", 600.0, speed_rpm=2500.0)],
                  variables=[DesignVariable("face_width_mm", MESH, 10.0, 24.0)],
                  objectives=[Objective("contact_safety_factor", MESH, sense="max", load_cases=("b",))],
                  limits=[Limit("scuffing_safety_factor_flash", MESH, lower=1.0, load_cases=("a",))])
    built = scene.build()
    ratings = {lc: built.models[f"iso6336_rating:{MESH}@{lc}"] for lc in ("a", "b")}
    assert "S_B" in ratings["a"].safety_factors and "S_B" not in ratings["b"].safety_factors


def test_symbolic_rating_is_a_kernel_traced_once_equal_to_the_numeric_rating():
    """The rating of a scene with a free helix angle (the packaged minimal pair, another train with other names) is
    one call of an SX kernel traced once per process (``numerics.traced_call``): a second build traces nothing new,
    and S_H, S_F and S_B at designs across the helix range equal ``rate_iso6336`` of the numeric pair (the numeric
    path, which no tracing touches) to 1e-9."""
    from gearopt import numerics as nm
    from gearopt.data import default_data_path, load_system

    system = load_system(default_data_path().parent / "minimal_train.toml")
    train = system.train(next(iter(system.trains)))
    mesh = next(iter(train.pairs))
    scene = Scene("helix", train=train, load_cases=[LoadCase("rated", 120.0, speed_rpm=1800.0)],
                  variables=[DesignVariable("helix_angle_deg", "train", lower=0.0, upper=12.0, init=4.0)],
                  objectives=[Objective("contact_safety_factor", mesh, sense="max")],
                  limits=[Limit("root_safety_factor", mesh, lower=0.5),
                          Limit("scuffing_safety_factor_flash", mesh, lower=0.5)], iso6336_options={"life_h": 2e4})
    built = scene.build()
    traced = nm.traced_kernel_stats()["traced"]
    again = scene.build()
    assert nm.traced_kernel_stats()["traced"] == traced
    speed = train.gear_speed_rpm(train.pairs[mesh].names[0], 1800.0)
    for beta in (0.0, 5.5, 12.0):
        q = again.quantities_at({"train.helix_angle_deg": beta}).set_index("quantity")
        pair = replace(train, helix_angle_deg=beta).pairs[mesh]
        ref = built.models[f"iso6336_rating:{mesh}@rated"]       # the symbolic rating itself is a kernel output
        assert not isinstance(ref.safety_factors["S_H"][0], float)
        numeric = rate_iso6336(pair, 120.0, speed, life_h=2e4, accuracy_grade=(6, 6),
                               materials=tuple(train.gears[g].material for g in pair.names))
        for quantity, key in (("contact_safety_factor", "S_H"), ("root_safety_factor", "S_F"),
                              ("scuffing_safety_factor_flash", "S_B")):
            expected = numeric.safety_factors[key]
            expected = min(map(float, expected)) if isinstance(expected, tuple) else float(expected)
            assert float(q.loc[quantity, "value"]) == pytest.approx(expected, rel=1e-9), (beta, quantity)
    # the kernel's derivative (what Ipopt differentiates) against central differences of the numeric rating
    import casadi as ca
    entry = built.problem._variables["train.helix_angle_deg"]
    s_b = built.models[f"iso6336_rating:{mesh}@rated"].safety_factors["S_B"]
    slope = ca.Function("dS_B", [entry.symbol], [ca.jacobian(s_b, entry.symbol) / float(entry.scale[0])])

    def numeric_s_b(beta):
        pair = replace(train, helix_angle_deg=beta).pairs[mesh]
        return float(rate_iso6336(pair, 120.0, speed, life_h=2e4, accuracy_grade=(6, 6),
                                  materials=tuple(train.gears[g].material for g in pair.names)).safety_factors["S_B"])
    for beta in (3.0, 9.0):
        h = 1e-5
        central = (numeric_s_b(beta + h) - numeric_s_b(beta - h)) / (2 * h)
        assert float(slope(beta / float(entry.scale[0]))) == pytest.approx(central, rel=1e-5, abs=1e-9), beta
