"""A failed ``forecast`` into a new nested ``--out`` removes every folder it made (review28).

``write_outputs``' docstring: any failure "removes the folders this call created when
nothing else is in them". ``make_out_dir`` returns them innermost first, so each
``rmdir`` finds its folder empty. The round 44 test made one folder, so planted bug
R28-F3 (the folders removed outermost first: the outer ``rmdir`` fails on the inner
one, left behind) escaped ``test_forecast_shared_out_round44.py``. Reference: the
file system, listed here (``tmp_path`` empty again).
"""
from pathlib import Path

import pytest

from modalinfo.cli.cmd_forecast import write_outputs


class _Failing:
    def to_json(self, path, provenance=None, quality=None):
        Path(path).write_text("{}")

    def to_csv(self, path, provenance=None, quality=None):
        Path(path).write_text("predictor\n")

    def save_plots(self, folder, provenance=None):
        raise OSError("disk full")


def test_a_failure_leaves_none_of_the_nested_folders_it_made(tmp_path):
    out = tmp_path / "a" / "b" / "c"
    with pytest.raises(OSError, match="disk full"):
        write_outputs(_Failing(), out, overwrite=False)
    assert list(tmp_path.iterdir()) == []
