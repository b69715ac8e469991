"""``rank_agreement`` correlates the modes' ranks (the inverse permutations), not the orders.

Reference: Spearman's ``rho = 1 - 6 sum d^2 / (n (n^2 - 1))`` and Kendall's tau by
counting concordant pairs, by hand on the ranks of two 3-cycle orders (each mode's
rank is its position in the order); and ``scipy.stats.spearmanr`` / ``kendalltau`` on
ranks found with ``list.index`` for random orders of 12 modes. The hand values in
``test_stability.py`` use the identity, a reversal and one swap, for which an order
and its ranks correlate alike (a permutation's and its inverse's distances from the
identity are equal), so they cannot tell orders from ranks.
"""

import numpy as np
import pytest
from scipy import stats

from modalinfo.ordering import rank_agreement


def test_hand_values_on_two_three_cycles():
    # ranks: a -> modes (0, 1, 2, 3) at (2, 0, 1, 3); b -> (0, 1, 3, 2)
    # d = (2, -1, -2, 1): sum d^2 = 10, rho = 1 - 60 / 60 = 0; 3 concordant, 3 discordant
    # pairs: tau = 0 (the orders themselves as sequences give rho = -0.2)
    rho, tau = rank_agreement([1, 2, 0, 3], [0, 1, 3, 2])
    assert rho == pytest.approx(0.0, abs=1e-12)
    assert tau == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("seed", range(4))
def test_random_orders_against_scipy_on_the_ranks(seed):
    rng = np.random.default_rng(seed)
    a, b = rng.permutation(12), rng.permutation(12)
    ra = [list(a).index(m) for m in range(12)]
    rb = [list(b).index(m) for m in range(12)]
    rho, tau = rank_agreement(a, b)
    assert rho == pytest.approx(stats.spearmanr(ra, rb).statistic, abs=1e-12)
    assert tau == pytest.approx(stats.kendalltau(ra, rb).statistic, abs=1e-12)
