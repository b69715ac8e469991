r"""Batch's error lines and table tell ``a\xe9.csv`` from ``a<0xE9>.csv`` (fixes 48-a).

Round 45 PART b, E21: a shown line must tell a file literally named ``a\xe9.csv`` (a
backslash, x, e, 9) from one whose name holds the byte 0xE9. After fixes 47-e the
message cells were shown as written, while the readers' messages still quoted the raw
path: both files' error lines read ``... 'in/a\xe9.csv' ...``. Here the rows are the
real task's (``run_log_task`` under ``_limited_call``, as a Dask worker runs it) for two
cut CSV files, judged in batch's stdout (``analyse_archive`` replaced by a stand-in, as
in review 29) and in batch.csv (Python's csv module reading it back). References: the
files' bytes (``os.fsencode``) and ``codecs.escape_decode`` of each quoted name.
"""

from __future__ import annotations

import codecs
import csv
import os
import re

import pytest

from modalinfo.cli import main

from .conftest import batch_stand_in

NAMES = [b"a\\xe9.csv", b"a\xe9.csv"]  # a literal backslash; the byte 0xE9


def _rows(folder: bytes) -> list[dict]:
    from modalinfo.batch.analyses import resolve_params, run_log_task
    from modalinfo.common.tasks.threads import _limited_call

    rows = []
    for name in NAMES:
        path = os.fsdecode(os.path.join(folder, name))
        with open(path, "w") as fh:
            fh.write("1,2\n3,4\n5\n")  # the last row cut
        payload = {"path": path, "fmt": None, "hints": {}, "analysis": "summary",
                   "params": resolve_params("summary")}
        rows.append({"path": path, "analysis": "summary", **_limited_call(
            run_log_task, payload, 1)})
    return rows


def _quoted_bytes(text: str) -> list[bytes]:
    text.encode("utf-8")  # printable: no lone surrogate
    return [codecs.escape_decode(q.encode("utf-8"))[0] for q in re.findall(r"'([^']*)'", text)]


def test_two_files_error_lines_name_their_own_bytes(tmp_path, monkeypatch, capsys):
    folder = os.fsencode(tmp_path / "in")
    os.mkdir(folder)
    rows = _rows(folder)
    assert [r["status"] for r in rows] == ["error", "error"]
    result = batch_stand_in(rows, tmp_path / "out")
    monkeypatch.setattr("modalinfo.batch.analyse_archive", lambda *a, **k: result)
    assert main(["batch", str(tmp_path / "in"), "--out", str(tmp_path / "out")]) == 1
    lines = [x for x in capsys.readouterr().out.splitlines() if x.startswith("error  ")]
    assert len(lines) == 2 and lines[0] != lines[1]
    for name, line in zip(NAMES, lines, strict=True):
        message = line.split(": ", 2)[2]  # after "error  PATH [summary]: TYPE: "
        assert os.path.join(folder, name) in _quoted_bytes(message), line


def test_two_files_message_cells_name_their_own_bytes(tmp_path):
    pytest.importorskip("pyarrow")
    from modalinfo.common.tasks.rows import write_table

    folder = os.fsencode(tmp_path)
    rows = _rows(folder)
    csv_path, _ = write_table(rows, tmp_path, "batch")
    with open(csv_path, newline="", encoding="utf-8") as fh:
        cells = [r["error_message"] for r in csv.DictReader(fh)]
    assert cells[0] != cells[1]
    for name, cell in zip(NAMES, cells, strict=True):
        assert os.path.join(folder, name) in _quoted_bytes(cell), cell


def test_another_librarys_raw_quote_of_the_rows_path_is_shown(tmp_path):
    """A text we do not write (h5py's ``name = '<path>'``) may quote the row's path raw."""
    pytest.importorskip("pyarrow")
    from modalinfo.common.tasks.rows import write_table

    path = os.fsdecode(os.path.join(os.fsencode(tmp_path), NAMES[0]))
    message = f"Unable to open file (unable to open file: name = '{path}', errno = 2)"
    csv_path, _ = write_table([{"path": path, "error_message": message}], tmp_path, "t")
    with open(csv_path, newline="", encoding="utf-8") as fh:
        (row,) = list(csv.DictReader(fh))
    assert _quoted_bytes(row["error_message"]) == [os.fsencode(path)], row["error_message"]
