"""Planted-bug review round 25 (review25, issue 27): the small-n and effective-sample
rules of fixes 38-a, where round 37's tests left a near variant of the rule passing.

References, from outside the code: the normal scores ``Phi^-1(rank / (n + 1))`` with
scipy's ``rankdata`` and ``ndtri`` and their Pearson correlation with numpy, the
Gaussian MI ``-0.5 ln(1 - r^2)``, and the documented extrapolation of
``small_sample_rule`` beyond its table's last point (g_L, n_L) = (2.80, 143):
``n_max = n_L e^(g - g_L) g_L / g`` ("n_max grows as e^g / g"); the lag-1
autocorrelations of statsmodels' ``acf`` with the Marriott & Pope (1954) correction
``r + (1 + 3 r) / n``, each series its own.
"""

import math

import numpy as np
import pytest
from scipy.special import ndtri
from scipy.stats import rankdata
from statsmodels.tsa.stattools import acf

from modalinfo.information.convergence import effective_sample_rule
from modalinfo.information.copula import small_sample_rule
from modalinfo.information.ksg import KSG_SMALL_N_REACH

from .test_bias_rules_round37 import _ar1_lag_pair, _pair


def _extrapolated_n_max(x, y):
    n = x.shape[0]
    r = np.corrcoef(ndtri(rankdata(x) / (n + 1)), ndtri(rankdata(y) / (n + 1)))[0, 1]
    g = -0.5 * math.log(1.0 - r * r)
    g_last, n_last = 2.80, 143
    assert g > g_last  # beyond the table: the e^g / g growth is what is judged
    return n_last * math.exp(g - g_last) * g_last / g


@pytest.mark.parametrize(("n", "seed"), [(200, 1), (300, 1)])
def test_beyond_the_table_n_max_grows_as_e_to_the_g_over_g(n, seed):
    """R25-I1: rho = 0.9999 (normal scores 3.3-3.5 nats at these n): n_max 205 at
    n = 200 (warned, "n ~ 205"), 236 at n = 300 (silent); g / g_L in place of g_L / g
    said 291 and warned at 300."""
    x, y = _pair(n, 0.9999, seed)
    n_max = _extrapolated_n_max(x, y)
    why = small_sample_rule(x, y, KSG_SMALL_N_REACH, "KSG with k = 3")
    if n <= n_max:
        assert why is not None and f"up to n ~ {n_max:.0f} " in why
    else:
        assert why is None


def test_the_message_gives_each_series_its_own_corrected_lag1():
    """R25-I5: x AR(1) 0.999, y AR(1) 0.995, n = 5000: 18.6 effective pairs; the
    message's two autocorrelations are x's and y's (0.9986 and 0.9940), not x's twice."""
    n = 5000
    x, y = _ar1_lag_pair(0.999, n, 1)[0], _ar1_lag_pair(0.995, n, 3)[0]
    rx, ry = acf(x, nlags=1)[1], acf(y, nlags=1)[1]
    rx, ry = rx + (1 + 3 * rx) / n, ry + (1 + 3 * ry) / n
    assert f"{rx:.4f}" != f"{ry:.4f}"
    why = effective_sample_rule(x, y)
    assert why is not None
    assert f"(lag-1 autocorrelations {rx:.4f} and {ry:.4f}, each r + (1 + 3 r) / n" in why


@pytest.mark.parametrize("seed", [100, 101, 102])
def test_kde_on_raw_values_is_not_judged_by_the_normal_score_table(seed):
    """R25-I3: the KDE table is the default KDE's on normal scores; with copula=False
    (raw values) the same rho = 0.99 pairs of 50 read within the tolerance (20 seeds,
    measured: -0.039 nats, s.e. 0.030, against max(0.05, 10 %) = 0.196): no warning.
    Judging every default bandwidth (``and`` for ``or``) warned on each."""
    import warnings

    from modalinfo.information import BiasRuleWarning, mutual_information

    x, y = _pair(50, 0.99, seed)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        mutual_information(x, y, method="kde", copula=False)
    assert [str(w.message) for w in record if issubclass(w.category, BiasRuleWarning)] == []
