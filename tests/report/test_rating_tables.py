"""Rating table of a train: rows and columns for the default spur and helical trains, agreement with the direct
rating calls, material overrides, errors."""

import pandas as pd
import pytest

import gearopt as go
from gearopt.errors import GearoptInputError
from gearopt.rating.contact_stress import contact_stress_iso6336
from gearopt.rating.root_stress import root_stress_iso6336
from gearopt.report.rating_tables import rating_table

COLUMNS = ["mesh", "gear_1", "gear_2", "torque_Nm", "F_t_N", "sigma_H0_MPa", "sigma_H_MPa", "S_H", "sigma_H_1_MPa",
           "sigma_H_2_MPa", "S_H_1", "S_H_2", "sigma_F_1_MPa", "sigma_F_2_MPa", "S_F_1", "S_F_2", "Y_F_1", "Y_S_1",
           "Y_F_2", "Y_S_2", "method"]


@pytest.mark.parametrize("kind", ["spur", "helical"])
def test_table_of_the_default_trains(kind):
    train = go.load_default_train(kind)
    torques = {"crank-cam": 300.0, "cam-fp": 150.0, "lpi-lpg": 5.0}
    df = rating_table(train, torques, K_A=1.25)
    assert list(df.columns) == COLUMNS
    assert list(df["mesh"]) == ["crank-cam", "cam-fp", "lpi-lpg"]  # the train's order, rated meshes only
    for _, row in df.iterrows():
        pair = train.pairs[row["mesh"]]
        c = contact_stress_iso6336(pair, row["torque_Nm"], K_A=1.25)
        r = root_stress_iso6336(pair, row["torque_Nm"], K_A=1.25)
        assert row["sigma_H_MPa"] == pytest.approx(max(c["sigma_H_MPa"]), rel=1e-12)
        assert row["S_H"] == pytest.approx(min(c["safety_factor"]), rel=1e-12)
        assert row["S_F_2"] == pytest.approx(r["gear2"]["safety_factor"], rel=1e-12)
        assert row["S_H"] > 1.0 and row["S_F_1"] > 1.0  # the timing gears are far from their limits at 300 N m
        assert "ISO 6336-2" in row["method"] and "ISO 6336-3" in row["method"]


def test_material_override_changes_the_safety_not_the_stress_of_root():
    train = go.load_default_train("spur")
    base = rating_table(train, {"crank-cam": 300.0})
    soft = rating_table(train, {"crank-cam": 300.0}, materials={"cam": "42CrMo4"})
    assert soft["sigma_F_2_MPa"][0] == pytest.approx(base["sigma_F_2_MPa"][0], rel=1e-14)
    assert soft["S_F_2"][0] == pytest.approx(base["S_F_2"][0] * 315 / 500, rel=1e-12)
    assert soft["S_H_2"][0] < base["S_H_2"][0]


def test_errors():
    train = go.load_default_train("spur")
    with pytest.raises(GearoptInputError, match="unknown mesh"):
        rating_table(train, {"crank-moon": 10.0})
    with pytest.raises(GearoptInputError, match="empty"):
        rating_table(train, {})


def test_the_table_is_the_one_train_rating_table_with_given_factors():
    from gearopt.rating import iso6336_train_table

    train = go.load_default_train("helical")
    torques = {"crank-cam": 300.0, "cam-ac": 120.0}
    loads = dict(K_v=1.2, K_Hbeta=1.3, K_Halpha=1.05, K_Fbeta=1.2, K_Falpha=1.1)
    df = rating_table(train, torques, K_A=1.25, materials={"cam": "42CrMo4"}, **loads)
    same = iso6336_train_table(train, torques, factors="given", application_factor=1.25, materials={"cam": "42CrMo4"},
                               **loads)
    pd.testing.assert_frame_equal(df, same, check_exact=True)
    with pytest.raises(GearoptInputError, match="factors='computed'"):
        iso6336_train_table(train, torques, factors="given", life_h=1000.0)
    with pytest.raises(GearoptInputError, match="root_speed_rpm"):
        iso6336_train_table(train, torques)
    with pytest.raises(GearoptInputError, match="factors="):
        iso6336_train_table(train, torques, 2500.0, factors="guessed")
