"""The Gaussian-copula normal scores (``modalinfo.information.copula``).

References (outside the code): the normal scores written out by hand from ranks counted
here, ``Phi^-1(rank / (n + 1))`` with ``scipy.stats.norm.ppf`` (Ince et al. 2017), tied
values sharing the mean of the ranks they occupy (ranks counted by hand in the test,
not with ``rankdata``); the standard normal law of the scores (the mean of
``Phi^-1(k / (n + 1))`` over k is 0 by symmetry, and their variance tends to 1); the
invariance of ranks under a strictly increasing map (Kraskov et al. 2004, eq. 2).
"""

import numpy as np
import pytest
from scipy import stats

from modalinfo.information.copula import check_copula, copula_scores, copula_scores_ties


def test_scores_are_the_normal_quantiles_of_hand_counted_ranks():
    x = np.array([2.5, -7.0, 40.0, 0.1, 3.0])
    ranks = np.array([3, 1, 5, 2, 4])  # counted by hand
    expected = stats.norm.ppf(ranks / 6.0)
    np.testing.assert_allclose(copula_scores(x), expected, rtol=1e-14, atol=1e-15)
    z, ties = copula_scores_ties(x)
    np.testing.assert_allclose(z, expected, rtol=1e-14, atol=1e-15)
    assert ties is False


def test_tied_values_share_the_mean_of_their_ranks():
    # 1.0 occupies ranks 2, 3, 4 (mean 3); 5.0 ranks 5 and 6 (mean 5.5)
    x = np.array([1.0, 0.0, 5.0, 1.0, 5.0, 1.0])
    ranks = np.array([3.0, 1.0, 5.5, 3.0, 5.5, 3.0])
    z, ties = copula_scores_ties(x)
    assert ties is True
    np.testing.assert_allclose(z, stats.norm.ppf(ranks / 7.0), rtol=1e-14, atol=1e-15)
    np.testing.assert_array_equal(z, copula_scores(x))
    # a single tie among distinct values is seen (two ranks: a half-integer mean)
    z, ties = copula_scores_ties(np.array([0.3, 0.1, 0.3, 0.2]))
    assert ties is True and z[0] == z[2] == pytest.approx(stats.norm.ppf(3.5 / 5.0))


def test_scores_are_standard_normal_whatever_the_units():
    # a heavy-tailed sample maps to the same scores as a strictly increasing map of it
    rng = np.random.default_rng(5)
    x = rng.standard_cauchy(4001)
    z = copula_scores(x)
    np.testing.assert_array_equal(z, copula_scores(1e6 * np.arctan(x) + 3.0))
    # scores are Phi^-1(k / (n + 1)), k = 1..n, in some order: mean 0 by symmetry and a
    # variance within 1 % of 1 at n = 4001 (the tails beyond Phi^-1(n / (n + 1)) are cut)
    assert abs(z.mean()) < 1e-12
    assert z.var() == pytest.approx(1.0, rel=0.01)
    assert z.max() == pytest.approx(stats.norm.ppf(4001 / 4002), rel=1e-12)


def test_copula_option_must_be_a_bool():
    assert check_copula(np.bool_(True)) is True
    with pytest.raises(TypeError, match=r"`copula` must be a bool; got 1"):
        check_copula(1)


def test_copula_scores_take_a_list_and_refuse_a_table():
    """Audit 9: a list raised AttributeError; a (T, M) table was ranked flattened
    against its row count (scores of ranks beyond n + 1: NaN). Reference: scipy's
    normal quantile of rank / (n + 1)."""
    x = [0.3, -1.2, 5.0, 0.0, 2.2]
    want = stats.norm.ppf(stats.rankdata(x) / 6.0)
    np.testing.assert_allclose(copula_scores(x), want, rtol=1e-12)
    with pytest.raises(ValueError, match="`x` must be 1-D; got 2-D"):
        copula_scores(np.ones((5, 2)))
    with pytest.raises(TypeError, match="`x` must be real"):
        copula_scores(np.array(x) + 1j)
