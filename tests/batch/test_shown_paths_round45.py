r"""Two files, two paths in batch.csv: a literal backslash is shown ``\\`` (round 45 PART b, E21).

A folder holding ``a<0xE9>.npz`` (a Latin-1 name, not UTF-8) and ``a\xe9.npz`` (backslash,
x, e, 9) gave two rows with different SHA-256 and one ``path``, ``.../a\xe9.npz``: the
undecodable byte was written ``\xe9`` as ``ls -b`` writes it, the backslash was left as it
was where ``ls -b`` writes ``\\`` (modalinfo/common/files.py ``shown_name``, used for every
cell at modalinfo/common/tasks/rows.py ``_utf8_text``). References, outside the package:
GNU ``ls -b``'s escapes (``a\\xe9.npz`` for the backslash name), Python's
``codecs.escape_decode`` (the shown path back to the file's bytes), ``hashlib.sha256`` of
the files, the csv module reading the table. Resume matches rows by task key (SHA-256,
analysis, parameters), never by the shown path: a folder whose table the old rule wrote
resumes with every task skipped.
"""

from __future__ import annotations

import codecs
import csv
import hashlib
import os
from pathlib import Path

import numpy as np
import pytest

from modalinfo.common.files import shown_name

BYTE_NAME = os.fsdecode(b"a\xe9.npz")  # the byte 0xE9: not UTF-8
SLASH_NAME = "a\\xe9.npz"  # a literal backslash, then x, e, 9


def test_shown_name_is_one_to_one_as_ls_b():
    assert shown_name(BYTE_NAME) == "a\\xe9.npz"
    assert shown_name(SLASH_NAME) == "a\\\\xe9.npz"  # ls -b: a\\xe9.npz
    assert shown_name("plain_\u00e9.npz") == "plain_\u00e9.npz"  # valid UTF-8 unchanged
    for name in (BYTE_NAME, SLASH_NAME, "x\\\\y\\", os.fsdecode(b"\\\xff\\x")):
        assert codecs.escape_decode(shown_name(name).encode("utf-8"))[0] == os.fsencode(name)


def _old_shown_name(text):
    """The rule before round 45 (bad bytes as \\xNN, a backslash as it is): the old table."""
    try:
        text.encode("utf-8")
    except UnicodeEncodeError:
        return text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    return text


def _table(path) -> list[dict]:
    with open(path, newline="", encoding="utf-8") as fh:
        return list(csv.DictReader(fh))


@pytest.mark.slow
def test_two_files_two_paths_each_back_to_its_file_and_an_old_folder_resumes(
        tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("pyarrow")
    from modalinfo.batch import analyse_archive
    from modalinfo.io import save
    from modalinfo.telemetry.log import ModalLog

    folder = tmp_path / "in"
    folder.mkdir()
    rng = np.random.default_rng(45)
    for name, frames in ((BYTE_NAME, 300), (SLASH_NAME, 400), ("plain.npz", 350)):
        save(ModalLog(rng.standard_normal((frames, 3)), rate=500.0, units="rad"),
             folder / name)
    out = tmp_path / "out"
    # memory_limit 0: no limit (the "auto" one follows limits other tests of the process set)
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1,
                            memory_limit=0, dashboard_address=":0") as client:
        with monkeypatch.context() as old:  # the folder as the old code wrote it
            old.setattr("modalinfo.common.tasks.rows.shown_name", _old_shown_name)
            first = analyse_archive(folder, "summary", out, client=client, progress=False,
                                    plots=False)
        old_paths = [r["path"] for r in _table(out / "batch.csv")]
        assert len(set(old_paths)) == 2  # the bug: two files, one path
        again = analyse_archive(folder, "summary", out, client=client, progress=False,
                                plots=False)
    assert first.report.n_submitted == 3
    assert again.report.n_skipped == 3 and again.report.n_submitted == 0  # resumed
    rows = _table(out / "batch.csv")
    assert [r["status"] for r in rows] == ["ok"] * 3
    paths = [r["path"] for r in rows]
    assert len(set(paths)) == 3
    for row in rows:
        raw = codecs.escape_decode(row["path"].encode("utf-8"))[0]
        data = Path(os.fsdecode(raw)).read_bytes()  # the bytes the path names
        assert hashlib.sha256(data).hexdigest() == row["sha256"]
    names = sorted(p.rsplit("/", 1)[-1] for p in paths)
    assert names == ["a\\\\xe9.npz", "a\\xe9.npz", "plain.npz"]
