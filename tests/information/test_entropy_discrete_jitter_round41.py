"""The kde entropy refuses a discrete sample whose levels carry float rounding jitter.

Adversarial round 41 PART a, issue 27 (row V19): ``entropy(method='kde')`` documents a
ValueError for a discrete sample (at most n / 10 distinct values), but a line at a quarter
of the frame rate written by ``cos`` takes 4 levels with rounding jitter (numpy: 15,295
distinct float64 values of 20,000), so it returned -0.02 nats and called the sample
"multimodal or heavy-tailed". Levels are now counted to 1e-9 of the range. References:
the 4 values ``cos(0.4 + k pi / 2)`` (analytic), and for the continuous samples that must
not be refused, the normal's entropy ``0.5 ln(2 pi e)`` (Cover & Thomas, eq. 8.9) and
numpy's count of their distinct values.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import entropy


def test_a_four_valued_line_written_by_cos_is_refused_as_discrete():
    t = np.arange(20000)
    x = np.cos(np.pi * t / 2 + 0.4)
    assert np.unique(x).size > 2000  # the jitter: exact counting sees a continuous sample
    levels = np.cos(0.4 + np.pi * np.arange(4) / 2)
    # within ~t eps of them (cos of arguments up to 3e4: 2.4e-12 measured)
    assert np.abs(x[:, None] - levels[None, :]).min(axis=1).max() < 1e-10
    with pytest.raises(ValueError, match="only 4 distinct values"):
        entropy(x, method="kde")


@pytest.mark.parametrize("n", [2000, 20000])
def test_continuous_float32_data_is_not_refused(n):
    x = np.random.default_rng(41).standard_normal(n).astype(np.float32)
    assert np.unique(x).size > 0.99 * n
    value = entropy(x.astype(float), method="kde")
    assert abs(value - 0.5 * math.log(2 * math.pi * math.e)) < 0.1


def test_data_with_a_few_exact_duplicates_is_not_refused():
    rng = np.random.default_rng(7)
    x = rng.standard_normal(5000)
    x[::50] = x[1::50]  # 100 exact duplicate pairs
    assert np.unique(x).size == 4900
    value = entropy(x, method="kde")
    assert abs(value - 0.5 * math.log(2 * math.pi * math.e)) < 0.1
