"""A CSV cut while the logger wrote it (adversarial round 34 PART b, B44-B47).

Reference: the file's own text - the row of another length is counted by hand from
the lines written (Python's ``str.split``), the expected message names its number and
its count of values. Before: numpy's "the number of columns changed ... use `usecols`"
advice for its API, no word of a partial last line.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import LogFormatError, load


def _write(path, rows: list[str]) -> None:
    path.write_text("time,z2,z3,z4\n" + "\n".join(rows))


def _rows(n: int = 50) -> list[str]:
    rng = np.random.default_rng(0)
    x = rng.normal(size=(n, 3))
    return [",".join(f"{v:.17g}" for v in (k / 1000.0, *x[k])) for k in range(n)]


def test_partial_last_row_is_named_as_such(tmp_path):
    rows = _rows()
    rows[-1] = rows[-1][: rows[-1].index(",", rows[-1].index(",") + 1)]  # 2 of 4 values
    assert len(rows[-1].split(",")) == 2
    _write(tmp_path / "cut.csv", rows)
    with pytest.raises(LogFormatError) as info:
        load(tmp_path / "cut.csv")
    text = str(info.value)
    assert "last data row (50) holds 2 of the 4 values" in text
    assert "ends mid-row" in text and "usecols" not in text


def test_short_row_inside_the_file_is_named_by_number(tmp_path):
    rows = _rows()
    rows[9] = ",".join(rows[9].split(",")[:3])
    _write(tmp_path / "short.csv", rows)
    with pytest.raises(LogFormatError, match=r"data row 10 holds 3 values where the rows "
                                             r"above hold 4") as info:
        load(tmp_path / "short.csv")
    assert "usecols" not in str(info.value)
