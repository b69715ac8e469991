"""Round 7 of issue 27's adversarial inputs (estimators' Python API): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 7, issue 27".

References: the API's documented contract (a ValueError/TypeError naming the argument,
the rule and the value, before any work); for the KDE bandwidth floor, Scott's rule
n^(-1/(d+4)) (Scott 1992, ch. 6), which reaches 1e-3 only at n = 1e15 samples (d = 1);
for the Gaussian pair's MI, the closed form -0.5 ln(1 - rho^2).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import entropy, mutual_information


@pytest.fixture
def pair():
    rng = np.random.default_rng(7)
    x = rng.standard_normal(2000)
    return x, 0.6 * x + 0.8 * rng.standard_normal(2000)


@pytest.mark.parametrize("h", [1e-300, 1e-4])
def test_kde_bandwidth_below_any_sample_size_is_refused(pair, h):
    # a16: bandwidth=1e-300 stopped with ZeroDivisionError (h^2 underflowed to 0)
    with pytest.raises(ValueError, match=r"`bandwidth` .* must be >= 0.001"):
        mutual_information(*pair, method="kde", bandwidth=h)
    with pytest.raises(ValueError, match=r"`bandwidth` .* must be >= 0.001"):
        entropy(pair[0], method="kde", bandwidth=h)


def test_kde_bandwidth_at_the_floor_still_estimates(pair):
    # the floor itself is accepted and gives a finite number (a needle-thin kernel)
    assert math.isfinite(mutual_information(*pair, method="kde", bandwidth=1e-3))


@pytest.mark.parametrize("g", [10**5, 10**7])
def test_kde_grid_size_beyond_memory_is_refused(pair, g):
    # a18, a80: grid_size 1e5 / 1e7 asked for 74 GiB / 720 TiB: MemoryError traceback
    with pytest.raises(ValueError, match=r"`grid_size` must be an int <= 4096; got"):
        mutual_information(*pair, method="kde", grid_size=g)


def test_kde_grid_size_at_the_cap_agrees_with_the_default(pair):
    # 4096 is accepted; on a Gaussian pair both grids give the closed form within the
    # estimator's error (rho = 0.6: 0.2231 nats; 2000 samples: sd ~ 0.02)
    exact = -0.5 * math.log(1 - 0.36)
    big = mutual_information(*pair, method="kde", bandwidth="scott", grid_size=4096)
    small = mutual_information(*pair, method="kde", bandwidth="scott")
    assert big == pytest.approx(small, abs=1e-3)
    assert big == pytest.approx(exact, abs=0.05)
