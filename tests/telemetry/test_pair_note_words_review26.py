"""Planted-bug review 26 (stop 50): the swapped-pairs note of both parities, word for word.

Fixes 40-a's note names "the frames of every pair <first>, or of some of those pairs",
where <first> is "2k, 2k + 1" when frames 2k, 2k + 1 are swapped and "2k + 1, 2k + 2"
when the pairs of the other parity are (rows 0, 2, 1, 4, 3, ...: the lag-1 correlation
from 2k + 1 to 2k + 2 is then the AR(1)'s rho^3 against rho, the larger). Reference: the
rows written by numpy indexing and the AR(1)'s autocorrelations. Plant R26-P1 ("each
pair" for "every pair") escaped tests/telemetry/test_pair_note_words_fix40a.py, which
tested the phrase after the pair only, and one parity.
"""

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.telemetry import ModalLog, assess_quality


def _log(rows):
    e = np.random.default_rng(38).standard_normal((4500, 6))
    return lfilter([1.0], [1.0, -0.9], e, axis=0)[500:][rows]


def _pairs(n, start):
    rows = np.arange(n)
    for k in range(start, n - 1, 2):
        rows[k], rows[k + 1] = k + 1, k
    return rows


@pytest.mark.parametrize("start, first", [(0, "2k, 2k + 1"), (1, "2k + 1, 2k + 2")])
def test_the_note_names_every_pair_of_the_parity_found(start, first):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        note = assess_quality(ModalLog(_log(_pairs(4000, start)), rate=1000.0)).pair_note
    assert f"the frames of every pair {first}, or of some of those pairs, look written in " \
           "reverse order" in note, note
