"""Round 32 PART b (issue 27): prose above comma-separated numbers is named too.

docs/ADVERSARIAL.md, "Round 32 PART b, issue 27", b22: a .csv opening with
'Telemetry exported 2026-11-30' / 'Operator: X' above ``numpy.savetxt(...,
delimiter=',')`` rows was "corrupt CSV file ...: could not convert string 'Operator:'
to float64 at row 0, column 1": the delimiter was guessed from the first line (prose,
no comma), so round 31's refusal of text lines did not see the numbers. b58: one title
line ('KAOS telemetry dump', or names 'Z2 Z3 Z4 Z5' separated by blanks) above comma
rows was "could not convert string '1.28,1.44,...'" (the whole row as one string).

Reference: the numbers are written by ``numpy.savetxt``; the refusal's advice, followed
literally (each text line starting with '#'), gives the array back exactly.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError

PROSE = ["Telemetry exported 2026-11-30", "Operator: X"]


@pytest.mark.parametrize(("sep", "name"), [(",", "prose.csv"), (" ", "prose.txt")])
def test_prose_without_the_numbers_delimiter_is_named(tmp_path, sep, name):
    x = np.random.default_rng(32).normal(size=(300, 5))
    np.savetxt(tmp_path / "numbers", x, fmt="%.17g", delimiter=sep)
    numbers = (tmp_path / "numbers").read_text()
    # a comma in the prose above blank-separated numbers: the other way round
    prose = PROSE if sep == "," else ["KAOS dump, night 3", "Operator: X"]
    (tmp_path / name).write_text("\n".join(prose) + "\n" + numbers)
    with pytest.raises(LogFormatError) as err:
        load(tmp_path / name, rate=1000.0)
    text = str(err.value)
    assert "corrupt" not in text and "first 2 lines are text" in text and "'#'" in text
    (tmp_path / ("fixed" + name[-4:])).write_text(
        "".join(f"# {ln}\n" for ln in prose) + numbers)
    log = load(tmp_path / ("fixed" + name[-4:]), rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, x)


@pytest.mark.parametrize("title", ["KAOS telemetry dump", "Z2 Z3 Z4 Z5"])
def test_one_title_line_without_the_numbers_delimiter_is_named(tmp_path, title):
    x = np.random.default_rng(58).normal(size=(50, 4))
    np.savetxt(tmp_path / "numbers", x, fmt="%.17g", delimiter=",")
    numbers = (tmp_path / "numbers").read_text()
    (tmp_path / "one.csv").write_text(title + "\n" + numbers)
    with pytest.raises(LogFormatError) as err:
        load(tmp_path / "one.csv", rate=1000.0)
    text = str(err.value)
    assert "corrupt" not in text and f"first line {title!r} is text" in text
    assert "'#'" in text and "','" in text
    (tmp_path / "fixed.csv").write_text(f"# {title}\n" + numbers)  # the advice, literally
    np.testing.assert_array_equal(load(tmp_path / "fixed.csv", rate=1000.0).coeffs, x)
    (tmp_path / "named.csv").write_text(title.replace(" ", ",") + "\n" + numbers)
    if title.startswith("Z"):  # the other advice: names separated as the numbers are
        log = load(tmp_path / "named.csv", rate=1000.0)
        np.testing.assert_array_equal(log.coeffs, x)
        assert log.labels == ["Z2", "Z3", "Z4", "Z5"]
