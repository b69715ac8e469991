"""The von Karman phase structure function at small ``u = 2 pi r / L0``, where its closed
form cancels, against the two leading terms of its small-u expansion.

Reference (outside the code): Abramowitz & Stegun 9.6.2 and 9.6.10,
``u^nu K_nu(u) = pi / (2 sin nu pi) 2^nu [1 / Gamma(1 - nu) - h^(2 nu) / Gamma(1 + nu)
+ h^2 / Gamma(2 - nu) - h^(2 + 2 nu) / Gamma(2 + nu) + ...]`` with ``h = u / 2`` and
``nu = 5/6``, so that the von Karman ``D`` over Kolmogorov's
``2 (24/5 Gamma(6/5))^(5/6) (r / r0)^(5/3)`` (Fried 1966, the 6.8839 constant written
exactly) is ``1 - Gamma(11/6) / Gamma(7/6) h^(1/3) + Gamma(11/6) / Gamma(17/6) h^2``
to ``O(h^(7/3))`` (below 1e-11 relative for u <= 3e-5). Written here with
``scipy.special.gamma``, not with the module's series.

Planted bug R8-19 (docs/MUTATION.md, round 8): the series switch ``_VK_SERIES_U`` moved
from 1e-4 to 1e-6 let the cancelling closed form through at 1e-6 < u < 1e-4 (measured
1.3e-6 relative at u = 1.5e-6, 1.3e-8 at u = 3e-5); ``test_dm_kl.py``'s monotone
Kolmogorov limit (tolerance 1e-9 on the ratio, deficits of 1e-2) did not see it.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.special import gamma

from modalinfo.bases.dm_kl import von_karman_structure_function


@pytest.mark.parametrize("u", [1.5e-6, 3e-6, 1e-5, 3e-5])
def test_small_u_follows_the_bessel_series_expansion(u):
    r0, r = 0.1, np.array([0.01, 0.02, 0.03])
    outer_scale = 2.0 * math.pi * r[-1] / u  # u at r[-1], down to u / 3 at r[0]
    h = math.pi * r / outer_scale  # u / 2
    ratio = (1.0 - gamma(11 / 6) / gamma(7 / 6) * h ** (1 / 3)
             + gamma(11 / 6) / gamma(17 / 6) * h**2)
    kolmogorov = 2.0 * (24 / 5 * gamma(6 / 5)) ** (5 / 6) * (r / r0) ** (5 / 3)
    got = von_karman_structure_function(r, r0, outer_scale)
    np.testing.assert_allclose(got / kolmogorov, ratio, rtol=1e-10, atol=0.0)
