"""Left 16: the constants of the telemetry quality pass, pinned at their edges.

References outside the code: the Bonferroni threshold ``Phi^-1(1 - alpha / (2 n))``
from ``scipy.stats.norm.isf`` at the documented 1 % family-wise level; the documented
switch of ``small_sample_threshold`` to that Bonferroni value from 2000 sample frames on
(below, the MAD's spread raises it); the documented lower bound of ``sample_frames``
(100); the documented stuck run (8 equal consecutive values); the documented stride
``ceil(n / 65536)`` of the median/MAD subsample; the documented effective frames
``(N - p) (1 - r) / (1 + r)`` of a white log (p = 4, r clipped at 0: ``N - 4``) against
the documented 12. A constant x 0.9 or x 1.1 (or off by one) flips one decision
(docs/MUTATION.md, "Left 16").
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from modalinfo.telemetry.quality import (
    assess_quality,
    gaussian_threshold,
    small_sample_threshold,
)


@pytest.mark.parametrize("n", [1, 27, 50 * 27])
def test_default_threshold_is_bonferroni_at_1_percent(n):
    assert gaussian_threshold(n) == pytest.approx(stats.norm.isf(0.01 / (2 * n)), rel=1e-12)


def test_small_sample_correction_stops_at_2000_frames():
    base = stats.norm.isf(0.01 / (2 * 50 * 27))
    assert small_sample_threshold(2000, 50, 27) == pytest.approx(base, rel=1e-12)
    # at 1999 frames the MAD's relative sd 1.17 / sqrt(1999) = 2.6 % raises k by ~0.5 %
    assert small_sample_threshold(1999, 50, 27) > 1.002 * base


def test_sample_frames_below_100_is_refused():
    x = np.random.default_rng(0).standard_normal((300, 2))
    assert assess_quality(x, sample_frames=100).sample_frames == 100  # every 3rd frame
    with pytest.raises(ValueError, match="sample_frames"):
        assess_quality(x, sample_frames=99)


@pytest.mark.parametrize("run, stuck", [(8, 1), (7, 0)])
def test_default_stuck_run_is_8_equal_values(run, stuck):
    x = np.random.default_rng(0).standard_normal((500, 1))
    x[100:100 + run, 0] = 0.3
    assert int(assess_quality(x).stuck[0] > 0) == stuck


@pytest.mark.parametrize("n, sample", [(65536, 65536), (65537, 32769)])
def test_median_sample_strides_beyond_65536_frames(n, sample):
    x = np.random.default_rng(0).standard_normal((n, 1))
    assert assess_quality(x).sample_frames == sample  # every ceil(n / 65536)-th frame


@pytest.mark.parametrize("n, assessed", [(15, False), (16, True)])
def test_twelve_effective_frames_are_assessed(n, assessed):
    # a white log whose innovations' lag-1 autocorrelation is <= 0: N - 4 effective
    x = np.random.default_rng(1).standard_normal((n, 1))
    report = assess_quality(x)
    assert report.effective_frames == n - 4
    assert report.assessed == assessed
