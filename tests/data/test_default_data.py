"""Packaged default data: provenance on every number, schema builds both trains, the trains are sound designs."""

import pytest

import gearopt as go
from gearopt.data import (load_default_data, load_default_train, load_thesis_tables, missing_provenance,
                          provenance_tags, train_from_data)
from gearopt.errors import GearoptInputError


@pytest.mark.parametrize("loader", [load_default_data, load_thesis_tables])
def test_every_number_has_a_tagged_source(loader):
    data = loader()
    assert missing_provenance(data) == []
    tags = provenance_tags(data)
    assert tags and all(t in "VTCEM" for t in tags.values()), {k: t for k, t in tags.items() if t not in "VTCEM"}


def test_provenance_check_catches_an_undocumented_number():
    assert missing_provenance({"a": {"x_mm": 1.0, "y_mm": 2.0, "y_mm_source": "[E] guess"}}) == ["a.x_mm"]


@pytest.mark.parametrize("kind", ["spur", "helical"])
def test_default_trains_are_sound(kind):
    train = load_default_train(kind)
    assert set(train.pairs) == {"crank-cam", "cam-ac", "cam-fp", "crank-lpi", "lpi-lpg"}
    for name, pair in train.pairs.items():
        pair.check(min_contact_ratio=1.2)  # raises GeometryError naming the limit if the default is unsound
        g = pair.geometry()
        # Cummins service data: timing-gear backlash roughly 0.08-0.33 mm (docs/source-study.md sec. 1)
        assert 0.08 <= g["normal_backlash_min_mm"] <= g["normal_backlash_max_mm"] <= 0.33, name
    if kind == "helical":
        assert float(train.helix_angle_deg) > 0 and all(p.helix_hands for p in train.pairs.values())


def test_default_centre_distances_follow_thesis_table_3_1():
    data = load_default_data()
    thesis = load_thesis_tables()["table_3_1"]
    train = load_default_train("spur")
    for mesh, change in zip(thesis["meshes"], thesis["centre_distance_change_percent"]):
        z1, z2 = train.pairs[mesh].teeth
        standard = 0.5 * 3.0 * (z1 + z2)
        assert data["meshes"][mesh]["centre_distance_mm"] == pytest.approx(standard / (1 + change / 100), abs=1e-3)


def test_unknown_train_kind_is_named():
    with pytest.raises(GearoptInputError, match="kind='bevel'"):
        train_from_data(load_default_data(), "bevel")


def test_top_level_loader():
    assert go.load_default_train("spur").pairs["crank-cam"].teeth == (38, 76)
