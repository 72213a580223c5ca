"""Every problem script takes the user's own train: ``--data FILE``."""

import pytest
from conftest import PROBLEMS, load_script

from gearopt.errors import DataFileError

SCRIPTS = sorted(p.stem for p in PROBLEMS.glob("*.py"))


@pytest.mark.parametrize("name", SCRIPTS)
def test_script_takes_data_file(name, capsys):
    with pytest.raises(SystemExit) as exit_:
        load_script(name).main(["--help"])
    assert exit_.value.code == 0
    assert "--data FILE" in capsys.readouterr().out


def test_missing_data_file_is_named(tmp_path):
    with pytest.raises(DataFileError, match="no_such_train.toml.*not found"):
        load_script("shift_split").main(["--quick", "--out", str(tmp_path), "--data", str(tmp_path / "no_such_train.toml")])
