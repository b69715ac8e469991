"""Round 15 PART a: ``rank_agreement`` at its smallest sizes.

Reference: the docstring's contract (1 for identical orderings, -1 for reversed ones),
with scipy's ``spearmanr`` / ``kendalltau`` for two modes; two orderings of one mode are
the same ordering.
"""

from __future__ import annotations

import warnings

import pytest
from scipy import stats

from modalinfo.ordering import rank_agreement


def test_one_mode_is_identical_agreement_without_warning():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert rank_agreement([0], [0]) == (1.0, 1.0)


def test_two_modes_match_scipy():
    rho, tau = rank_agreement([0, 1], [1, 0])
    assert rho == pytest.approx(stats.spearmanr([0, 1], [1, 0]).statistic)
    assert tau == pytest.approx(stats.kendalltau([0, 1], [1, 0]).statistic)


def test_empty_orderings_refused_by_name():
    with pytest.raises(ValueError, match="`order_a` and `order_b` must each order at least"):
        rank_agreement([], [])
