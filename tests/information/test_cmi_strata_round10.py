"""A curve within every stratum of a discrete z: infinite CMI (round 10 PART a).

Reference: Cover & Thomas 2006, sec. 8.5, applied per stratum: with s = +-1 independent
of x and y = s x, the conditional law of y given (x, s) is a point, so I(x; y | s) is
infinite; with noise added it is finite (0.5 ln(1 + 1 / sigma^2) for y = s x + sigma e).
"""

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information
from modalinfo.information.api import InfiniteMIError

RNG = np.random.default_rng(4)
X = RNG.standard_normal(4000)
S = RNG.choice([-1.0, 1.0], X.size)


@pytest.mark.parametrize("method", ["ksg", "histogram", "gaussian"])
def test_sign_product_given_the_sign_is_refused(method):
    with pytest.raises(InfiniteMIError, match="within each of the 2 strata"):
        conditional_mutual_information(X, S * X, S, method=method)


def test_noisy_product_is_estimated():
    y = S * X + 0.5 * RNG.standard_normal(X.size)
    cmi = conditional_mutual_information(X, y, S)
    assert abs(cmi - 0.5 * np.log(1 + 1 / 0.25)) < 0.08
