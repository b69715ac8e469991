"""Lag-1 autocorrelation of series far from zero (adversarial round 36 PART a, S1).

Reference: the same estimator (Brockwell & Davis eq. 1.4.4) computed by numpy in long
double with two passes on the values as stored (an offset of 1e16 quantises unit noise
to steps of 2: the reference is what the stored numbers say, not the AR coefficient).
Before the fix each column was divided by its ``max |x|``, which rounded every value by
~1e-16 of the offset: 0.578 against 0.596 at 1e16 (sampling SE 0.005).
"""

import numpy as np
import pytest

from modalinfo.forecast import lag1_autocorrelations


def _reference(v: np.ndarray) -> float:
    d = v.astype(np.longdouble)
    d = d - d.mean()
    return float((d[:-1] * d[1:]).sum() / (d * d).sum())


@pytest.mark.parametrize("offset", [1e15, 1e16, -3e16])
def test_lag1_far_from_zero_matches_long_double(offset):
    rng = np.random.default_rng(3)
    e = rng.standard_normal(20000)
    a = np.zeros(20000)
    for i in range(1, a.size):
        a[i] = 0.7 * a[i - 1] + e[i]
    v = a + offset
    got = lag1_autocorrelations(np.c_[v, v[::-1]])
    ref = _reference(v)
    # ulp-level agreement of a ratio of sums of 2e4 terms (long double: 1e-19 each)
    assert got[0] == pytest.approx(ref, abs=1e-6)
    assert got[1] == pytest.approx(_reference(v[::-1]), abs=1e-6)


def test_lag1_extreme_scales_still_right():
    x = np.array([1.0, -1.0, 1.0, 2.0])
    for scale in (1e300, 1e-310, 1.0):
        got = lag1_autocorrelations((x * scale)[:, None])[0]
        assert got == pytest.approx(_reference(x), rel=1e-12)
