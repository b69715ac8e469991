"""Histogram entropy of rounded (lattice) data and of heavy tails (audit 11).

Reference: the differential entropy of the dequantised density (uniform within each
cell of width q around a lattice value), ``H(P) + ln q`` with the cell probabilities
P_j = Phi((j + 1/2) q) - Phi((j - 1/2) q) of a standard normal (scipy), 1.4292 and
1.4590 nats at q = 0.5 and 1 (1.4189 unrounded); and ln 8 for integers uniform on 0..7.
Before audit 11 the rule's bins, narrower than q, gave 0.91 and 0.32 nats.
Heavy tails: the entropy of Student's t (scipy.stats.t.entropy), 2.531 nats for one
degree of freedom, where equal-width bins over the range gave 5.7 silently (now a
BiasRuleWarning; equiprobable bins are the way out it names).
"""

import math
import warnings

import numpy as np
import pytest
from scipy.stats import norm, t

from modalinfo.information import BiasRuleWarning, entropy


def _dequantised_normal_entropy(q: float) -> float:
    j = np.arange(-200, 201)
    p = norm.cdf((j + 0.5) * q) - norm.cdf((j - 0.5) * q)
    p = p[p > 0]
    return float(-np.sum(p * np.log(p)) + math.log(q))


@pytest.mark.parametrize("q", [0.5, 1.0, 2.0])
def test_rounded_normal_entropy_is_the_dequantised_density_entropy(q):
    x = q * np.round(np.random.default_rng(1).standard_normal(5000) / q)
    assert entropy(x, method="histogram") == pytest.approx(_dequantised_normal_entropy(q),
                                                           abs=0.03)


def test_integers_on_eight_levels():
    x = np.random.default_rng(2).integers(0, 8, 5000).astype(float)
    assert entropy(x, method="histogram") == pytest.approx(math.log(8.0), abs=0.01)


def test_fine_rounding_keeps_the_rule_bins():
    # bins of the rule (~0.3 sd at n = 5000) wider than q = 0.01: the continuous value
    x = 0.01 * np.round(np.random.default_rng(3).standard_normal(5000) / 0.01)
    assert entropy(x, method="histogram") == pytest.approx(0.5 * math.log(2 * math.pi * math.e),
                                                           abs=0.03)


def test_heavy_tail_warns_and_the_named_way_out_is_near_the_truth():
    x = np.random.default_rng(4).standard_t(1, 5000)
    with pytest.warns(BiasRuleWarning, match="equal-width bins"):
        biased = entropy(x, method="histogram")
    assert biased > t(1).entropy() + 1.0  # what the warning is about
    quantile = entropy(x, method="histogram", binning="quantile")
    assert quantile == pytest.approx(t(1).entropy(), abs=0.4)  # measured +0.27..+0.33


@pytest.mark.parametrize("df", [3, 5])
def test_moderate_tails_do_not_warn(df):
    x = np.random.default_rng(5).standard_t(df, 5000)
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiasRuleWarning)
        got = entropy(x, method="histogram")
    assert got == pytest.approx(t(df).entropy(), abs=0.1)
