"""Lines of text above a text log's numbers are named whatever the number of columns.

docs/MUTATION.md, "Planted bugs, round 23" (review23): round 31 PART b's a30 fix took a
row of the log's width holding *one* number for a frame with a bad cell, so the same
three lines of prose ('KAOS telemetry dump', 'units: nm', 'rate: 1000 Hz') above a
3-column log (the width of 'rate: 1000 Hz') were "corrupt CSV file ...: could not
convert string 'units:' to float64" again. A frame is now a row of the log's width of
which at least half the cells are numbers (or empty).

Reference: the numbers are written by ``numpy.savetxt``; the refusal's advice, followed
literally (each text line starting with '#'), gives the array back exactly.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError

PROSE = ["KAOS telemetry dump", "units: nm", "rate: 1000 Hz"]


@pytest.mark.parametrize("n_cols", [2, 3, 4])
def test_prose_is_named_at_every_width(tmp_path, n_cols):
    x = np.random.default_rng(n_cols).normal(size=(200, n_cols))
    np.savetxt(tmp_path / "numbers.txt", x, fmt="%.17g")
    numbers = (tmp_path / "numbers.txt").read_text()
    (tmp_path / "prose.txt").write_text("\n".join(PROSE) + "\n" + numbers)
    with pytest.raises(LogFormatError) as err:
        load(tmp_path / "prose.txt", rate=1000.0)
    text = str(err.value)
    assert "corrupt" not in text and "first 3 lines are text" in text, text
    (tmp_path / "fixed.txt").write_text("".join(f"# {ln}\n" for ln in PROSE) + numbers)
    np.testing.assert_array_equal(load(tmp_path / "fixed.txt", rate=1000.0).coeffs, x)


@pytest.mark.parametrize("first", ["N/A,0.5", "0.25,N/A,0.5", "N/A,,0.5"])
def test_a_first_frame_with_a_bad_cell_is_still_named_by_its_cell(tmp_path, first):
    n_cols = first.count(",") + 1
    x = np.random.default_rng(3).normal(size=(50, n_cols))
    rows = "".join(",".join(map(repr, r)) + "\n" for r in x)
    names = ",".join(f"Z{j + 2}" for j in range(n_cols))
    (tmp_path / "na.csv").write_text(f"{names}\n{first}\n{rows}")
    with pytest.raises(ValueError) as err:
        load(tmp_path / "na.csv", rate=1000.0)
    assert "'N/A'" in str(err.value) and "lines are text" not in str(err.value)
