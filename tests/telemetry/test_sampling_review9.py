"""Rate-change and repeated-block rules at their documented edges.

Round 9 of planted bugs (review9). Reference: time axes and frame orders by
construction, and the rules as documented (``modalinfo/telemetry/sampling.py``; audit
10-time):

* a rate change is "a spread of the block rates beyond 1e-3 (ModalLog's rate tolerance)
  plus the rounding plus six standard errors of a block median under the jitter": with
  exact clocks (no jitter, float64 rounding ~1e-13 of an interval) 2000 Hz then 1994 Hz
  (0.3 %) is a change and 2000 then 1999.2 Hz (0.04 %) is not. The existing tests used a
  1 % change, so a tolerance of 1e-2 went unseen (planted bug T2 escaped);
* a repeated block is "runs of >= 8 frames equal to earlier frames at one offset"
  (``REPEAT_RUN``): 8 frames written twice are found, 7 are not. The existing test wrote
  100 frames twice, so ``> 8`` went unseen (planted bug T5 escaped);
* ``clock_interval`` is "the mean of the regular intervals (neither gaps nor short, as
  in sampling_of)": an exact 2 kHz clock with one extra frame mid-interval (two 0.25 ms
  intervals, short) has a clock interval of exactly 0.5 ms; with the short intervals in
  the mean it is 0.4995 ms, 1e-3 off, the whole rate tolerance (planted bug P3 escaped:
  the existing tests had jitter or gaps, no short interval).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import sampling_of
from modalinfo.telemetry.sampling import REPEAT_RUN, clock_interval, repeated_blocks


def _two_clocks(r1: float, r2: float, n: int = 1500) -> np.ndarray:
    t = np.arange(n) / r1
    return np.r_[t, t[-1] + np.arange(1, n + 1) / r2]


def test_a_rate_change_of_three_per_mille_is_found():
    s = sampling_of(_two_clocks(2000.0, 1994.0))
    assert s.uniform
    assert s.rate_low == pytest.approx(1994.0, rel=1e-9)
    assert s.rate_high == pytest.approx(2000.0, rel=1e-9)
    assert s.rate_change == pytest.approx(6.0 / 1994.0, rel=1e-6)


def test_a_rate_change_under_one_per_mille_is_not():
    s = sampling_of(_two_clocks(2000.0, 1999.2))
    assert s.rate_change == 0.0
    assert s.rate_low == pytest.approx(1999.2, rel=1e-9)  # measured, below the rule


def test_a_block_of_exactly_the_rule_written_twice_is_found():
    assert REPEAT_RUN == 8  # the documented rule
    x = np.random.default_rng(4).standard_normal((600, 3))
    twice = x[np.r_[0:308, 300:600]]  # frames 300..307 written again after 307
    assert repeated_blocks(twice) == [(308, 8, 300)]
    once_less = x[np.r_[0:307, 300:600]]  # 7 frames again: below the rule
    assert repeated_blocks(once_less) == []


def test_clock_interval_leaves_short_intervals_out():
    t = np.arange(1000) / 2000.0
    t = np.sort(np.r_[t, t[500] + 0.25e-3])  # one extra frame: two short intervals
    dt = np.diff(t)
    assert np.sum(dt < 0.5e-3 / 1.5) == 2
    assert clock_interval(t) == pytest.approx(0.5e-3, rel=1e-12)
    assert np.mean(dt) == pytest.approx(0.4995e-3, rel=1e-12)  # what a plain mean gives
