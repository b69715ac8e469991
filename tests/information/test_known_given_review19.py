"""Columns known given z through a monotone map with flats (review19, planted bug CM1).

Reference: the chain rule of mutual information (Cover & Thomas, Thm 2.5.2): a column
x1 that is any function of z gives I(x1; y | z) = 0 exactly, whatever the joint law, and
I(x1, x2; y | z) = I(x2; y | z). ``max(z, 0)`` (rectified) and ``round(z)`` (quantised)
are monotone functions of z with flat stretches. Before review19 only strictly monotone
columns were dropped: I(max(z, 0); y | z) was -0.041 nats with KSG (below 0, impossible)
and 0.083 with the Gaussian estimator at n = 2000.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information as cmi

N = 2000


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(3)
    z = rng.standard_normal(N)
    x = np.maximum(z, 0.0)
    return z, x, x + 0.5 * rng.standard_normal(N), rng.standard_normal(N)


@pytest.mark.parametrize("method", ["ksg", "gaussian", "kde", "histogram"])
@pytest.mark.parametrize("how", ["rectified", "quantised", "clipped from above"])
def test_a_function_of_z_with_flats_carries_nothing_given_z(data, method, how):
    z, x, y, _ = data
    col = {"rectified": x, "quantised": np.round(z),
           "clipped from above": np.minimum(-z, 0.5)}[how]
    assert cmi(col, y, z, method=method) == 0.0


@pytest.mark.parametrize("method", ["ksg", "gaussian"])
def test_the_known_column_drops_out_of_a_pair(data, method):
    z, x, y, noise = data
    assert cmi(np.column_stack([x, noise]), y, z, method=method) == cmi(
        noise, y, z, method=method)


def test_a_column_not_a_function_of_z_is_kept():
    # x2 = z + n1, y = x2 + e (unit normals): given z, x2 is n1 and y is n1 + e, so
    # I(x2; y | z) = -ln(1 - 1/2) / 2 = 0.3466 nats (Gaussian law); sampling sd at
    # n = 2000 about 0.016, bound 0.05 (3 sd)
    rng = np.random.default_rng(7)
    z, n1, e = rng.standard_normal((3, N))
    assert cmi(z + n1, z + n1 + e, z, method="gaussian") == pytest.approx(
        0.5 * np.log(2.0), abs=0.05)
