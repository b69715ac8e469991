"""The histogram CMI's resolution rule: coarse rule-chosen grids switch to the KSG CMI.

References: the exact MI of two Gaussian pairs at rho = 0.8 in 2 x 2 groups,
-ln(1 - 0.8^2) = 1.0217 nats (Cover & Thomas 2006, eq. 8.56, summed over independent
pairs); the exact share of a Gaussian pair's MI that k equiprobable bins per axis keep,
from the bivariate normal's cell probabilities (``scipy.stats.multivariate_normal``),
the numbers the rule's message quotes; the switched value must equal the public KSG
CMI (``method="ksg"``) bit for bit, and a kept histogram the histogram with the same
bins given explicitly.
"""

import math
import warnings

import numpy as np
import pytest
from scipy.stats import multivariate_normal, norm

from modalinfo.information import BiasRuleWarning, conditional_mutual_information
from modalinfo.information.conditional import KSG_SWITCH_MAX_SAMPLES
from modalinfo.information.histogram import MIN_RESOLVING_BINS

TRUTH = -math.log(1 - 0.8**2)  # two pairs at rho = 0.8


def _pairs(n, seed=50):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((n, 2))
    y = 0.8 * x + 0.6 * rng.standard_normal((n, 2))
    return x, y


def _kept_share(rho, k):
    """Exact MI of a Gaussian pair cut into k equiprobable bins per axis, over its MI."""
    e = norm.ppf(np.linspace(0, 1, k + 1))
    e[0], e[-1] = -40.0, 40.0
    g = np.stack(np.meshgrid(e, e, indexing="ij"), axis=-1)
    cdf = multivariate_normal([0, 0], [[1, rho], [rho, 1]]).cdf(g)
    p = np.clip(np.diff(np.diff(cdf, axis=0), axis=1), 1e-300, None)
    return float(np.sum(p * np.log(p * k * k))) / (-0.5 * math.log(1 - rho * rho))


def test_the_rule_quotes_the_exact_discretisation_loss():
    # the message's numbers: 8 bins lose 14 %, 4 bins 31 % of a rho = 0.8 pair's MI
    assert MIN_RESOLVING_BINS == 8
    assert round(100 * (1 - _kept_share(0.8, 8))) == 14
    assert round(100 * (1 - _kept_share(0.8, 4))) == 31


def test_coarse_grid_switches_to_ksg_with_a_warning():
    x, y = _pairs(4000)  # 5 bins per axis over 4 columns
    with pytest.warns(BiasRuleWarning, match="5 bins per axis.*resolution rule.*KSG"):
        got = conditional_mutual_information(x, y, method="histogram")
    assert got == conditional_mutual_information(x, y, method="ksg")
    assert got == pytest.approx(TRUTH, abs=0.05)  # the 5-bin histogram: -0.22
    with pytest.warns(BiasRuleWarning, match="returned anyway"):
        kept = conditional_mutual_information(x, y, fallback="none", method="histogram")
    assert kept == conditional_mutual_information(x, y, bins=5, method="histogram")
    assert kept < TRUTH - 0.15
    with pytest.raises(ValueError, match="resolution rule.*fallback='raise'"):
        conditional_mutual_information(x, y, fallback="raise", method="histogram")


def test_no_switch_for_chosen_bins_discrete_columns_or_above_the_sample_cap():
    x, y = _pairs(4000)
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiasRuleWarning)
        # the caller's bins are kept
        conditional_mutual_information(x, y, bins=5, method="histogram")
        # repeated values: the KSG's neighbour counts need distinct points; since fix54-c
        # the histogram kept for these 62-66-level columns, whose levels share 5 bins, is
        # judged against the KSG (0.790 against 1.017; exact 1.022) and warns
        xr, yr = np.round(x, 1), np.round(y, 1)
        with pytest.warns(BiasRuleWarning, match="merges into 5 bins"):
            kept = conditional_mutual_information(xr, yr, method="histogram")
        assert kept == conditional_mutual_information(xr, yr, bins=5, method="histogram")
        # 1 x 1 given 3 columns at n above the cap: 6 bins per axis, histogram kept
        n = KSG_SWITCH_MAX_SAMPLES + 10_000
        rng = np.random.default_rng(51)
        z = rng.standard_normal((n, 3))
        a = z.sum(axis=1) + rng.standard_normal(n)
        b = a + rng.standard_normal(n)
        assert conditional_mutual_information(a, b, z, method="histogram") == \
            conditional_mutual_information(
            a, b, z, bins=6, method="histogram")


def test_fine_grid_keeps_the_histogram():
    # 1 x 1 given 1 column at n = 4000: 8 bins per axis, the rule holds
    rng = np.random.default_rng(52)
    z, e1, e2 = rng.standard_normal((3, 4000))
    x = z + e1
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiasRuleWarning)
        got = conditional_mutual_information(x, x + e2, z, method="histogram")
    assert got == conditional_mutual_information(x, x + e2, z, bins=8, method="histogram")
