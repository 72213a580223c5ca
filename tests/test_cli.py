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
