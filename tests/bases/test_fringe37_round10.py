"""Fringe index 37 is the 12th-order spherical aberration (adversarial round 10 PART a).

Reference: the 37-term Fringe Zernike table that Zemax exports (e.g. Opt. Express 20,
15928 (2012), Table 2: Z37 = 924 rho^12 - 2772 rho^10 + 3150 rho^8 - 1680 rho^6
+ 420 rho^4 - 42 rho^2 + 1), whose radial polynomial is R_12^0; the unit-RMS factor of
(n, 0) is sqrt(n + 1) (Noll 1976, eq. 4).
"""

import numpy as np
from numpy.polynomial import polynomial

from modalinfo.bases import fringe_to_noll, fringe_to_zernike, noll_to_fringe, zernike_radial
from modalinfo.bases.indexing import zernike_to_fringe
from modalinfo.telemetry import rms_from_peak_normalized

#: Zemax's Fringe Z37, coefficients of rho^0, rho^2, ..., rho^12.
Z37_EVEN_COEFFS = [1, -42, 420, -1680, 3150, -2772, 924]


def test_fringe_37_is_the_published_polynomial():
    n, m = fringe_to_zernike(37)
    assert (n, m) == (12, 0)
    rho = np.linspace(0.0, 1.0, 11)
    coeffs = np.zeros(13)
    coeffs[::2] = Z37_EVEN_COEFFS
    np.testing.assert_allclose(zernike_radial(n, m, rho), polynomial.polyval(rho, coeffs),
                               atol=1e-9)
    assert zernike_to_fringe(12, 0) == 37


def test_peak_to_rms_factor_of_term_37():
    np.testing.assert_allclose(rms_from_peak_normalized([1.0], [37]), [1 / np.sqrt(13)])


def test_conversion_stays_a_bijection():
    j = np.arange(1, 2001)
    n, m = fringe_to_zernike(j)
    assert len(set(zip(n.tolist(), m.tolist(), strict=True))) == j.size
    np.testing.assert_array_equal(zernike_to_fringe(n, m), j)
    np.testing.assert_array_equal(noll_to_fringe(fringe_to_noll(j)), j)
    assert fringe_to_zernike(49) == (6, 6)
