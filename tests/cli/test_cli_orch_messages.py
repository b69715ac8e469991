"""Messages of the modalinfo commands that must fit the input: a directory given as a log.

Reference: the file system itself (the path is a directory, not a missing file).
"""

import pytest

from modalinfo.cli import main


@pytest.mark.parametrize("command", [["info"], ["forecast"], ["reorder"]])
def test_a_directory_given_as_a_log_is_called_a_directory(tmp_path, capsys, command):
    assert main([*command, str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"'{tmp_path}' is a directory, not a log file" in err
    assert "does not exist" not in err
