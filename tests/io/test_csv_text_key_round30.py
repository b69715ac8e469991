"""Round 30 PART b (issue 27): a text key column of a CSV gets the key-column refusal.

docs/ADVERSARIAL.md, "Round 30 PART b, issue 27", K04: a CSV of named Zernike columns
with a ``night`` column of dates ('2024-01-01') was "corrupt CSV file ...: could not
convert string '2024-01-01' to float64 at row 0, column 1", while the same key written
as numbers (round 29 PART b, M35) is refused naming the column and what to do.

Reference: the file is written with the standard library's ``csv`` module; the refusal
of the numeric key (``night`` = 1 / 2) is the expected message, word for word but for
the file name; a non-number inside a mode column still names the cell.
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError

NAMES = [f"Z{j}" for j in range(2, 8)]


def _write(path, key_name, keys, values):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([key_name, *NAMES])
        for k, row in zip(keys, values, strict=True):
            w.writerow([k, *map(repr, row.tolist())])  # numbers (numpy 2's repr is np.float64(...))


def _message(path):
    with pytest.raises(LogFormatError) as err:
        load(path)
    return str(err.value)


def test_a_text_key_column_is_refused_as_the_numeric_key_is(tmp_path):
    values = np.random.default_rng(0).normal(0.0, 0.1, (200, len(NAMES)))
    nights = np.repeat(["2024-01-01", "2024-01-02"], 100)
    _write(tmp_path / "text.csv", "night", nights, values)
    _write(tmp_path / "num.csv", "night", np.repeat([1, 2], 100), values)
    text, num = _message(tmp_path / "text.csv"), _message(tmp_path / "num.csv")
    assert "corrupt" not in text
    assert text.replace("text.csv", "num.csv") == num
    assert "'night'" in text and "drop the column" in text


def test_a_word_inside_a_mode_column_still_names_the_cell(tmp_path):
    values = np.random.default_rng(1).normal(0.0, 0.1, (50, len(NAMES))).astype(object)
    values[7, 3] = "bad"
    with open(tmp_path / "cell.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(NAMES)
        w.writerows(values.tolist())
    text = _message(tmp_path / "cell.csv")
    assert "'bad'" in text and "row 7" in text
