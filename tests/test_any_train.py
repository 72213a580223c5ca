"""Every entry point on a train that is not the packaged timing train: the packaged minimal pair and a copy of it
whose gears and mesh carry other names (issue 26's acceptance interface). Each command exits 0 (every requirement
met) or 1 (a requirement fails), reports the user's names and never the timing train's; a missing section the
command needs exits 2 with a message naming the file and the section."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import gearopt as go
from gearopt.cli import main
from gearopt.data import default_data_path

ROOT = Path(__file__).resolve().parents[1]
MINIMAL = default_data_path().parent / "minimal_train.toml"
TIMING_NAMES = ("crank-cam", "cam-ac", "cam-fp", "crank-lpi", "lpi-lpg", "crank", "lpi", "lpg")
RENAMED = {"pinion": "sun_gear", "wheel": "drum_gear"}


def _renamed(tmp_path: Path) -> Path:
    text = MINIMAL.read_text(encoding="utf-8")
    for old, new in RENAMED.items():
        text = re.sub(rf"\b{old}\b", new, text)
    path = tmp_path / "renamed.toml"
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture(params=["minimal", "renamed"])
def train_file(request, tmp_path) -> tuple[Path, str]:
    """(data file, its mesh name)."""
    if request.param == "minimal":
        return MINIMAL, "pinion-wheel"
    return _renamed(tmp_path), "sun_gear-drum_gear"


def _run(argv, capsys) -> tuple[int, str]:
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out + out.err


def _names_only_the_users(text: str, mesh: str) -> None:
    assert mesh in text
    words = set(re.findall(r"[A-Za-z_]+(?:-[A-Za-z_]+)?", text))
    assert not words & set(TIMING_NAMES), f"the timing train's names leak: {words & set(TIMING_NAMES)}"
    assert "Traceback" not in text


def test_the_system_record_carries_the_users_names(train_file):
    path, mesh = train_file
    system = go.load_system(path)
    assert list(system.meshes) == [mesh]
    m = system.meshes[mesh]
    assert m.design_torque_Nm == 120.0 and system.torque_range_Nm(mesh) == (120.0, 60.0, 180.0)
    assert set(system.joints) == set(m.gears)
    assert system.train("spur").pairs[mesh].names == m.gears


def test_rate(train_file, capsys):
    path, mesh = train_file
    code, text = _run(["rate", "--data", path], capsys)
    assert code in (0, 1)
    _names_only_the_users(text, mesh)
    assert f"S_H {mesh}" in text


def test_microgeometry(train_file, capsys):
    path, mesh = train_file
    code, text = _run(["microgeometry", "--mesh", mesh, "--data", path, "--quick"], capsys)
    assert code in (0, 1)
    _names_only_the_users(text, mesh)
    assert f"{mesh}: optimised microgeometry over 60, 120, 180 N m" in text


def test_dynamics(train_file, capsys):
    path, mesh = train_file
    code, text = _run(["dynamics", "--data", path], capsys)
    assert code in (0, 1)
    _names_only_the_users(text, mesh)
    system = go.load_system(path)
    for gear in system.gears:                     # every joint of the user's data judged at each speed
        assert f"slip margin joint:{gear} at 1500 rpm" in text and f"walk-off margin joint:{gear} at 1800 rpm" in text


def test_scene(train_file, capsys):
    path, mesh = train_file
    code, text = _run(["scene", ROOT / "docs" / "scene-example.toml", "--data", path], capsys)
    assert code in (0, 1)
    assert f"-> {mesh} of {path}" in text      # the scene's mesh moved to the data's only mesh, said so
    assert "verdict:" in text and "Traceback" not in text


def test_train_table(train_file, capsys):
    path, mesh = train_file
    code, text = _run(["train", "spur", "--data", path], capsys)
    assert code == 0
    _names_only_the_users(text, mesh)


def _without(path: Path, tmp_path: Path, section: str) -> Path:
    """A copy of ``path`` without the top-level table ``[section]`` (and its sub-tables)."""
    out, skip = [], False
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("["):
            name = line.strip("[] ").split("]")[0].strip("[] ")
            skip = name == section or name.startswith(section + ".")
        if not skip:
            out.append(line)
    target = tmp_path / f"without_{section}.toml"
    target.write_text("\n".join(out) + "\n", encoding="utf-8")
    return target


def test_a_missing_section_is_named(tmp_path, capsys):
    no_exc = _without(MINIMAL, tmp_path, "excitation")
    code, text = _run(["dynamics", "--data", no_exc], capsys)
    assert code == 2 and str(no_exc) in text and "[excitation]" in text and "Traceback" not in text
    no_spur = _without(MINIMAL, tmp_path, "trains.spur")
    code, text = _run(["rate", "--data", no_spur], capsys)
    assert code == 2 and str(no_spur) in text and "[trains.spur]" in text
    no_torque = tmp_path / "no_torque.toml"
    no_torque.write_text(re.sub(r"(?m)^(design_torque_Nm|torque_range_Nm) = .*$", "", MINIMAL.read_text()))
    for argv in (["rate"], ["microgeometry", "--quick"]):
        code, text = _run([*argv, "--data", no_torque], capsys)
        assert code == 2 and str(no_torque) in text and "design_torque_Nm" in text, (argv, text)


def test_unknown_mesh_is_named(capsys):
    code, text = _run(["microgeometry", "--mesh", "sun-planet", "--data", MINIMAL, "--quick"], capsys)
    assert code == 2 and "sun-planet" in text and "pinion-wheel" in text and str(MINIMAL) in text


def test_an_unreachable_centre_distance_names_file_and_mesh(tmp_path, capsys):
    bad = tmp_path / "near.toml"
    bad.write_text(MINIMAL.read_text().replace("centre_distance_mm = 90.5", "centre_distance_mm = 70.0"))
    code, text = _run(["rate", "--data", bad], capsys)
    assert code == 2 and str(bad) in text and "pinion-wheel" in text and "centre_distance_mm" in text
    assert "Traceback" not in text


def test_microgeometry_names_the_users_gears(train_file, capsys):
    path, mesh = train_file
    _, text = _run(["microgeometry", "--data", path, "--quick"], capsys)    # the only mesh, named by default
    gears = mesh.split("-")
    assert f"  {gears[0]}: tip relief" in text and f"  {gears[1]}: tip relief" in text
