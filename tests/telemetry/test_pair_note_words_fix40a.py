"""Fixes 40-a (round 38 PART b, I07): the swapped-pairs note says what the test can tell.

A log with every pair of frames swapped (rows 1, 0, 3, 2, ...) and one with every
other pair swapped (rows 1, 0, 2, 3, 5, 4, 6, 7, ...) both make the lag-1 correlation
from frame 2k to 2k + 1 larger than from 2k + 1 to 2k + 2 (lag 1 against lag 3, and lag
1 against lag 2: an AR(1) of 0.9 gives 0.9 against 0.729 and 0.81), so the rule cannot
tell them apart. The note said "the frames of each pair 2k, 2k + 1 look written in
reverse order" for both, which swapping every pair back makes right for the first only
(the second then becomes the complementary pattern). Reference: the rows written
(numpy indexing) and the AR(1)'s autocorrelations rho^k; the unswapped log stays clean.
"""

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.telemetry import ModalLog, assess_quality


def _log(rows=None):
    e = np.random.default_rng(38).standard_normal((4500, 6))
    x = lfilter([1.0], [1.0, -0.9], e, axis=0)[500:]
    return x if rows is None else x[rows]


def _note(x):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return assess_quality(ModalLog(x, rate=1000.0)).pair_note


def _every_pair(n):
    rows = np.arange(n)
    rows[0::2], rows[1::2] = np.arange(1, n, 2), np.arange(0, n, 2)
    return rows


def _every_other_pair(n):
    rows = np.arange(n)
    for k in range(0, n - 1, 4):  # pairs (0, 1), (4, 5), ... swapped
        rows[k], rows[k + 1] = k + 1, k
    return rows


@pytest.mark.parametrize("rows", [_every_pair, _every_other_pair])
def test_both_patterns_found_and_worded_as_either(rows):
    note = _note(_log(rows(4000)))
    assert "frames in swapped pairs?" in note
    assert "2k, 2k + 1, or of some of those pairs" in note
    assert "every pair or every other pair swapped gives the same test" in note


def test_an_unswapped_log_has_no_note():
    assert _note(_log()) == ""
