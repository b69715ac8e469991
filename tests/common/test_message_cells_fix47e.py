r"""A batch error cell keeps the shown path its message already quotes (fixes 47-e item 2).

``modalinfo/common/tasks/rows.py`` ``_utf8_text`` applied ``shown_name`` to every cell,
so an error message that already held a path in its shown form (``files.quoted``, e.g.
``check_readable``'s "no such file: 'd\\e'" for a log ``d\e`` removed during a run) had
its backslashes doubled again in batch.csv (``'d\\\\e'``) and in batch's ``error`` lines
on stdout. References, outside the package: GNU ``ls -b``'s escape of the name ``d\e``
(``d\\e``, written here as a literal), Python's csv module reading the table back, and
``codecs.escape_decode`` (the shown form back to the file's bytes).
"""

from __future__ import annotations

import codecs
import csv
import os

import pytest

from modalinfo.common.files import check_readable

SHOWN = "d\\\\e"  # ls -b of the name d\e: backslash doubled, once


def test_a_removed_logs_message_cell_keeps_its_shown_path(tmp_path):
    pytest.importorskip("pyarrow")
    from modalinfo.common.tasks.rows import write_table

    log = tmp_path / "d\\e"
    log.write_bytes(b"x")
    os.remove(log)  # removed before its task runs
    with pytest.raises(FileNotFoundError) as caught:
        check_readable(log)
    message = str(caught.value)
    assert f"{SHOWN}'" in message  # the message quotes the shown form (files.quoted)
    rows = [{"path": str(log), "status": "error", "error_type": "FileNotFoundError",
             "error_message": message}]
    csv_path, _ = write_table(rows, tmp_path, "batch")
    with open(csv_path, newline="", encoding="utf-8") as fh:
        (row,) = list(csv.DictReader(fh))
    assert row["path"].endswith("/" + SHOWN)  # a path cell: shown once
    assert row["error_message"] == message, row["error_message"]  # kept as shown
    shown_path = row["error_message"].split("'")[1]
    assert codecs.escape_decode(shown_path.encode())[0] == os.fsencode(str(log))


def test_a_message_cell_still_escapes_an_undecodable_byte(tmp_path):
    pytest.importorskip("pyarrow")
    from modalinfo.common.tasks.rows import write_table

    raw = os.fsdecode(b"bad \xe9 byte")  # a lone surrogate: pyarrow's UTF-8 refuses it
    csv_path, _ = write_table([{"error_message": raw}], tmp_path, "t")
    with open(csv_path, newline="", encoding="utf-8") as fh:
        (row,) = list(csv.DictReader(fh))
    assert row["error_message"] == "bad \\xe9 byte"


def test_a_copys_error_names_its_own_shown_path():
    """A byte-identical copy's row names its own file also where the shown form differs.

    ``batch.archive._labelled`` replaced the raw path of the first file in the shared
    message, which quotes the shown form ``'d\\\\e'``: the copy's row named the other file
    (round 18 PART b, M04, for names with a backslash). Reference: the literal messages.
    """
    from modalinfo.batch.archive import _labelled
    from modalinfo.common.files import quoted

    first = "/in/d\\e"
    row = {"path": first, "error_message": quoted(first) + " is empty"}
    out = _labelled(row, {"path": "/in/copy\\f"})
    assert out["error_message"] == "'/in/copy\\\\f' is empty", out["error_message"]
    plain = _labelled({"path": "/in/a.csv", "error_message": "'/in/a.csv' is empty"},
                      {"path": "/in/a.csv.bak"})
    assert plain["error_message"] == "'/in/a.csv.bak' is empty"
