"""A refused standard output names the files written only when a file was written.

Fixes 47-b (issue 27; the leftover of fixes 45-b): ``StdoutEncodingError`` and a stdout
like /dev/full ended "...; the files written before it are complete" also for commands
that wrote none (``modalinfo info``). Reference: the folder's listing (``os.listdir``:
nothing written).
"""

from __future__ import annotations

import io
import os
import sys

from modalinfo.cli import main as modalinfo_main


def test_a_label_stdout_cannot_encode_names_no_file_when_none_was_written(
        tmp_path, monkeypatch, capsys):
    log = tmp_path / "lab.csv"
    log.write_text("Tip_\u00e9,Tilt\n0.1,0.2\n0.3,-0.1\n0.2,0.4\n", encoding="utf-8")
    monkeypatch.setenv("PYTHONIOENCODING", "ascii")
    monkeypatch.setattr(sys, "stdout", io.TextIOWrapper(io.BytesIO(), encoding="ascii",
                                                        errors="strict", write_through=True))
    assert modalinfo_main(["info", str(log), "--quiet"]) == 1
    err = capsys.readouterr().err
    assert err.startswith("modalinfo info: error: could not write standard output: its "
                          "encoding ascii (from PYTHONIOENCODING) cannot encode"), err
    assert err.endswith("or a UTF-8 locale to print it\n") and err.count("\n") == 1, err
    assert sorted(os.listdir(tmp_path)) == ["lab.csv"]
