"""Small-n and effective-sample bias warnings of round 37 PART a, S13-S16 (fixes 38-a, issue 27).

Reference: the exact MI of a bivariate Gaussian pair (and of an AR(1)'s lag-1 pair),
-0.5 ln(1 - rho^2): 1.959 nats at rho = 0.99, 2.761 at 0.998, 0.144 at 0.5. Measured on
the code before the fix (docs/ADVERSARIAL.md, "Fixes 38-a"; 20-40 seeds, mean error
(s.e.)): default KSG at rho = 0.99, n = 20: -0.60 (0.06), n = 50: -0.29 (0.03), 0 of 20
warned; KDE at n = 50, rho = 0.99: -0.19 to -0.23 (0.02-0.03) for a tolerance 0.196,
0-4 of 40 warned; the histogram of AR(1) rho = 0.998 lagged pairs at n = 5000 (true
n_eff 10, below the rule's 20): -0.42 (0.03), 8 of 30 silent. The tolerance is the
package's max(0.05 nats, 10 %). The values are unchanged: only a ``BiasRuleWarning`` is
added (one per call). The effective-pair count is checked against statsmodels' acf with
the Marriott & Pope (1954) correction r + (1 + 3 r) / n.
"""

import math
import warnings

import numpy as np
import pytest
from statsmodels.tsa.stattools import acf

from modalinfo.information import BiasRuleWarning, mutual_information
from modalinfo.information.convergence import effective_pairs
from modalinfo.information.copula import SMALL_SAMPLE_RULE_MAX, small_sample_rule
from modalinfo.information.ksg import KSG_SMALL_N_REACH


def _pair(n, rho, seed):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(n)
    return x, rho * x + math.sqrt(1.0 - rho * rho) * rng.standard_normal(n)


def _ar1_lag_pair(rho, n, seed):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n + 1)
    a = np.empty(n + 1)
    a[0] = e[0] / math.sqrt(1.0 - rho * rho)  # stationary start
    for t in range(1, n + 1):
        a[t] = rho * a[t - 1] + e[t]
    return a[:-1], a[1:]


def _bias_warnings(x, y, method):
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        value = mutual_information(x, y, method=method)
    return value, [str(w.message) for w in record if issubclass(w.category, BiasRuleWarning)]


@pytest.mark.parametrize("n", [20, 50])
@pytest.mark.parametrize("seed", [5000, 5001, 5002])
def test_default_ksg_of_a_strong_small_pair_warns_once(n, seed):
    """S13 (n = 20) / S14 (n = 50): KSG -0.60 / -0.29 nats below 1.959 (tolerance 0.196)."""
    x, y = _pair(n, 0.99, seed)
    _, found = _bias_warnings(x, y, "ksg")
    assert len(found) == 1 and "KSG with k = 3" in found[0] and f"n = {n}" in found[0]


def test_default_kde_of_a_strong_pair_of_50_warns_once():
    """S15: KDE at n = 50, rho = 0.99, -0.19 to -0.23 nats for a tolerance 0.196 (the
    table warns 15 of 20 such pairs, those whose normal scores read >= ~1.68 nats)."""
    for seed in (5000, 5002, 5004):
        x, y = _pair(50, 0.99, seed)
        _, found = _bias_warnings(x, y, "kde")
        assert len(found) == 1 and found[0].startswith("mutual_information with method='kde': KDE")


@pytest.mark.parametrize("method", ["ksg", "kde"])
@pytest.mark.parametrize(("rho", "seed"), [(0.5, 5000), (0.5, 5001), (0.0, 5002)])
def test_weak_or_independent_pairs_of_50_are_not_warned(method, rho, seed):
    """rho = 0.5 (0.144 nats) and independent pairs of 50: KSG / KDE within the tolerance
    (means +-0.02 nats, s.e. 0.015-0.022, 20 seeds), 0 of 20 warned before and after."""
    _, found = _bias_warnings(*_pair(50, rho, seed), method)
    assert found == []


def test_the_rule_stops_where_the_bias_is_within_the_tolerance():
    """rho = 0.99 at n = 150 (KSG -0.07, s.e. 0.02) and any pair above its largest n
    (a near copy at 10^4, the Beyond-Normal tasks' n) are not judged."""
    x, y = _pair(150, 0.99, 5003)
    assert small_sample_rule(x, y, KSG_SMALL_N_REACH, "KSG") is None
    x, y = _pair(SMALL_SAMPLE_RULE_MAX + 1, 0.999999, 5004)
    assert small_sample_rule(x, y, KSG_SMALL_N_REACH, "KSG") is None


def test_effective_pairs_corrects_each_lag1_for_its_bias():
    """Bartlett's n (1 - rx ry) / (1 + rx ry) on statsmodels' lag-1 plus (1 + 3 r) / n."""
    x, y = _ar1_lag_pair(0.998, 5000, 7001)
    rx, ry = acf(x, nlags=1)[1], acf(y, nlags=1)[1]
    rx, ry = rx + (1 + 3 * rx) / 5000, ry + (1 + 3 * ry) / 5000
    assert effective_pairs(x, y) == pytest.approx(5000 * (1 - rx * ry) / (1 + rx * ry),
                                                  rel=1e-9)


@pytest.mark.parametrize("seed", [7001, 7015, 7022, 7026])  # silent before
def test_ar1_0998_lag_pairs_are_warned(seed):
    """S16: AR(1) rho = 0.998, n = 5000 (true n_eff 10): histogram -0.42 nats (s.e. 0.03)
    below 2.761 (tolerance 0.276); these seeds' sample lag-1 read n_eff 20-25 before."""
    x, y = _ar1_lag_pair(0.998, 5000, seed)
    value, found = _bias_warnings(x, y, "histogram")
    truth = -0.5 * math.log(1 - 0.998**2)
    assert truth - value > max(0.05, 0.1 * truth)  # the bias the warning is for
    assert len(found) == 1


def test_white_and_weakly_correlated_series_keep_their_effective_pairs():
    """White noise and AR(1) 0.3 at n = 5000: n_eff ~ n (Bartlett), no warning."""
    for rho, seed in ((0.0, 7100), (0.3, 7101)):
        x, y = _ar1_lag_pair(rho, 5000, seed)
        assert effective_pairs(x, y) > 0.8 * 5000 * (1 - rho**2) / (1 + rho**2)
        assert _bias_warnings(x, y, "histogram")[1] == []
