r"""Batch's stdout error line shows another library's raw quote of the row's path (review 31).

Round 31 mutation, plant B2: ``cmd_batch`` calling ``shown_message`` without the row's
path passed every test: ``tests/cli/test_batch_shown_lines_fix48a.py`` checks the raw
quote (h5py's ``name = '<path>'``) in batch.csv's cell only, and the error lines with
messages of ours, already quoted. Reference: the file's bytes (``os.fsencode``) and
``codecs.escape_decode`` of the quoted name on the line (``ls -b``'s escapes to bytes).
"""

from __future__ import annotations

import os

from modalinfo.cli import main
from tests.cli.test_batch_shown_lines_fix48a import NAMES, _quoted_bytes

from .conftest import batch_stand_in


def test_a_raw_quote_of_the_rows_path_is_shown_on_its_error_line(tmp_path, monkeypatch, capsys):
    os.mkdir(tmp_path / "in")
    path = os.fsdecode(os.path.join(os.fsencode(tmp_path / "in"), NAMES[0]))
    message = f"Unable to open file (unable to open file: name = '{path}', errno = 2)"
    rows = [{"path": path, "analysis": "summary", "status": "error", "error_type": "OSError",
             "error_message": message}]
    result = batch_stand_in(rows, tmp_path / "out")
    monkeypatch.setattr("modalinfo.batch.analyse_archive", lambda *a, **k: result)
    assert main(["batch", str(tmp_path / "in"), "--out", str(tmp_path / "out")]) == 1
    (line,) = [x for x in capsys.readouterr().out.splitlines() if x.startswith("error  ")]
    shown = line.split(": ", 2)[2]  # after "error  PATH [summary]: TYPE: "
    assert _quoted_bytes(shown) == [os.fsencode(path)], line
