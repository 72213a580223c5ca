"""Bolt preload from nut torque (thesis Eq. 3.49, Shigley Eq. 8-27): stress areas against the published ISO 898-1
table, the nut-factor tables against the data file, the friction-based nut factor, errors."""

import pytest

from gearopt.data import load_default_data, values
from gearopt.errors import GearoptInputError
from gearopt.joints.bolt import (
    NUT_FACTORS,
    bolt_preload,
    bolt_preload_N,
    nut_factor_from_friction,
    nut_factor_range,
    nut_torque_Nm,
    thread_stress_area_mm2,
)


@pytest.mark.parametrize("d, p, area", [(10, 1.5, 58.0), (12, 1.75, 84.3), (14, 2.0, 115.0), (16, 2.0, 157.0),
                                        (20, 2.5, 245.0), (24, 3.0, 353.0), (30, 3.5, 561.0)])
def test_stress_area_matches_iso_898_1_table(d, p, area):
    # EN ISO 898-1 nominal stress areas of coarse threads as tabulated by usefastener.com ("Minimum ultimate tensile
    # loads for metric coarse pitch thread"), printed to 3 significant digits
    assert thread_stress_area_mm2(d, p) == pytest.approx(area, rel=4e-3)


def test_default_data_fine_thread_areas_and_preloads():
    d = values(load_default_data())["joints"]
    for name in ("ac", "fp"):
        j = d[name]
        assert thread_stress_area_mm2(j["nut_thread_diameter_mm"], j["nut_thread_pitch_mm"]) == pytest.approx(
            j["nut_thread_stress_area_mm2"], rel=4e-3)
        assert bolt_preload_N(j["nut_torque_Nm"], j["nut_factor"], j["nut_thread_diameter_mm"]) == pytest.approx(
            j["preload_N"], abs=0.5)


def test_nut_factor_table_matches_thesis_table_3_11_in_the_data():
    t = values(load_default_data())["thesis"]["table_3_11"]
    keys = {"no plating": "thesis/no plating", "zinc plated": "thesis/zinc plated", "lubricated": "thesis/lubricated",
            "cadmium plated": "thesis/cadmium plated"}
    for coating, k_min, k_max in zip(t["coatings"], t["nut_factor_min"], t["nut_factor_max"]):
        assert nut_factor_range(keys[coating]) == (k_min, k_max)
    assert all(row["source"][:3] in ("[T]", "[M]", "[V]") for row in NUT_FACTORS.values())


def test_nut_factor_from_thread_friction_is_about_0_2_at_f_0_15():
    # Shigley's MED sec. 8-8 ([M] not re-read here): with f = f_c = 0.15 the torque relation gives K ~ 0.20 for
    # common sizes, the value taken when nothing is stated. Computed here from the power-screw torque.
    for d, p in ((10, 1.5), (12, 1.75), (16, 2.0), (20, 2.5)):
        k = nut_factor_from_friction(d, p, 0.15, 0.15)
        assert 0.18 < k < 0.21
    # lower friction, lower factor (lubrication); thread and collar friction both count
    ks = [nut_factor_from_friction(16, 1.5, f, f) for f in (0.05, 0.10, 0.15, 0.20)]
    assert all(b > a for a, b in zip(ks, ks[1:]))
    # no friction: only the lead-angle term p/(2 pi d) remains
    assert nut_factor_from_friction(16, 2.0, 0.0, 0.0) == pytest.approx(2.0 / (2 * 3.141592653589793 * 16), rel=1e-12)


def test_preload_range_and_torque_round_trip():
    r = bolt_preload(150.0, 16.0, 1.5, condition="thesis/lubricated", proof_strength_MPa=830.0)
    assert r["preload_min_N"] == pytest.approx(150e3 / (0.16 * 16))
    assert r["preload_max_N"] == pytest.approx(150e3 / (0.12 * 16))
    assert r["thread_stress_MPa"] == pytest.approx(r["preload_max_N"] / thread_stress_area_mm2(16, 1.5))
    # default data note: ~470 MPa thread stress at k 0.12, ~57 % of the class 10.9 proof stress
    assert r["thread_stress_MPa"] == pytest.approx(470, abs=5)
    assert r["proof_utilisation"] == pytest.approx(0.57, abs=0.01)
    assert nut_torque_Nm(bolt_preload_N(150.0, 0.15, 16.0), 0.15, 16.0) == pytest.approx(150.0)


def test_errors():
    with pytest.raises(GearoptInputError, match="nut_factor=0 is below"):
        bolt_preload_N(100.0, 0.0, 16.0)
    with pytest.raises(GearoptInputError, match="thread_diameter_mm=-1 mm"):
        bolt_preload_N(100.0, 0.2, -1.0)
    with pytest.raises(GearoptInputError, match="not in NUT_FACTORS"):
        nut_factor_range("greased")
    with pytest.raises(GearoptInputError, match="exactly one"):
        bolt_preload(100.0, 16.0, condition="thesis/lubricated", nut_factor=0.2)
