"""Review 21 (K2), settled by left28-misc: the kde rank rule with repeated values.

Reference: ``numpy.unique`` counts and ln d - 2 (d the distinct values of the variable
with fewer of them, the most the ranks of a tied variable resolve is ln d), and the
exact MI of a Gaussian pair with x rounded to ``delta`` (quadrature of
``H(X_d) - H(X_d | Y)``, tests/information/test_kde_rank_ties_left28.py). Review 21
pinned the old rule (any repeated value: not judged), under which x rounded to 1e-3
(about 1550 distinct of 2000) read 6.22 for 6.56 with no word; that case now warns
(test_kde_rank_ties_left28.py). What stays unjudged is a variable with fewer distinct
values than half the samples (``RANK_DISTINCT_SHARE``): there the levels bind, not the
ranks. Here x rounded to 0.01 (444 distinct of 2000): the estimate is past ln 444 - 2
= 4.10 yet within 10 % of the rounded pair's exact MI 5.769, and silent.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import mutual_information

N = 2000
EXACT_ROUNDED_001 = 5.769  # rho = 0.999999, x rounded to 0.01 (quadrature, module notes)


@pytest.mark.parametrize("side", ["x", "y"])
def test_a_heavily_rounded_variable_is_not_judged_by_the_ranks(side):
    rng = np.random.default_rng(7)
    x = rng.standard_normal(N)
    y = 0.999999 * x + math.sqrt(1 - 0.999999**2) * rng.standard_normal(N)
    if side == "x":
        x = np.round(x, 2)
    else:
        y = np.round(y, 2)
    distinct = min(np.unique(x).size, np.unique(y).size)
    assert distinct < N / 2  # the levels bind
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = mutual_information(x, y, method="kde")
    assert value > math.log(distinct) - 2.0  # past ln d - 2: only the share silences it
    assert abs(value - EXACT_ROUNDED_001) < 0.1 * EXACT_ROUNDED_001
    assert [str(w.message) for w in caught if "ranks of n" in str(w.message)] == []
