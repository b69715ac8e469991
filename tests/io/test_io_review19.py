"""Two edges the round 21 / 23 tests did not reach (review19, planted bugs UN2 and CS1).

References, outside the code:

- the Unicode standard's NFKC as Python's ``unicodedata`` implements it: the micro sign
  U+00B5 becomes Greek mu U+03BC and full-width ``\uff55\uff4d`` becomes ``um``, the
  ASCII spelling of the same unit, so columns spelling micrometres four ways state ONE
  unit (compared as written they were four, and the file was refused as mixing units);
  the values must come back as numpy wrote them (``numpy.array_equal``), in um;
- IEEE 754 binary64 as numpy implements it: every integer below 2**53 = 9.007e15 (all
  of 15 digits) is exact, 2**53 + 1 (16 digits) is not: a spreadsheet, which stores
  numbers as doubles and shows 15 significant digits, cannot show a 16-digit label as
  written, while a 15-digit one it can.
"""

from __future__ import annotations

import unicodedata
import warnings

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.csv import write_csv
from modalinfo.telemetry import ModalLog

MICRO = ["\u00b5m", "\u03bcm", "\uff55\uff4d", "um"]


def test_reference_forms():
    # NFKC: the micro sign becomes Greek mu, full-width letters become ASCII 'um'
    assert {unicodedata.normalize("NFKC", u) for u in MICRO} == {"\u03bcm", "um"}
    assert len({u.lower() for u in MICRO}) == 4  # four words as written (str.lower)
    assert float(np.float64(10**15 - 1)) == 10**15 - 1
    assert int(np.float64(2**53 + 1)) != 2**53 + 1


def test_columns_spelling_micrometres_differently_are_one_unit(tmp_path):
    a = np.random.default_rng(19).standard_normal((200, 4)).cumsum(0) * 0.01
    path = tmp_path / "mixed.csv"
    header = ",".join(f"Z{j} [{u}]" for j, u in zip(range(2, 6), MICRO, strict=True))
    np.savetxt(path, a, delimiter=",", header=header, comments="", fmt="%.17g",
               encoding="utf-8")
    log = load(path, rate=1000.0, wavelength=5e-7)
    assert log.units == "um"
    assert log.labels == ["Z2", "Z3", "Z4", "Z5"]
    assert np.array_equal(np.asarray(log.coeffs), a)


def _log(labels):
    x = np.random.default_rng(23).standard_normal((20, len(labels)))
    return ModalLog(x, rate=1000.0, modes=labels, convention="labels")


def test_a_16_digit_label_is_said_and_a_15_digit_one_is_not(tmp_path):
    sixteen = str(2**53 + 1)
    assert len(sixteen) == 16
    with pytest.warns(UserWarning, match=r"1 text cell\(s\) .*first '9007199254740993'"):
        write_csv(_log(["Z2", sixteen]), tmp_path / "a.csv")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        write_csv(_log(["Z2", "9" * 15]), tmp_path / "b.csv")
