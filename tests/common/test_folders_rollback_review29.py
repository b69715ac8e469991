"""Folders a failed run made are removed when left empty, kept with what they hold (review29).

Round 29 R1 (modalinfo/common/folders.py:431, ``locked_out_dir``) and R3
(modalinfo/cli/cmd_forecast.py:315, ``write_outputs``): stop 53 moved both rollbacks onto
``remove_empty``. Planted slips passed every test: the marker folders removed only when
something else was left (the swapped choice), and the innermost new folder skipped
when the staging folder cannot be made. References, from outside the code: the
docstrings' promises ("a run that failed at its start leaves nothing behind; a folder
holding anything else keeps its ``marker``"; "removes the folders this call created when
nothing else is in them"), checked on the file system listed here.
"""

from __future__ import annotations

import tempfile

import pytest

from modalinfo.cli.cmd_forecast import write_outputs
from modalinfo.common.folders import locked_out_dir


def test_a_run_failing_before_its_first_row_leaves_nothing(tmp_path):
    out = tmp_path / "new" / "out"
    with pytest.raises(RuntimeError), locked_out_dir(out, "test", marker="rows",
                                                     parents=True):
        (out / "rows").mkdir()  # as a batch makes it, before any row
        raise RuntimeError("failed at its start")
    assert list(tmp_path.iterdir()) == []


def test_a_folder_holding_something_else_keeps_its_marker(tmp_path):
    out = tmp_path / "out"
    with pytest.raises(RuntimeError), locked_out_dir(out, "test", marker="rows"):
        (out / "rows").mkdir()
        (out / "hashes.json").write_text("{}")  # a batch interrupted before its first row
        raise RuntimeError("interrupted")
    assert sorted(p.name for p in out.iterdir()) == ["hashes.json", "rows"]


def test_forecast_staging_refused_leaves_none_of_the_new_folders(tmp_path, monkeypatch):
    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(tempfile, "mkdtemp", refuse)
    with pytest.raises(PermissionError):
        write_outputs(None, tmp_path / "a" / "b", overwrite=False)
    assert list(tmp_path.iterdir()) == []
