"""Quantile intervals need a replicate in each tail (adversarial round 10 PART a).

Reference: order statistics. With B replicates and no replicate beyond the (1 - level)/2
quantile, the percentile bounds are the extreme replicates, and the chance that a new
exchangeable draw falls between the minimum and maximum of B is (B - 1) / (B + 1)
whatever the level asked; 2 / (1 - level) replicates put one in each tail.
"""

import numpy as np
import pytest

from modalinfo.information import mutual_information_ci
from modalinfo.information.resampling import BlockBootstrapWarning


@pytest.fixture(scope="module")
def pair():
    rng = np.random.default_rng(0)
    x = rng.standard_normal(500)
    return x, 0.6 * x + 0.8 * rng.standard_normal(500)


@pytest.mark.parametrize("interval", ["percentile", "basic"])
def test_too_few_replicates_for_the_level_are_refused(pair, interval):
    with pytest.raises(ValueError, match=r"`n_resamples`=50 .* n_resamples >= 2000"):
        mutual_information_ci(*pair, interval=interval, confidence_level=0.999,
                              n_resamples=50, seed=0)


def test_edge_at_two_over_one_minus_level(pair):
    # 0.95: 40 replicates put one in each 2.5 % tail; 39 do not
    with pytest.raises(ValueError, match="n_resamples >= 40"):
        mutual_information_ci(*pair, interval="percentile", n_resamples=39, seed=0)
    # the histogram's block quantile intervals warn (fix53-b: its replicates' bias)
    with pytest.warns(BlockBootstrapWarning, match="block replicates are biased upward"):
        res = mutual_information_ci(*pair, interval="percentile", n_resamples=40, seed=0)
    assert res.low < res.high


def test_normal_interval_has_no_such_limit(pair):
    res = mutual_information_ci(*pair, confidence_level=0.999, n_resamples=50, seed=0)
    assert res.low < res.estimate < res.high
