"""A modalinfo CSV with lines appended after its end marker that end in a marker again.

Round 40 PART b F35 / F53: ``tail -n 5 a.csv >> a.csv`` (four data rows and the end
marker appended, as when one log's tail is copied onto another, or a writer appends the
marker lines while ``info`` reads) was refused as "data row 2001 holds 1 values where the
rows above hold 27; every row must hold one value per column" - row 2001 is the first
``# end of modalinfo log`` line, not a short data row. Reference: the file's own lines,
counted here with Python: the marker stands after data row T and ``k`` lines follow it,
so the refusal names the end marker and those ``k`` lines, like the one-line append that
already was (tests/io/test_corrupt.py).
"""

import numpy as np
import pytest

from modalinfo.io import LogFormatError, load, save
from modalinfo.telemetry import ModalLog


@pytest.mark.parametrize("tail", [1, 3, 5])
def test_lines_appended_after_the_end_marker_are_named_when_they_end_in_one(tmp_path, tail):
    log = ModalLog(np.random.default_rng(40).standard_normal((20, 3)), rate=100.0)
    path = save(log, tmp_path / "a.csv")
    lines = path.read_text().splitlines()
    assert lines[-1] == "# end of modalinfo log"
    appended = lines[-tail:]  # the last tail - 1 data rows and the end marker
    path.write_text("\n".join(lines + appended) + "\n")
    with pytest.raises(LogFormatError) as caught:
        load(path)
    message = str(caught.value)
    assert f"{tail} line(s) after the end marker" in message, message
    assert "values where the rows above" not in message, message
