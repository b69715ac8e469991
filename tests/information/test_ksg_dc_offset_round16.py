"""KSG on raw values (``copula=False``) of data riding on a large DC offset.

References (outside the code under test): the exact MI of a bivariate normal pair,
``-0.5 ln(1 - rho^2)``, and the exact CMI of a Gaussian triple from its partial
correlation; the KSG distances' invariance under a common shift of a variable (the
same estimate on the data without the offset is the same question asked by another
road). Round 16 PART a found a log at 1e12 +- 1 (float64 spacing there 1.2e-4, so the
values repeat) estimated at 0.027 nats for the exact 0.223, and a CMI at -0.011 for the
exact 0.112: the tie-breaking noise was scaled by ``mean |u|`` of the uncentred data
(1e-10 x 1e12 = 100 standard deviations). The bounds: the KSG estimate's sampling
standard deviation at n = 2000 is ~0.015 nats (measured over seeds in
tests/information/test_accuracy.py's regime), so 0.06 is four of them.
"""

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information, mutual_information

N = 2000


@pytest.fixture(scope="module")
def pair():
    rng = np.random.default_rng(1)
    x = rng.standard_normal(N)
    y = 0.6 * x + 0.8 * rng.standard_normal(N)
    return x, y


@pytest.mark.parametrize("offset", [1e6, 1e9, 1e12])
def test_mi_of_offset_pair_is_the_exact_mi(pair, offset):
    x, y = pair
    exact = -0.5 * np.log(1 - 0.36)
    shifted = mutual_information(x + offset, y + offset, method="ksg", copula=False)
    assert abs(shifted - exact) < 0.06
    # the offset only rounds the data to its float spacing (1.2e-4 sd at 1e12)
    assert abs(shifted - mutual_information(x, y, method="ksg", copula=False)) < 0.01


def test_cmi_of_offset_triple_is_the_exact_cmi():
    rng = np.random.default_rng(4)
    z = rng.standard_normal(N)
    x = z + rng.standard_normal(N)
    y = 0.5 * x + z + rng.standard_normal(N)
    # given z: x = e1, y = 0.5 e1 + e2, partial correlation 0.5 / sqrt(1.25)
    exact = -0.5 * np.log(1 - 0.25 / 1.25)
    got = conditional_mutual_information(x + 1e12, y + 1e12, z + 1e12, method="ksg",
                                         copula=False)
    assert abs(got - exact) < 0.06
