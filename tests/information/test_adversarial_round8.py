"""Round 8 of issue 27's adversarial inputs (estimators): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 8, issue 27".

References: the Kozachenko-Leonenko estimator's definition (the log of the distance to
the k-th neighbour, 0 for a tie: no finite estimate) and its exact value for a normal
sample, 0.5 ln(2 pi e); the rank of a sample correlation matrix (<= n - 1, so the
Gaussian CMI's determinants are undefined for n <= d columns) and the exact Gaussian
MI -0.5 ln(1 - rho^2).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information, entropy


@pytest.fixture(scope="module")
def normal():
    return np.random.default_rng(8).standard_normal(2000)


@pytest.mark.parametrize("make", [
    lambda x: (x > 0).astype(float),  # a40: binary data gave -701 nats
    lambda x: np.round(x, 2),  # d23: rounded data gave -577 nats
    lambda x: np.r_[np.zeros(10), x[10:]],  # b44: ten zeros of 2000 gave -2.1 for 1.42
])
def test_ksg_entropy_refuses_repeated_values(normal, make):
    with pytest.raises(ValueError, match=r"`x` has \d+ repeated value"):
        entropy(make(normal), method="ksg")


def test_ksg_entropy_of_distinct_normal_values_is_still_estimated(normal):
    # the refusal is for ties only: a normal sample keeps its estimate near 0.5 ln(2 pi e)
    exact = 0.5 * math.log(2.0 * math.pi * math.e)
    assert entropy(normal, method="ksg") == pytest.approx(exact, abs=0.05)


def test_gaussian_cmi_refuses_fewer_samples_than_columns(normal):
    # d15: 20 samples over 102 columns gave -1.48 nats (exact 0.22) with no word
    rng = np.random.default_rng(2)
    x = normal[:20]
    y = 0.6 * x + 0.8 * rng.standard_normal(20)
    z = rng.standard_normal((20, 100))
    with pytest.raises(ValueError, match=r"more samples than columns.*102 columns"):
        conditional_mutual_information(x, y, z, method="gaussian")


def test_gaussian_cmi_with_more_samples_than_columns_is_estimated(normal):
    # the same pair with 3 noise columns and 2000 samples: near the exact Gaussian MI
    rng = np.random.default_rng(2)
    y = 0.6 * normal + 0.8 * rng.standard_normal(normal.size)
    z = rng.standard_normal((normal.size, 3))
    exact = -0.5 * math.log(1.0 - 0.36)
    value = conditional_mutual_information(normal, y, z, method="gaussian", copula=False)
    assert value == pytest.approx(exact, abs=0.03)
