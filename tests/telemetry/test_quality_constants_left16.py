"""Left 16: the constants of the telemetry quality pass, pinned at their edges.

References outside the code: the Bonferroni threshold ``Phi^-1(1 - alpha / (2 n))``
from ``scipy.stats.norm.isf`` at the documented 1 % family-wise level; the documented
switch of ``small_sample_threshold`` to that Bonferroni value from 2000 sample frames on
(below, the MAD's spread raises it); the documented lower bound of ``sample_frames``
(100); the documented stuck run (8 equal consecutive values); the documented stride
``ceil(n / 65536)`` of the median/MAD subsample; the documented effective frames
``(N - p) (1 - r) / (1 + r)`` of a white log (p = 4, r clipped at 0: ``N - 4``) against
the documented 12; the grouped-data median of Kendall & Stuart (vol. 1, sec. 2.13),
``v - h/2 + h (1/2 - F(<v)) / F(=v)``, written out for a column whose MAD value v is
shared by 3 deviations (interpolated) or 2 (the plain 1.4826 MAD). A constant x 0.9 or
x 1.1 (or off by one) flips one decision (docs/MUTATION.md, "Left 16").
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

from modalinfo.telemetry.quality import (
    MAD_TO_SIGMA,
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


@pytest.mark.parametrize("ties", [3, 2])
def test_three_deviations_equal_to_the_mad_mark_a_quantised_column(ties):
    # 101 values: the median 0, then +-magnitudes (alternating signs): 49 below v = 1,
    # v shared by `ties` of them, the rest above; the MAD (the 51st deviation) is v
    rng = np.random.default_rng(4)
    v = 1.0
    below = np.sort(rng.uniform(0.1, 0.9, 49))
    above = np.sort(rng.uniform(1.1, 3.0, 48))
    mags = np.concatenate([below, [v, v, v if ties == 3 else v + 0.01], above])
    x = np.concatenate([[0.0], np.where(np.arange(100) % 2 == 0, 1.0, -1.0) * mags])
    x = x[np.random.default_rng(9).permutation(x.size)]
    n, h = x.size, min(v - below.max(), above.min() - v)
    grouped = v - h / 2.0 + h * (0.5 - 50 / n) / (3 / n)  # 50 deviations below v
    expected = grouped if ties == 3 else v
    assert grouped < 0.97 * v  # the two readings differ by > 3 %
    sigma = assess_quality(x[:, None]).sigma[0]
    assert sigma == pytest.approx(MAD_TO_SIGMA * expected, rel=1e-12)
