"""A folder given to a one-log command is told what to pass (round 46 PART b, F12).

`modalinfo info b1` (a batch output folder) said "'b1' is a directory, not a log file"
and no more. Reference: the README's batch section (`modalinfo batch DIR --out OUT`
analyses every log of a folder).
"""

from __future__ import annotations

from modalinfo.cli import main


def test_info_of_a_folder_points_to_batch(tmp_path, capsys):
    assert main(["info", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is a directory, not a log file" in err[0]
    assert f"modalinfo batch '{tmp_path}' --out DIR" in err[0]
