"""GearTrain: tree checks, shift propagation at fixed centre distances, speeds, helix hands, helical->spur table.

Shape checks against the thesis' Tables 3.1-3.3 (docs/source-study.md sec. 1: shifts recovered from Table 3.4).
"""


import casadi as ca
import numpy as np
import pytest

import gearopt.geometry as G
from gearopt.errors import GearoptInputError
from gearopt.geometry.conversion import helical_to_spur_table, spur_teeth_from_helical

TEETH = {"crank": 38, "cam": 76, "ac": 38, "fp": 76, "lpi": 24, "lpg": 24}
# housing centre distances recovered from thesis Table 3.1: standard spur a / (1 + change)
CHANGE = {"crank-cam": -0.72025, "cam-ac": -1.61458, "cam-fp": -0.97796, "crank-lpi": -1.77229, "lpi-lpg": -3.41413}


def train(root_profile_shift=0.3124, helix=0.0, **kw):
    gears = {n: G.GearSpec(n, z, 25.0) for n, z in TEETH.items()}
    meshes = {}
    for name, change in CHANGE.items():
        g1, g2 = name.split("-")
        a_std = 1.5 * (TEETH[g1] + TEETH[g2])
        meshes[name] = G.MeshSpec((g1, g2), a_std / (1 + change / 100))
    return G.GearTrain(gears, meshes, root_mesh="crank-cam", root_gear="crank", root_profile_shift=root_profile_shift,
                       helix_angle_deg=helix, **kw)


def test_shift_propagation_closes_every_mesh():
    t = train()
    for name, pair in t.pairs.items():
        g1, g2 = name.split("-")
        x = pair.geometry()["profile_shifts"]
        assert x == pytest.approx((t.profile_shifts[g1], t.profile_shifts[g2]), abs=1e-12)
        # the pair meets its housing centre distance exactly with these shifts
        again = G.GearPair.from_profile_shifts(teeth=pair.teeth, profile_shifts=x, module_mm=3.0)
        assert again.geometry()["centre_distance_mm"] == pytest.approx(t.meshes[name].centre_distance_mm, abs=1e-9)


def test_shape_check_against_thesis_tables_3_3_and_3_2():
    t = train()
    # actual shifts recovered from thesis Table 3.4 (docs/source-study.md sec. 1); crank is the given root shift
    thesis = {"cam": 0.1118, "ac": 0.8777, "fp": 0.6652}
    for gear, x in thesis.items():
        assert t.profile_shifts[gear] == pytest.approx(x, abs=0.001)
    # LPI/LPG tooth counts are not recoverable exactly (about 24): a looser shape check
    assert t.profile_shifts["lpi"] == pytest.approx(0.2787, abs=0.01)
    assert t.profile_shifts["lpg"] == pytest.approx(0.6757, abs=0.02)
    # Table 3.2: sums of shifts normalised by the cam-AC sum
    mt = t.mesh_table()
    norm = mt["sum_profile_shift"] / mt.loc["cam-ac", "sum_profile_shift"]
    for mesh, ref in {"crank-cam": 0.4287, "crank-lpi": 0.5974, "lpi-lpg": 0.9645, "cam-fp": 0.7853}.items():
        assert norm[mesh] == pytest.approx(ref, abs=0.01)


def test_speed_ratios_and_rotation_senses():
    t = train()
    assert t.speed_ratios == pytest.approx({"crank": 1.0, "cam": -0.5, "ac": 1.0, "fp": 0.5, "lpi": -38 / 24,
                                            "lpg": 38 / 24})


def test_helix_hands_alternate_and_pairs_carry_them():
    t = train(helix=6.0)
    assert t.helix_hands["crank"] == "right" and t.helix_hands["cam"] == "left" and t.helix_hands["ac"] == "right"
    for pair in t.pairs.values():
        assert pair.helix_hands[0] != pair.helix_hands[1]


def test_each_gear_has_one_tip_diameter_with_clearance_in_every_mesh():
    t = train()
    for pair in t.pairs.values():
        g = pair.geometry()
        for name, d_a in zip(pair.names, g["tip_diameter_mm"]):
            assert d_a == pytest.approx(t.tip_diameters_mm[name])
        # the smallest tip over a gear's meshes keeps at least the basic-rack clearance 0.25 m everywhere
        assert min(g["bottom_clearance_mm"]) >= 0.25 * 3.0 - 1e-9


def test_symbolic_root_shift_gives_expressions_equal_to_numeric():
    x = ca.SX.sym("x")
    ts, tn = train(root_profile_shift=x), train(root_profile_shift=0.35)
    f = ca.Function("f", [x], [ca.vertcat(*[ts.profile_shifts[g] for g in TEETH])])
    np.testing.assert_allclose(np.array(f(0.35)).ravel(), [tn.profile_shifts[g] for g in TEETH], atol=1e-12)


def test_iso_split_when_no_root_shift_given():
    t = train(root_profile_shift=None)
    x1, x2 = G.shift_split_iso_tr_4467((38, 76), t.pairs["crank-cam"].geometry()["sum_profile_shift"], 0.5)
    assert t.profile_shifts["crank"] == pytest.approx(x1) and t.profile_shifts["cam"] == pytest.approx(x2)


def test_tree_errors_are_named():
    gears = {n: G.GearSpec(n, z, 20.0) for n, z in (("a", 20), ("b", 30), ("c", 40))}
    with pytest.raises(GearoptInputError, match="tree"):
        G.GearTrain(gears, {"a-b": G.MeshSpec(("a", "b"), 50.0)})
    with pytest.raises(GearoptInputError, match="gear 'd'"):
        G.GearTrain(gears, {"a-b": G.MeshSpec(("a", "b"), 50.0), "a-d": G.MeshSpec(("a", "d"), 50.0)})
    with pytest.raises(GearoptInputError, match="not connected"):
        gears4 = dict(gears, d=G.GearSpec("d", 20, 20.0))
        G.GearTrain(gears4, {"a-b": G.MeshSpec(("a", "b"), 50.0), "b-a": G.MeshSpec(("b", "a"), 50.0),
                             "c-d": G.MeshSpec(("c", "d"), 60.0)})
    with pytest.raises(GearoptInputError, match="root_gear='c'"):
        G.GearTrain(gears, {"a-b": G.MeshSpec(("a", "b"), 50.0), "b-c": G.MeshSpec(("b", "c"), 70.0)},
                    root_mesh="a-b", root_gear="c")


def test_helical_to_spur_reproduces_thesis_table_3_1_mechanism():
    # A helical train of z 37 (crank), 74 (cam), 24 (LPI) at beta 11.55 deg, m_n 3, keeps its reference diameters
    # with spur gears of z = round(d/m) = 38, 76, 24 (thesis Eq. 3.1): the crank-LPI ratio changes by 38/37 - 1 =
    # 2.7027 %, the thesis' Table 3.1 value, while crank-cam keeps its ratio.
    beta = 11.55
    assert [spur_teeth_from_helical(z, 3.0, beta) for z in (37, 74, 24)] == [38, 76, 24]
    gears = {n: G.GearSpec(n, z, 25.0) for n, z in (("crank", 37), ("cam", 74), ("lpi", 24))}
    a = {"crank-cam": 172.24, "crank-lpi": 94.68}
    meshes = {k: G.MeshSpec(tuple(k.split("-")), v) for k, v in a.items()}
    helical = G.GearTrain(gears, meshes, helix_angle_deg=beta, root_mesh="crank-cam")
    df = helical_to_spur_table(helical)
    assert df.loc["crank-lpi", "speed_ratio_error_percent"] == pytest.approx(2.7027, abs=5e-5)
    assert df.loc["crank-cam", "speed_ratio_error_percent"] == pytest.approx(0.0, abs=1e-12)
    assert df.loc["crank-cam", "centre_distance_change_percent"] == pytest.approx((171 - 172.24) / 172.24 * 100)
