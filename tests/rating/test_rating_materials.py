"""Material catalogue: merge of default_train.toml and materials.toml, provenance of every number, computed Blok
coefficient against the gearcalc manual's range, ISO 6336-2's published elasticity factor, errors."""

import dataclasses
import math

import pytest

from gearopt.data import load_default_data
from gearopt.errors import GearoptInputError
from gearopt.rating import materials as mt


def test_catalogue_covers_the_four_material_groups():
    names = set(mt.material_names())
    assert {"20MnCr5", "42CrMo4", "31CrMoV9", "GJS-600-3", "GJL-250"} <= names
    treatments = {mt.material(n).treatment for n in names}
    assert treatments == set(mt.TREATMENTS)


@pytest.mark.parametrize("name", ["20MnCr5", "42CrMo4", "31CrMoV9", "GJS-600-3", "GJL-250"])
def test_every_number_has_a_tagged_source(name):
    m = mt.material(name)
    for f in dataclasses.fields(m):
        value = getattr(m, f.name)
        if isinstance(value, float):
            src = m.source(f.name)
            assert src[0] == "[" and src[2] == "]" and src[1] in "VCEMT", (name, f.name, src)
    assert m.source("thermal_contact_coefficient_N_per_mm_sqrt_s_K").startswith("[C]")


def test_default_data_values_are_reused_not_copied():
    data = load_default_data()["materials"]
    for name in ("20MnCr5", "42CrMo4", "GJL-250"):
        m = mt.material(name)
        assert m.E_MPa == data[name]["E_MPa"] and m.sources["E_MPa"] == data[name]["E_MPa_source"]
    # the computed B_M equals the value the default data quotes for 20MnCr5 (13.44, rounded there)
    assert mt.material("20MnCr5").thermal_contact_coefficient_N_per_mm_sqrt_s_K == pytest.approx(
        data["20MnCr5"]["thermal_contact_coefficient_N_per_mm_sqrt_s_K"], abs=0.005)


def test_blok_coefficient_inside_the_gearcalc_range_for_martensitic_steel():
    # gearcalc manual sec. 14.11: lambda 41-52 N/(s K) and rho c ~3.8 N/(mm^2 K) for martensitic steels,
    # average B_M = 13.6 N/(mm s^0.5 K)
    low, high = math.sqrt(41 * 3.8), math.sqrt(52 * 3.8)
    assert low < mt.material("20MnCr5").thermal_contact_coefficient_N_per_mm_sqrt_s_K < high
    assert mt.thermal_contact_coefficient(46.5, 7850.0, 3.8e6 / 7850.0) == pytest.approx(
        math.sqrt(46.5 * 3.8), rel=1e-12)


def test_elasticity_factor_matches_iso_published_value_for_steel():
    # ISO 6336-2: Z_E = 189.8 sqrt(N/mm^2) for steel/steel (E 206000 MPa, nu 0.3)
    assert mt.elasticity_factor_sqrt_MPa("20MnCr5") == pytest.approx(189.8, abs=0.05)
    # a softer wheel lowers Z_E
    assert mt.elasticity_factor_sqrt_MPa("20MnCr5", "GJL-250") < 189.8


def test_material_is_frozen_and_passes_through():
    m = mt.material("42CrMo4")
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.E_MPa = 1.0
    assert mt.material(m) is m
    assert mt.material_pair(("20MnCr5", m)) == (mt.material("20MnCr5"), m)


def test_errors_name_the_problem():
    with pytest.raises(GearoptInputError, match="unobtainium"):
        mt.material("unobtainium")
    with pytest.raises(GearoptInputError, match="yield_strength_MPa"):
        mt.material("GJL-250").require("yield_strength_MPa")
    with pytest.raises(GearoptInputError, match="one source"):
        mt.merge_catalogue({"A": {"E_MPa": 1.0}}, {"A": {"E_MPa": 2.0}})
    with pytest.raises(GearoptInputError, match="2-tuple"):
        mt.material_pair(("20MnCr5",) * 3)
