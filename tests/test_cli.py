"""The command line prints the geometry of a pair and reports bad input as a named error (exit code 2)."""

from gearopt.cli import main


def test_pair_from_shifts_prints_khk_centre_distance(capsys):
    # KHK profile-shifted spur example: z 12/24, m 3, x 0.6/0.36 -> a = 56.4999 mm
    assert main(["pair", "--teeth", "12", "24", "--module-mm", "3", "--profile-shifts", "0.6", "0.36"]) == 0
    out = capsys.readouterr().out
    line = next(l for l in out.splitlines() if l.startswith("centre_distance_mm "))
    assert abs(float(line.split()[1]) - 56.4999) < 1e-4


def test_bad_input_is_named(capsys):
    assert main(["pair", "--teeth", "20", "40", "--module-mm", "2", "--centre-distance-mm", "50"]) == 2
    assert "centre_distance_mm=50.0000 is unreachable" in capsys.readouterr().err


def test_default_train(capsys):
    assert main(["train", "spur"]) == 0
    assert "crank-cam" in capsys.readouterr().out


# ----------------------------------------------------------------------------- studies on a data file, exit codes
import shutil
import tomllib
from pathlib import Path

import pytest

import gearopt as go
from gearopt.data import default_data_path
from gearopt.errors import GearoptInputError

ROOT = Path(__file__).resolve().parents[1]


def test_check_failure_exits_non_zero(capsys):
    # KHK pair (contact ratio 1.202) against a 1.3 minimum: the check fails and says so
    argv = ["pair", "--teeth", "12", "24", "--module-mm", "3", "--profile-shifts", "0.6", "0.36"]
    assert main(argv + ["--min-contact-ratio", "1.3"]) == 1
    assert "check: FAIL" in capsys.readouterr().out
    assert main(argv + ["--min-contact-ratio", "1.2"]) == 0


def _data_with(tmp_path, old: str, new: str) -> Path:
    text = default_data_path().read_text()
    assert text.count(old) == 1
    path = tmp_path / "my_train.toml"
    path.write_text(text.replace(old, new))
    return path


def test_rate_reads_the_users_file_and_fails_on_a_low_safety(tmp_path, capsys):
    assert main(["rate"]) == 0                                         # packaged data: every S_H, S_F passes
    capsys.readouterr()
    # ten times the crank-cam torque: sigma_H grows with sqrt(T) (ISO 6336-2), S_H 1.95 -> ~0.62 < 1
    path = _data_with(tmp_path, "design_torque_Nm = 300.0", "design_torque_Nm = 3000.0")
    assert main(["rate", "--data", str(path), "--unit-factors"]) == 1
    out = capsys.readouterr().out
    line = next(l for l in out.splitlines() if l.startswith("S_H crank-cam"))
    # load factors 1: the analytic law sigma_H ~ sqrt(T) holds exactly
    assert line.endswith("FAIL") and float(line.split()[2]) == pytest.approx(1.948 / 10 ** 0.5, rel=0.01)
    # by default every factor is computed (issue 27): K_v, K_Hbeta, K_Halpha > 1 lower S_H further
    assert main(["rate", "--data", str(path)]) == 1
    out = capsys.readouterr().out
    computed = next(l for l in out.splitlines() if l.startswith("S_H crank-cam"))
    assert computed.endswith("FAIL") and float(computed.split()[2]) < float(line.split()[2])
    assert "every factor computed" in out and "S_B crank-cam" in out


def test_scene_from_file_solves_and_names_bad_keys(tmp_path, capsys):
    assert main(["scene", str(ROOT / "docs" / "scene-example.toml")]) == 0
    out = capsys.readouterr().out
    assert "Solve_Succeeded" in out and "verdict: PASS" in out
    bad = tmp_path / "bad.toml"
    bad.write_text((ROOT / "docs" / "scene-example.toml").read_text().replace("upper = 1150.0", "uper = 1150.0"))
    assert main(["scene", str(bad)]) == 2
    assert "did you mean 'upper'" in capsys.readouterr().err


def test_scene_file_matches_the_python_scene():
    from gearopt.design import Limit
    from gearopt.design.scene_file import scene_from_data

    scenes = tomllib.loads((ROOT / "docs" / "scene-example.toml").read_text())
    with pytest.raises(GearoptInputError, match="did you mean 'crank_cam_ppte'"):
        scene_from_data(scenes, "crank_cam_pte")
    scene = scene_from_data(scenes, "crank_cam_ppte", train_data=go.load_system())
    assert [lc.mesh_torque_Nm("crank-cam") for lc in scene.load_cases] == [150.0, 300.0, 450.0]
    assert scene.limits[0] == Limit("max_contact_stress_MPa", "crank-cam", upper=1150.0)


def test_dynamics_sweep_exits_1_when_a_joint_slips(capsys):
    # the source study's finding: at overspeed the crank gear's press fit slips (margin < 1) with backlash
    assert main(["dynamics", "--speeds", "3000", "--run-in-cycles", "0", "--joints", "crank", "cam"]) == 1
    out = capsys.readouterr().out
    crank = next(l for l in out.splitlines() if l.startswith("slip margin joint:crank"))
    cam = next(l for l in out.splitlines() if l.startswith("slip margin joint:cam"))
    assert crank.endswith("FAIL") and float(crank.split()[6]) < 1.0
    assert cam.endswith("PASS")
