"""Round 8 of issue 27's adversarial inputs (K-L bases): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 8, issue 27".

Reference: linear algebra: the mean-square matrix of coefficients whose third column is
the sum of the first two has rank 2, so a third K-L mode is any unit vector of its null
space (arbitrary); numpy.linalg.matrix_rank gives the rank.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis


@pytest.fixture(scope="module")
def dependent():
    rng = np.random.default_rng(3)
    x, y = rng.standard_normal((2, 500))
    return np.c_[x, y, x + y]


def test_more_data_kl_modes_than_the_rank_are_refused(dependent):
    # d37: three modes asked of rank-2 data were returned, the third arbitrary
    assert np.linalg.matrix_rank(dependent.T @ dependent) == 2
    zb = ZernikeBasis(Pupil(16), [2, 3, 4])
    with pytest.raises(ValueError, match=r"`n_modes` must be at most the rank .* 2"):
        KLBasis.from_data(zb, dependent, n_modes=3)


def test_data_kl_modes_up_to_the_rank_are_given(dependent):
    zb = ZernikeBasis(Pupil(16), [2, 3, 4])
    kl = KLBasis.from_data(zb, dependent, n_modes=2)
    assert kl.n_modes == 2
    # the default keeps every mode, the null one with variance 0 (a dead mode downstream)
    full = KLBasis.from_data(zb, dependent)
    assert full.variances[-1] < 1e-12 * full.variances[0]
