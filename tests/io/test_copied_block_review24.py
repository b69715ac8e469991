"""Planted-bug review 24 (issue 27): a block written twice in the middle of a log.

Reference: the file's own rows (numpy). Frames 600..699 of an 800-frame 2 kHz log are
written again after frame 799 with their times, then the logger goes on with new
frames at 0.4 s: the copy is exactly 100 rows (rows 800..899), the rows after it are new.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load

RATE = 2000.0


def test_a_copied_block_followed_by_new_frames_is_named_to_its_last_row(tmp_path):
    x = np.random.default_rng(24).normal(size=(1000, 3))
    t = np.arange(1000) / RATE
    rows_t = np.r_[t[:800], t[600:700], t[800:]]
    rows_x = np.r_[x[:800], x[600:700], x[800:]]
    copied = np.flatnonzero(np.all(rows_x[800:900] == rows_x[600:700], axis=1))
    assert copied.size == 100 and not np.array_equal(rows_x[900], rows_x[700])
    names = ",".join(f"z{m}" for m in range(2, 5))
    np.savetxt(tmp_path / "twice.csv", np.column_stack([rows_t, rows_x]), delimiter=",",
               header="time," + names, comments="", fmt="%.17g")
    with pytest.raises(ValueError, match=r"frames 800\.\.899 repeat frames 600\.\.699 .*"
                                         r"delete those 100 rows"):
        load(tmp_path / "twice.csv")
