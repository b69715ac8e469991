"""Round 35 PART a (issue 27, S3): ``lag1_autocorrelations`` of columns far from zero.

Reference: ``statsmodels.tsa.stattools.acf`` (lag 1, ``adjusted=False``, the same biased
estimator) of each column as a 1-D series, on the same stored float64 values. Unit noise
offset by 1e12 keeps ~13 bits of its spread in float64, enough for a lag-1 estimate
within 1e-5; the sampling error of the estimate itself is 1 / sqrt(n) = 3e-3 at
n = 10^5, far above the bound. Before the fix the column means along axis 0 of the 2-D
array were summed row by row and their rounding (~1e-11 of the scaled values) exceeded
the scaled noise: 0.57 for white noise and 0.67 instead of 0.40 for the second column.
"""

import numpy as np
import pytest
from statsmodels.tsa.stattools import acf

from modalinfo.forecast import lag1_autocorrelations


@pytest.mark.parametrize("offset", [1e12, -3e11])
def test_columns_far_from_zero_match_statsmodels(offset):
    rng = np.random.default_rng(0)
    n = 100_000
    x = rng.standard_normal((n, 2))
    x[:, 1] = np.cumsum(x[:, 1]) * 0.01 + rng.standard_normal(n)  # lag-1 about 0.4
    y = x + offset
    got = lag1_autocorrelations(y)
    want = [acf(y[:, j], nlags=1, fft=False)[1] for j in range(2)]
    assert got == pytest.approx(want, abs=1e-5)
