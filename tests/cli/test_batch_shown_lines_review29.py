r"""``modalinfo batch``'s own lines show paths as its table does (review29, round 29 B1-B3).

Stop 53 made every path the batch command prints pass through ``shown_name`` (``ls -b``'s
escapes: a byte that is not UTF-8 as ``\xNN``, a backslash as ``\\``), and names at most
five skipped files followed by ", ..." only when more exist. Planted slips that printed
the raw path or message, or ", ..." after exactly five names, passed every test: the
batch CLI tests run a real Dask batch, whose rows are all ``ok``. Here ``analyse_archive``
is replaced by a stand-in result, so the lines are judged alone. References, from
outside the package: GNU ``ls -b``'s escapes written by hand (``a\\xe9.npz`` for the
name ``a\xe9.npz``, ``b\xff.npz`` for the byte 0xFF), ``codecs.escape_decode`` giving the
name's bytes back, and the count of names given (five: no ", ...").
"""

from __future__ import annotations

import codecs
import os

import pytest

from modalinfo.cli import main

from .conftest import batch_stand_in

SLASH = "in/a\\xe9.npz"  # a literal backslash, then x, e, 9
BYTE = os.fsdecode(b"in/b\xff.npz")  # the byte 0xFF: not UTF-8


def _result(tmp_path, rows, skipped=()):
    return batch_stand_in(rows, tmp_path / "out", skipped=skipped)


def _run(tmp_path, monkeypatch, result) -> int:
    monkeypatch.setattr("modalinfo.batch.analyse_archive", lambda *a, **k: result)
    (tmp_path / "in").mkdir(exist_ok=True)
    return main(["batch", str(tmp_path / "in"), "--out", str(tmp_path / "out")])


@pytest.mark.parametrize(("path", "shown"), [(SLASH, "in/a\\\\xe9.npz"),
                                             (BYTE, "in/b\\xff.npz")])
def test_an_error_row_prints_its_path_and_message_as_ls_b(tmp_path, monkeypatch, capsys,
                                                           path, shown):
    row = {"path": path, "analysis": "summary", "status": "error",
           "error_type": "ValueError", "error_message": f"cannot read '{path}'"}
    assert _run(tmp_path, monkeypatch, _result(tmp_path, [row])) == 1
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("error  "))
    assert line == f"error  {shown} [summary]: ValueError: cannot read '{shown}'"
    assert codecs.escape_decode(shown.encode("utf-8"))[0] == os.fsencode(path)


@pytest.mark.parametrize("n", [5, 6])
def test_skipped_files_note_counts_and_ellipsis(tmp_path, monkeypatch, capsys, n):
    skipped = [f"in/s{k}\\x.dat" for k in range(n)]
    row = {"path": "in/x.npz", "analysis": "summary", "status": "error",
           "error_type": "ValueError", "error_message": "x"}
    assert _run(tmp_path, monkeypatch, _result(tmp_path, [row], skipped)) == 1
    err = capsys.readouterr().err
    note = next(x for x in err.splitlines() if "skipped, their extension" in x)
    names = note.split("): ", 1)[1].split("; name them", 1)[0]
    assert names.split(", ")[:5] == [f"in/s{k}\\\\x.dat" for k in range(5)]
    assert names.endswith(", ...") == (n > 5)  # five names given: nothing left unnamed
    assert note.startswith(f"modalinfo batch: note: {n} file(s)")
