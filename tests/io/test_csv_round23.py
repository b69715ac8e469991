"""Round 23 PART b: mode labels that a spreadsheet takes for formulas, in written CSVs.

Reference: OWASP "CSV injection" (a cell starting with ``=``, ``+``, ``-``, ``@`` is
evaluated by spreadsheets; digits with a leading zero or over 15 of them are shown as
another number) and pandas' ``read_csv``, which must read the labels back
exactly as written; the file keeps the text, and the writer says a spreadsheet may not.
"""

import warnings

import numpy as np
import pandas as pd
import pytest

from modalinfo.io.csv import write_csv
from modalinfo.telemetry.log import ModalLog

LABELS = ["=1+1", "@cmd", "Z 2,\"q\"", "007", "12345678901234567890"]


def _log(labels):
    x = np.random.default_rng(23).standard_normal((50, len(labels)))
    return ModalLog(x, rate=1000.0, modes=labels, convention="labels")


def test_formula_like_labels_are_written_as_is_and_said(tmp_path):
    with pytest.warns(UserWarning, match=r"4 text cell\(s\) a spreadsheet would not show"):
        path = write_csv(_log(LABELS), tmp_path / "a.csv")
    assert list(pd.read_csv(path, comment="#").columns) == LABELS


def test_plain_labels_write_without_a_warning(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_csv(_log(["Z2", "7", "x-y", "0"]), tmp_path / "b.csv")
