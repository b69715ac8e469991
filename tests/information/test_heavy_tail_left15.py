"""Leftovers 15-stats: the heavy-tail rule of the block bootstrap gives its stated false-alarm rate.

References, outside the code under test: the binomial law of the false alarms of
seeded Gaussian pairs (scipy.stats.binom), the statistic written here with numpy's
least squares (AR(4) with a constant, as ``_stats.ar_innovations`` documents it) and
median / MAD (1 / Phi^-1(3/4) from statistics.NormalDist); Student t3 innovations
(infinite fourth moment, Athreya 1987) for the rule's purpose. Before the fix the rule's
per-series Bonferroni threshold treated the MAD as exact: 4.8e-4 of 1e5 Gaussian pairs
at n = 500 flagged for a stated 1e-4 (benchmarks/bench_heavy_tail_left15.py).
"""

from statistics import NormalDist

import numpy as np
import pytest
from scipy import stats
from scipy.signal import lfilter

from modalinfo.information import resampling
from modalinfo.information.resampling import _heavy_tail_rule, heavy_tail_threshold

MAD_TO_SIGMA = 1.0 / NormalDist().inv_cdf(0.75)


def _statistic(x):
    """max |e - median| / (1.4826 MAD) of the AR(4) least-squares innovations, per row."""
    m, n = x.shape
    out = np.empty(m)
    for i, row in enumerate(x):
        lags = np.column_stack([row[4 - j:n - j] for j in range(1, 5)] + [np.ones(n - 4)])
        e = row[4:] - lags @ np.linalg.lstsq(lags, row[4:], rcond=None)[0]
        dev = np.abs(e - np.median(e))
        out[i] = dev.max() / (MAD_TO_SIGMA * np.median(dev))
    return out


def _bounds(m, p, tail=5e-4):
    return stats.binom.ppf(tail, m, p), stats.binom.isf(tail, m, p)


def test_threshold_gives_the_stated_rate_on_gaussian_pairs():
    # 3000 white Gaussian pairs of n = 200 at a pair rate of 1e-2: 30 expected, the
    # two-sided 99.9 % binomial range about [14, 50]. The old per-series Bonferroni
    # threshold at the same level flagged ~4.5 % of pairs (~134).
    n, pairs, alpha = 200, 3000, 1e-2
    z = _statistic(np.random.default_rng(151).standard_normal((2 * pairs, n)))
    k = heavy_tail_threshold(n - 4, 2, alpha)
    hits = int((z.reshape(pairs, 2).max(axis=1) > k).sum())
    lo, hi = _bounds(pairs, alpha)
    assert lo <= hits <= hi, (hits, lo, hi)


def test_the_rule_flags_gaussian_ar1_pairs_at_its_stated_rate(monkeypatch):
    # the rule itself (its threshold read from HEAVY_TAIL_ALPHA) on 1500 AR(1) 0.9
    # Gaussian pairs of n = 200 at a stated 2e-2 per pair: 30 expected, 99.9 % range
    # about [14, 50]; before, ~0.09 of pairs (~135)
    monkeypatch.setattr(resampling, "HEAVY_TAIL_ALPHA", 2e-2)
    rng = np.random.default_rng(152)
    pairs = 1500
    g = lfilter([1.0], [1.0, -0.9], rng.standard_normal((2 * pairs, 400)), axis=1)[:, 200:]
    hits = sum(_heavy_tail_rule(g[2 * i], g[2 * i + 1], "t") is not None
               for i in range(pairs))
    lo, hi = _bounds(pairs, 2e-2)
    assert lo <= hits <= hi, (hits, lo, hi)


@pytest.mark.parametrize("both", [True, False])
def test_t3_pairs_at_n500_are_still_flagged(both):
    # the rule's purpose: AR(1) 0.9 pairs with Student t3 innovations (t3 in x only:
    # P(|t3| > 5.6 robust sigmas) ~ 0.6 % per value, scipy.stats.t, so ~3 of 496 values
    # pass and a miss has probability ~ e^-3 per record; 20 records with both heavy,
    # 20 with x alone, seeded)
    rng = np.random.default_rng(153)
    flagged = 0
    for _ in range(20):
        x = lfilter([1.0], [1.0, -0.9], rng.standard_t(3, 500))
        e = rng.standard_t(3, 500) if both else rng.standard_normal(500)
        y = lfilter([1.0], [1.0, -0.9], e)
        why = _heavy_tail_rule(x, y, "mutual_information_ci")
        flagged += why is not None and "fourth moments" in why
    assert flagged >= (20 if both else 17)
