"""Where the histogram interval's mixed-pair raise applies, and where not (review34).

``uncertainty._grid_loss_bound`` with ``HistogramEngine.mixed_grid_loss`` (round 51 PART a,
Q63) raises the upper bound for a discrete variable against a continuous one with no
repeated value, in either order. Reference: the pair is the test's own channel (x ~
Bernoulli(0.05), y = x + N(0, 0.5^2), n = 2,000: the raise applies, as
``test_mixed_data_round51.py`` shows), its mirror (y discrete, x continuous: the same
pair), and the same y rounded to 0.02 (about 2,000 draws on ~200 values: repeated values,
so y is no continuum whose k bins the model describes, and the interval is the
bootstrap's alone); and the units: 1 bit = ln 2 nats, so the interval in bits is the
nats one over ln 2; and a persistent pair (Bartlett's effective sample count, from numpy's
lag-1 autocorrelations, under 20), which the raise is documented not to judge.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import mutual_information_ci
from modalinfo.information.resampling import BlockBootstrapWarning


def _channel():
    rng = np.random.default_rng(351)
    x = (rng.random(2000) < 0.05).astype(float)
    return x, x + 0.5 * rng.standard_normal(2000)


def test_the_raise_applies_in_either_order():
    x, y = _channel()
    for a, b in ((x, y), (y, x)):
        res = mutual_information_ci(a, b, n_resamples=99, seed=1)
        assert "upper bound raised" in res.note, res.note


def test_a_continuous_side_with_repeated_values_takes_no_raise():
    x, y = _channel()
    y = np.round(y / 0.02) * 0.02
    assert np.unique(y).size < y.size
    res = mutual_information_ci(x, y, n_resamples=99, seed=1)
    assert "upper bound raised" not in res.note, res.note


def test_the_raised_interval_in_bits_is_the_nats_one_over_ln_2():
    # 1 bit = ln 2 nats: the same draw and seed, read in bits, is the nats interval scaled
    x, y = _channel()
    nats = mutual_information_ci(x, y, n_resamples=99, seed=1)
    bits = mutual_information_ci(x, y, n_resamples=99, seed=1, units="bits")
    assert "upper bound raised" in bits.note
    for a, b in ((nats.estimate, bits.estimate), (nats.low, bits.low),
                 (nats.high, bits.high)):
        assert b * np.log(2.0) == pytest.approx(a, rel=1e-9, abs=1e-12)


def test_bins_the_caller_chose_take_no_raise():
    # a bin rule the caller named (Sturges) is theirs, as for the Gaussian pair's raise
    x, y = _channel()
    res = mutual_information_ci(x, y, method="histogram", bins="sturges", n_resamples=99,
                                seed=1)
    assert "upper bound raised" not in res.note, res.note


def test_a_persistent_pair_takes_no_raise():
    # "Not for a persistent pair": a flag in runs (switching with probability 0.003 per
    # frame) and y = flag + 0.5 AR(1) noise (phi 0.999). Bartlett's effective sample
    # count n (1 - rx ry) / (1 + rx ry), from numpy's lag-1 autocorrelations, is far
    # under 20; the iid bootstrap's narrow interval is where a raise would show
    rng = np.random.default_rng(34)
    n = 2000
    flag = (np.cumsum(rng.random(n) < 0.003) % 2).astype(float)
    e = np.zeros(n)
    w = rng.standard_normal(n)
    for t in range(1, n):
        e[t] = 0.999 * e[t - 1] + np.sqrt(1 - 0.999**2) * w[t]
    y = flag + 0.5 * e
    rx, ry = (np.corrcoef(a[:-1], a[1:])[0, 1] for a in (flag, y))
    assert n * (1 - rx * ry) / (1 + rx * ry) < 20
    # the iid bootstrap on such a pair is itself warned (stop 58, iid_bootstrap_rule)
    with pytest.warns(BlockBootstrapWarning, match="bootstrap='iid'"):
        res = mutual_information_ci(flag, y, n_resamples=99, seed=1, bootstrap="iid")
    assert "upper bound raised" not in res.note, res.note
