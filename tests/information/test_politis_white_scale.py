"""The Politis-White block length does not depend on the series' scale.

Reference: the definition (Politis & White 2004, with Patton et al. 2009): the length is
``(2 G^2 / D)^(1/3) n^(1/3)`` with G and D sums of autocovariances and of their square,
so multiplying the series by any constant leaves it unchanged. Audit 9 (centre): a
series at 1e100 overflowed ``g(0)^2`` (NaN: a traceback from ``order_modes``) and one at
1e-160 underflowed to a "constant" series of length 1.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.information.resampling import politis_white_length
from modalinfo.ordering import order_modes


@pytest.fixture(scope="module")
def ar1():
    rng = np.random.default_rng(3)
    e = rng.standard_normal(2000)
    x = np.zeros(2000)
    for t in range(1, 2000):
        x[t] = 0.9 * x[t - 1] + e[t]
    return x


@pytest.mark.parametrize("scale", [1e-300, 1e-160, 1e-60, 1e60, 1e100, 1e150, 1e300])
def test_the_length_is_scale_free(ar1, scale):
    b = politis_white_length(ar1)
    assert b > 10  # an AR(1) of 0.9 needs long blocks (the scale-free value it must keep)
    assert politis_white_length(ar1 * scale) == pytest.approx(b, rel=1e-12)


def test_an_mi_ordering_of_coefficients_at_1e100_is_that_at_1():
    # the MI orderings are functions of ranks: the order at any scale is the order at 1
    rng = np.random.default_rng(5)
    a = rng.standard_normal((300, 5)) * [3.0, 2.0, 1.5, 1.0, 0.5]
    basis = ZernikeBasis(Pupil(16), range(2, 7))
    kw = dict(seed=0, n_resamples=0, sample_budget=2000)
    ref = order_modes(a, basis, "mi_marginal", **kw)
    big = order_modes(a * 1e100, basis, "mi_marginal", **kw)
    assert big.order.tolist() == ref.order.tolist() == [0, 1, 2, 3, 4]
    assert big.block_length == ref.block_length
