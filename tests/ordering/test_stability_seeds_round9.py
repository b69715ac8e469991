"""Repeated seeds are refused by ordering_stability (round 9, row o-stab-seeds-dup).

Reference: a seed fixes the subsample, so two equal seeds give the same ordering and a
Spearman rho of exactly 1 by construction (``seeds=(0, 0)`` reported perfect seed
stability); two distinct seeds give a rho computed from two subsamples, which scipy's
spearmanr of the two stored orders' ranks reproduces.
"""

import numpy as np
import pytest
from scipy import stats

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import ordering_stability


def test_repeated_seeds_refused_distinct_seeds_reproduced():
    rng = np.random.default_rng(1)
    a = rng.standard_normal((600, 6)) * np.linspace(1.0, 0.5, 6)
    zb = ZernikeBasis(Pupil(16), modes=range(2, 8))
    with pytest.raises(ValueError, match="`seeds` must be distinct"):
        ordering_stability(a, zb, "mi_marginal", seeds=(0, 0), window=300)
    s = ordering_stability(a, zb, "mi_marginal", seeds=(0, 1), window=300)
    ranks = np.empty_like(s.seed_orders)
    for i, o in enumerate(s.seed_orders):
        ranks[i, o] = np.arange(o.size)
    assert np.ravel(s.seed_spearman)[-1] == pytest.approx(
        stats.spearmanr(ranks[0], ranks[1]).statistic)
