"""Round 22 PART a: information identities when z determines a column of x or y.

Reference: the chain rule of mutual information (Cover & Thomas, Thm 2.5.2). A column
x1 that is a strictly monotone function of a column of z is known given z, so
I(x1; y | z) = 0 and I(x1, x2; y | z) = I(x2; y | z), for any joint law, exactly; the
estimators must give the same number both ways (0.0 for I(x; y | y)). Before the fix the
KDE CMI returned -0.0527 nats for I(x; y | y) at n = 3000 (its four entropies held a
singular pair and stopped cancelling) while I(x; y | x) was 0.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information as cmi

N = 1500


@pytest.fixture(scope="module")
def xyn():
    rng = np.random.default_rng(22)
    x = rng.standard_normal(N)
    return x, 0.7 * x + rng.standard_normal(N), rng.standard_normal(N)


@pytest.mark.parametrize("method", ["kde", "ksg", "histogram", "gaussian"])
def test_conditioning_on_a_copy_of_y_gives_zero(xyn, method):
    x, y, _ = xyn
    assert cmi(x, y, y, method=method) == 0.0
    assert cmi(x, y, np.exp(y), method=method) == 0.0  # a monotone copy: known given z


@pytest.mark.parametrize("method", ["kde", "gaussian"])
def test_a_known_column_drops_out_by_the_chain_rule(xyn, method):
    x, y, noise = xyn
    both = cmi(np.column_stack([x, noise]), y, np.column_stack([-x, y[::-1]]),
               method=method)
    assert both == cmi(noise, y, np.column_stack([-x, y[::-1]]), method=method)
