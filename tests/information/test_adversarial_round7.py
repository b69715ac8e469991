"""Round 7 of issue 27's adversarial inputs (estimators' Python API): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 7, issue 27".

References: the API's documented contract (a ValueError/TypeError naming the argument,
the rule and the value, before any work); for the KDE bandwidth floor, Scott's rule
n^(-1/(d+4)) (Scott 1992, ch. 6), which reaches 1e-3 only at n = 1e15 samples (d = 1);
the grid cap (4096) from the memory of its joint grid; a continuous copy has infinite
(C)MI (no joint density, Cover & Thomas 2006, sec. 8.5) and a fair binary copy ln 2; a
circular block of the whole series is a rotation holding the same (x, y) pairs.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information,
    conditional_mutual_information_ci,
    entropy,
    mutual_information,
    mutual_information_ci,
    transfer_entropy,
)
from modalinfo.information.api import InfiniteMIError
from modalinfo.information.kde import KDEEngine


@pytest.fixture
def pair():
    rng = np.random.default_rng(7)
    x = rng.standard_normal(2000)
    return x, 0.6 * x + 0.8 * rng.standard_normal(2000)


@pytest.mark.parametrize("h", [1e-300, 1e-4])
def test_kde_bandwidth_below_any_sample_size_is_refused(pair, h):
    # a16: bandwidth=1e-300 stopped with ZeroDivisionError (h^2 underflowed to 0)
    with pytest.raises(ValueError, match=r"`bandwidth` .* must be >= 0.001"):
        mutual_information(*pair, method="kde", bandwidth=h)
    with pytest.raises(ValueError, match=r"`bandwidth` .* must be >= 0.001"):
        entropy(pair[0], method="kde", bandwidth=h)


def test_kde_bandwidth_at_the_floor_still_estimates(pair):
    # the floor itself is accepted and gives a finite number (a needle-thin kernel),
    # with the bias rule's warning since audit 9 (n h^2 = 0.002 < 30)
    with pytest.warns(BiasRuleWarning, match="n h\\^d"):
        assert math.isfinite(mutual_information(*pair, method="kde", bandwidth=1e-3))


@pytest.mark.parametrize("g", [10**5, 10**7])
def test_kde_grid_size_beyond_memory_is_refused(pair, g):
    # a18, a80: grid_size 1e5 / 1e7 asked for 74 GiB / 720 TiB: MemoryError traceback
    with pytest.raises(ValueError, match=r"`grid_size` must be an int <= 4096; got"):
        mutual_information(*pair, method="kde", grid_size=g)


def test_kde_grid_size_cap_is_4096_exactly():
    # the boundary of the rule: 4096 accepted (an engine is built), 4097 refused
    assert KDEEngine(grid_size=4096).grid_size == 4096
    with pytest.raises(ValueError, match=r"`grid_size` must be an int <= 4096; got 4097"):
        KDEEngine(grid_size=4097)


@pytest.mark.parametrize("method", ["histogram", "ksg", "gaussian", "kde"])
def test_cmi_of_a_copy_is_refused_as_infinite_like_mi(pair, method):
    # a48, a48b, a48c: cmi(x, x, z) gave 3.34 nats (ksg, histogram) and cmi(x, -x, z)
    # 16.9 (gaussian), where mutual_information(x, x) is refused: a copy has no joint
    # density, its (C)MI is infinite (Cover & Thomas 2006, sec. 8.5)
    x, y = pair
    z = y[::-1].copy()
    n = 300 if method == "kde" else x.size  # kde's CMI is exact O(n^2)
    with pytest.raises(InfiniteMIError, match=r"strictly monotone function"):
        conditional_mutual_information(x[:n], -x[:n], z[:n], method=method)


def test_cmi_of_a_discrete_copy_stays_finite():
    # a copy with repeated values is a discrete variable: finite (its entropy), as for MI
    b = np.repeat([0.0, 1.0], 500)
    z = np.random.default_rng(3).standard_normal(1000)
    assert conditional_mutual_information(b, b.copy(), z, method="ksg") == pytest.approx(
        math.log(2), abs=0.05)


def test_te_of_a_delayed_copy_is_refused_and_the_reverse_is_near_zero():
    # a42: te(s, s delayed by one frame) gave 3.54 (ksg) / 1.94 (histogram) nats
    s = np.random.default_rng(5).standard_normal(3000)
    delayed = np.r_[0.0, s[:-1]]
    with pytest.raises(InfiniteMIError, match=r"`target` is a strictly monotone function "
                                              r"of `source` 1 sample"):
        transfer_entropy(s, delayed)
    # the other direction: the target's own past holds everything, TE ~ 0 (sd ~ 0.02)
    assert abs(transfer_entropy(delayed, s, method="ksg")) < 0.05


@pytest.mark.parametrize("b", [2000, 1999, 1001])
def test_bootstrap_blocks_longer_than_half_the_series_are_refused(pair, b):
    # a54, f19, f20: block_length = n (n - 1) gave a 95 % interval 1e-16 (3e-4) wide
    # around an estimate whose bootstrap sd at b = 3 is 0.015: every circular block of
    # the whole series is a rotation, holding the same (x, y) pairs
    with pytest.raises(ValueError, match=r"`block_length` must be at most half the "
                                         r"series \(1000 of 2000 samples\)"):
        mutual_information_ci(*pair, n_resamples=20, block_length=b)
    with pytest.raises(ValueError, match=r"`block_length` must be at most half"):
        conditional_mutual_information_ci(*pair, None, n_resamples=20, block_length=b)


def test_a_block_of_half_the_series_still_spreads(pair):
    # at b = n / 2 each resample joins two arcs from random starts: a spread remains
    ci = mutual_information_ci(*pair, n_resamples=30, block_length=1000, seed=0)
    assert ci.bootstrap_std > 1e-3


def test_scoring_before_fit_is_a_value_error(pair):
    # a76: a RuntimeError, where every other refusal of the API is a ValueError/TypeError
    from modalinfo.information import MutualInformation

    with pytest.raises(ValueError, match=r"not fitted: call \.fit\(x\) first"):
        MutualInformation("ksg").score(pair[1])
