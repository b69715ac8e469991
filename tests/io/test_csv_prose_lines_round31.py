"""Round 31 PART b (issue 27): lines of text above a text log's numbers are named.

docs/ADVERSARIAL.md, "Round 31 PART b, issue 27", a30: a whitespace-separated .txt that
opens with three lines of prose ('KAOS telemetry dump', 'rate: 1000 Hz', 'units: nm')
was "corrupt CSV file ...: could not convert string 'rate:' to float64 at row 0,
column 1" (row 0 being the file's second line), with no word on how to mark such lines.

Reference: the numbers are written by ``numpy.savetxt``; the refusal's advice, followed
literally (each text line starting with '#'), gives the array back exactly, and the
'# units: nm' line is then read as the README documents.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError

PROSE = ["KAOS telemetry dump", "units: nm", "rate: 1000 Hz"]


def test_prose_above_the_numbers_is_named_and_the_advice_works(tmp_path):
    x = np.random.default_rng(31).normal(size=(400, 5))
    np.savetxt(tmp_path / "numbers.txt", x, fmt="%.17g")
    numbers = (tmp_path / "numbers.txt").read_text()
    (tmp_path / "prose.txt").write_text("\n".join(PROSE) + "\n" + numbers)
    with pytest.raises(LogFormatError) as err:
        load(tmp_path / "prose.txt", rate=1000.0)
    text = str(err.value)
    assert "corrupt" not in text and "first 3 lines are text" in text and "'#'" in text
    (tmp_path / "fixed.txt").write_text("".join(f"# {ln}\n" for ln in PROSE) + numbers)
    log = load(tmp_path / "fixed.txt", rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)
    assert log.units == "nm"


def test_a_word_deep_in_the_numbers_still_names_the_cell(tmp_path):
    x = np.random.default_rng(1).normal(size=(100, 3)).astype(object)
    x[60, 1] = "bad"
    (tmp_path / "cell.txt").write_text(
        "Z2 Z3 Z4\n" + "".join(" ".join(map(str, r)) + "\n" for r in x))
    with pytest.raises(ValueError) as err:
        load(tmp_path / "cell.txt", rate=1000.0)
    assert "'bad'" in str(err.value) and "lines are text" not in str(err.value)


def test_a_bad_cell_in_the_first_frame_is_not_called_prose(tmp_path):
    x = np.random.default_rng(2).normal(size=(100, 3)).astype(object)
    x[0, 1] = "N/A"
    (tmp_path / "na.csv").write_text(
        "Z2,Z3,Z4\n" + "".join(",".join(map(str, r)) + "\n" for r in x))
    with pytest.raises(ValueError) as err:
        load(tmp_path / "na.csv", rate=1000.0)
    assert "'N/A'" in str(err.value) and "lines are text" not in str(err.value)
