"""Mode lists written as modalinfo's own notes print them ("Z2..Z7") read as ranges.

Reference: a round trip through ``io._foreign.describe_modes`` (the text modalinfo writes
into metadata records and notes) and the plain ``a-b`` range of the same indices; the
command line's ``--in-modes`` against the log's column count (fix53-c noticed that the
note's spelling was refused as "got 1" entry).
"""

import numpy as np
import pytest

from modalinfo.bases.indexing import parse_modes
from modalinfo.io._foreign import describe_modes


@pytest.mark.parametrize("modes", [[2, 3, 4, 5, 6, 7], list(range(4, 52))])
def test_describe_modes_round_trips(modes):
    text = describe_modes(modes, "noll").split(" ")[0]
    assert ".." in text
    assert parse_modes(text, "--in-modes") == modes == parse_modes(f"{modes[0]}-{modes[-1]}")


def test_dotted_forms():
    assert parse_modes("2..4,9") == [2, 3, 4, 9]
    assert parse_modes("z3 .. z5") == [3, 4, 5]


@pytest.mark.parametrize("text, words", [("KL1..KL4", "'1-4'"), ("Z2..X5", "'2-5'"),
                                          ("Z7..Z2", "decreasing")])
def test_dotted_refusals_name_the_argument(text, words):
    with pytest.raises(ValueError, match="--in-modes") as err:
        parse_modes(text, "--in-modes")
    assert words in str(err.value) and text in str(err.value)


def test_cli_in_modes_accepts_the_notes_spelling(tmp_path):
    from modalinfo.cli import main

    path = tmp_path / "log.npy"
    np.save(path, np.random.default_rng(0).normal(size=(200, 6)))
    assert main(["info", str(path), "--in-modes", "Z2..Z7"]) == 0
