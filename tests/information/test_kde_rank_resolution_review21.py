"""Review 21: the kde rank-resolution rule leaves a pair with a repeated value alone.

Reference: the documented rule (``information.api.ceiling_problem``): a pair in which
EITHER variable repeats a value is left to the discrete rules (its table is its law), so
the rank rule, ln n - 2 nats (ln 2000 - 2 = 5.60), does not speak there. The pair is a
Gaussian one at rho = 0.999999 (exact MI 6.56 nats, past the rule) with one variable
rounded to 1e-3: about 1550 distinct values of 2000 (counted with ``numpy.unique``).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import mutual_information

N = 2000


@pytest.mark.parametrize("side", ["x", "y"])
def test_one_rounded_variable_is_not_judged_by_the_ranks(side):
    rng = np.random.default_rng(7)
    x = rng.standard_normal(N)
    y = 0.999999 * x + math.sqrt(1 - 0.999999**2) * rng.standard_normal(N)
    if side == "x":
        x = np.round(x, 3)
    else:
        y = np.round(y, 3)
    assert np.unique(x).size < N or np.unique(y).size < N  # a repeated value on one side
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        value = mutual_information(x, y, method="kde")
    assert value > math.log(N) - 2.0  # past the rank rule's line: only the ties silence it
    assert [str(w.message) for w in caught if "ranks of n" in str(w.message)] == []
