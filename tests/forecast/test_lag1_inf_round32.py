"""Round 32 (issue 27): ``lag1_autocorrelations`` on a column holding an infinite value.

Reference: ``statsmodels.tsa.stattools.acf`` (lag 1, ``adjusted=False``) for the finite
columns; NaN for a column holding inf, as the docstring gives a column holding NaN.
Before the fix the answer was NaN with numpy's "invalid value encountered in divide"
RuntimeWarning (an error in this suite), which named neither the argument nor the cause.
"""

import numpy as np
import pytest
from statsmodels.tsa.stattools import acf

from modalinfo.forecast import lag1_autocorrelations


@pytest.mark.parametrize("bad", [np.inf, -np.inf])
def test_a_column_holding_inf_is_nan_and_silent(bad):
    rng = np.random.default_rng(0)
    good = rng.standard_normal(200).cumsum()
    broken = good.copy()
    broken[50] = bad
    out = lag1_autocorrelations(np.c_[broken, good, np.r_[np.inf, -np.inf, good[2:]]])
    assert np.isnan(out[0]) and np.isnan(out[2])
    assert out[1] == pytest.approx(acf(good, nlags=1, fft=False)[1], rel=1e-12)
