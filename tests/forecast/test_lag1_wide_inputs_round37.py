"""Series that float64 cannot hold are refused by name (adversarial round 37 PART a, S12 / W1).

Reference: numpy in long double, two passes on the values as given (Brockwell & Davis
eq. 1.4.4). An AR(1) series (phi 0.6) plus 1e16 stored as ``np.longdouble`` keeps its
spread (64-bit mantissa: steps of 2^-10 at 1e16), and its lag-1 is ~0.6; cast to float64
(steps of 2) it read 0.49, silently. It must be refused as integers beyond 2^53 are,
naming ``x`` and "subtract an offset"; the same series near zero, or plus 1e6 (float64
steps 1e-10 of a unit spread), is accepted and equals the long-double reference. A list
of Python ints near 1e20 (an object array: beyond int64) is refused for its range, not
as "not a numeric array".
"""

import numpy as np
import pytest

from modalinfo.forecast import lag1_autocorrelations

pytestmark = pytest.mark.skipif(np.finfo(np.longdouble).nmant <= np.finfo(np.float64).nmant,
                                reason="long double is float64 on this platform")


def _ar1(n: int = 5000) -> np.ndarray:
    e = np.random.default_rng(5).standard_normal(n).astype(np.longdouble)
    a = np.zeros(n, dtype=np.longdouble)
    for i in range(1, n):
        a[i] = 0.6 * a[i - 1] + e[i]
    return a


def _reference(v: np.ndarray) -> float:
    d = v - v.mean()
    return float((d[:-1] * d[1:]).sum() / (d * d).sum())


def test_long_double_far_from_zero_refused_by_name():
    v = _ar1() + np.longdouble(1e16)
    assert abs(_reference(v) - 0.6) < 0.05  # the long double holds the series
    with pytest.raises(ValueError, match="`x` is float.* data whose spread.*subtract an offset"):
        lag1_autocorrelations(v)


@pytest.mark.parametrize("offset", [0.0, 1e6])
def test_long_double_float64_can_hold_is_accepted(offset):
    v = _ar1() + np.longdouble(offset)
    assert lag1_autocorrelations(v)[0] == pytest.approx(_reference(v), abs=1e-6)


def test_python_ints_beyond_int64_name_the_range():
    values = [10**20 + i % 3 for i in range(50)]
    with pytest.raises(ValueError, match=r"`x` holds integers beyond int64.*subtract an offset"):
        lag1_autocorrelations(values)
    with pytest.raises(TypeError, match="must be a numeric array"):  # not numbers: as before
        lag1_autocorrelations(np.array(["a", "b", "c"], dtype=object))
