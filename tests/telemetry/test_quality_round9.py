"""The quality pass's false-alarm rate on short clean logs (adversarial round 9 PART b, Q01).

Reference: the stated rule itself, checked by simulation outside the code: on clean
Gaussian logs (seeded standard normals) the probability that any value is flagged must
be at most ``alpha`` = 1 %; the count of flagged logs out of ``n`` is bounded by the
binomial(n, 0.01) quantile at 1 - 1e-6 (scipy.stats.binom). Before the fix the
Bonferroni ``k`` with a MAD from few frames flagged 63 % of 20-frame logs and 26 % of
50-frame logs; autocorrelated ones (AR(1) with rho = 0.95 by scipy.signal.lfilter, 200
frames) 8 % even after that (row P02). From 2000 frames on ``k`` is Bonferroni's
(scipy.stats.norm.isf).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from modalinfo.telemetry import assess_quality
from modalinfo.telemetry.quality import SMALL_SAMPLE_FRAMES, small_sample_threshold

N_LOGS = 300


@pytest.mark.parametrize("frames", [20, 50])
def test_short_clean_gaussian_logs_are_rarely_flagged(frames):
    rng = np.random.default_rng(frames)
    flagged = sum(assess_quality(rng.standard_normal((frames, 27))).n_flagged > 0
                  for _ in range(N_LOGS))
    assert flagged <= stats.binom.ppf(1 - 1e-6, N_LOGS, 0.01)  # 10 of 300


def test_short_autocorrelated_gaussian_logs_are_rarely_flagged():
    from scipy.signal import lfilter

    rng = np.random.default_rng(11)
    flagged = 0
    for _ in range(N_LOGS):
        x = lfilter([1.0], [1.0, -0.95], rng.standard_normal((700, 27)), axis=0)[500:]
        flagged += assess_quality(x).n_flagged > 0  # 200 frames after the burn-in
    assert flagged <= stats.binom.ppf(1 - 1e-6, N_LOGS, 0.01)


def test_a_glitch_in_a_short_log_is_still_found():
    x = np.random.default_rng(5).standard_normal((20, 27))
    x[7, :5] += 50.0  # a 50-sigma glitch in five modes
    report = assess_quality(x)
    assert report.glitch_frames.tolist() == [7]


def test_long_logs_keep_the_bonferroni_threshold():
    n, m = SMALL_SAMPLE_FRAMES, 27
    assert small_sample_threshold(n, n, m) == pytest.approx(
        stats.norm.isf(0.005 / (n * m)), rel=1e-12)
    assert small_sample_threshold(20, 20, m) > stats.norm.isf(0.005 / (20 * m))
