"""KSG CMI keeps a discrete column as it is when it partials out z (review10).

Round 10 of planted bugs. Audit 11 made :func:`modalinfo.information.ksg.ksg_cmi`
replace each continuous column of x and y by its residual on z; a discrete column is
kept (its residual would break its levels apart). Reference (analytic): for a fair
binary x, its copy y = x and z independent continuous noise, ``I(X; Y | Z) = H(X) =
ln 2`` nats. Measured 0.694 and 0.701 (2 seeds, n = 2000); with the binary columns
residualised 0.843 and 0.846 (planted bug R10-R1, which escaped the KSG and CMI tests:
their discrete cases are all-discrete, which the table estimator takes).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information


@pytest.mark.parametrize("seed", [0, 1])
def test_a_binary_copy_given_independent_noise_holds_ln2(seed):
    rng = np.random.default_rng(seed)
    n = 2000
    x = rng.integers(0, 2, n).astype(float)
    z = rng.standard_normal(n)
    value = conditional_mutual_information(x, x.copy(), z, method="ksg")
    assert value == pytest.approx(math.log(2.0), abs=0.05)
