"""The one exact rescaling rule (modalinfo.common.scaling) and its three callers.

References: IEEE 754 (multiplying by a power of two changes only the exponent, so
``x * 2**-e * 2**e == x`` bit for bit), the scaling law of differential entropy
(h(c X) = h(X) + ln c, Cover & Thomas 2006, Theorem 8.6.4) and the scale invariance of
mutual information and of the Politis-White block length (a ratio of autocovariances).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.common.scaling import SAFE_MAGNITUDE, rescale_power_of_two
from modalinfo.information import entropy, mutual_information
from modalinfo.information.resampling import politis_white_length
from modalinfo.information.selection import _safe_scale


def test_within_bounds_returns_the_same_object():
    x = np.random.default_rng(0).normal(size=50)
    scaled, e = rescale_power_of_two(x, float(np.max(np.abs(x))))
    assert scaled is x and e == 0


@pytest.mark.parametrize("size", [1e-200, 3e-101, 2e100, 1e300])
def test_out_of_bounds_is_exact_and_lands_in_half_to_one(size):
    x = np.random.default_rng(1).uniform(-1.0, 1.0, 64) * size
    mag = float(np.max(np.abs(x)))
    scaled, e = rescale_power_of_two(x, mag)
    assert e != 0
    assert 0.5 <= np.max(np.abs(scaled)) < 1.0
    np.testing.assert_array_equal(np.ldexp(scaled, e), x)  # IEEE: no digit lost


def test_columns_are_judged_one_by_one():
    rng = np.random.default_rng(2)
    a = rng.normal(size=(40, 3)) * np.array([1.0, 1e150, 1e-150])
    scaled, e = rescale_power_of_two(a, np.abs(a).max(axis=0))
    assert e[0] == 0 and e[1] > 0 and e[2] < 0
    np.testing.assert_array_equal(scaled[:, 0], a[:, 0])
    np.testing.assert_array_equal(np.ldexp(scaled, e), a)


def test_peak_alone_can_trigger():
    # a spread in bounds with a peak beyond them (a large offset): rescaled by the spread
    x = np.array([1e101, 1e101 + 2e85, 1e101 + 4e85])
    spread = float(np.max(x) / 2 - np.min(x) / 2)
    scaled, e = rescale_power_of_two(x, spread, peak=float(np.max(np.abs(x))))
    assert e == math.frexp(spread)[1]
    assert SAFE_MAGNITUDE[0] < spread < SAFE_MAGNITUDE[1]


@pytest.mark.parametrize("method", ["ksg", "kde", "histogram", "gaussian"])
def test_callers_answer_as_for_the_sample_in_range(method):
    rng = np.random.default_rng(3)
    x = rng.normal(size=400)
    y = 0.6 * x + 0.8 * rng.normal(size=400)
    k = 700  # 2^700 ~ 5e210: beyond the bounds, the squares would overflow
    # MI is scale invariant: the scaled pair answers exactly as the pair in range
    assert (mutual_information(np.ldexp(x, k), np.ldexp(y, -k), method=method)
            == mutual_information(x, y, method=method))
    # entropy shifts by ln 2^k (Cover & Thomas 8.6.4)
    h = entropy(x, method=method)
    assert entropy(np.ldexp(x, k), method=method) == pytest.approx(h + k * math.log(2), 1e-12)
    assert entropy(np.ldexp(x, -k), method=method) == pytest.approx(h - k * math.log(2),
                                                                    1e-12)


def test_block_length_and_selection_scale_invariant():
    rng = np.random.default_rng(4)
    s = np.zeros(500)
    for i in range(1, 500):
        s[i] = 0.8 * s[i - 1] + rng.normal()
    ref = politis_white_length(s)
    for k in (-400, -200, 200, 400):  # 2^200 ~ 1.6e60: beyond the block length's 1e50
        assert politis_white_length(np.ldexp(s, k)) == ref
    both = np.stack([s, np.ldexp(s, 500), np.ldexp(s, -500)], axis=1)
    scaled = _safe_scale(both)
    np.testing.assert_array_equal(scaled[:, 0], s)
    np.testing.assert_array_equal(scaled[:, 1], scaled[:, 2])
