"""A refused stdout names the files written by THIS command only (review30, round 30 S2).

Fixes 47-b counts ``atomic_write``'s completed files before and after a command (the
note "the files written before it are complete" only when the command wrote one).
test_stdout_refusal_files_fix47b.py runs in a process that has written nothing, so a
planted ``if files_written() else`` (any file of the process: an earlier command run by
``main`` in the same interpreter, a notebook's or a test's) passed. Reference: the
folder's listing (``info`` wrote nothing) after a file written earlier in the process.
"""

from __future__ import annotations

import io
import os
import sys

from modalinfo.cli import main as modalinfo_main
from modalinfo.common.files import atomic_write


def test_a_file_written_earlier_in_the_process_is_not_claimed(tmp_path, monkeypatch,
                                                              capsys):
    atomic_write(tmp_path / "earlier.txt", lambda f: f.write(b"x"), overwrite=False)
    log = tmp_path / "lab.csv"
    log.write_text("Tip_\u00e9,Tilt\n0.1,0.2\n0.3,-0.1\n0.2,0.4\n", encoding="utf-8")
    before = sorted(os.listdir(tmp_path))
    monkeypatch.setenv("PYTHONIOENCODING", "ascii")
    monkeypatch.setattr(sys, "stdout", io.TextIOWrapper(io.BytesIO(), encoding="ascii",
                                                        errors="strict", write_through=True))
    assert modalinfo_main(["info", str(log), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("modalinfo info: error: could not write standard output"), err
    assert "files written" not in err and err.count("\n") == 1, err
    assert sorted(os.listdir(tmp_path)) == before
