"""Scales of the Zernike turbulence statistics refused outside their validity (round 25).

References, from outside the code: the pupil diameter range of ``Pupil`` (1e-6 - 1e6 m);
scipy.integrate.quad of the von Karman integral of ``modalinfo.bases.turbulence``'s
module notes, ``int (x^2 + x0^2)^(-11/6) J_{n+1}(x)^2 / x dx`` with ``x0 = pi D / L0``,
against which the finite-L0 variance ratio is checked at D / L0 = 10 (the largest
accepted); Kolmogorov's Noll Delta_10 at a huge outer scale.
"""

import numpy as np
import pytest
from scipy import integrate, special

from modalinfo.bases import (
    KLBasis,
    Pupil,
    noll_residual_variance,
    zernike_covariance,
    zernike_variance,
)


@pytest.mark.parametrize("call", [
    lambda: noll_residual_variance(10, outer_scale=1e-300, diameter=1.0),   # was OverflowError
    lambda: zernike_variance([2], outer_scale=1e-300, diameter=1.0),        # was [0.]
    lambda: zernike_covariance(range(2, 6), outer_scale=1e-6, diameter=1e6),  # was ~1e-46
    lambda: noll_residual_variance(10, outer_scale=0.09, diameter=1.0),     # D / L0 = 11
], ids=["overflow", "zero-variance", "tiny-covariance", "just-beyond"])
def test_outer_scale_below_a_tenth_of_the_diameter_refused(call):
    with pytest.raises(ValueError, match="`outer_scale` must be >= diameter / 10"):
        call()


@pytest.mark.parametrize("diameter", [2.0**70, 1e300, 1e-300, 1e-7])
def test_diameter_outside_the_pupil_range_refused(diameter):
    with pytest.raises(ValueError, match="`diameter` must be in metres within 1e-06 - 1e"):
        noll_residual_variance(10, outer_scale=np.inf, diameter=diameter)


def _vk_integral(n: int, x0: float) -> float:
    f = lambda x: (x * x + x0 * x0) ** (-11 / 6) * special.jv(n + 1, x) ** 2 / x  # noqa: E731
    edges = np.r_[0.0, np.logspace(-8, np.log10(50 * x0 + 400), 400)]
    return sum(integrate.quad(f, a, b, limit=200, epsabs=0, epsrel=1e-11)[0]
               for a, b in zip(edges[:-1], edges[1:], strict=True))


def test_largest_accepted_ratio_matches_scipy_quad():
    # D / L0 = 10 is accepted; the variance relative to D / L0 = 0.1 equals the ratio of
    # quad integrals (measured 4e-5 for tip, 6e-6 for Z11)
    for j, n in [(2, 1), (11, 4)]:
        ours = (zernike_variance([j], outer_scale=1.0, diameter=10.0)[0]
                / zernike_variance([j], outer_scale=1.0, diameter=0.1)[0])
        ref = _vk_integral(n, np.pi * 10.0) / _vk_integral(n, np.pi * 0.1)
        assert ours == pytest.approx(ref, rel=2e-4)


def test_plausible_scales_unchanged():
    assert noll_residual_variance(10, outer_scale=1e300, diameter=1.0) == pytest.approx(
        noll_residual_variance(10), rel=1e-6)
    assert np.isfinite(noll_residual_variance(10, outer_scale=4.0, diameter=39.0))


def test_theoretical_kl_applies_the_same_rule():
    # KLBasis.from_turbulence built its covariance blocks without zernike_covariance's
    # checks: L0 = 1e-300 gave five zero variances and a RuntimeWarning
    with pytest.raises(ValueError, match="`outer_scale` must be >= diameter / 10"):
        KLBasis.from_turbulence(Pupil(16, diameter=1.0), 5, outer_scale=1e-300)
    # the accepted edge: an eigen-decomposition keeps the trace, so all 20 K-L variances
    # sum to the 20 Zernike variances
    kl = KLBasis.from_turbulence(Pupil(64, diameter=1.0), 20, outer_scale=0.1,
                                 zernike_modes=range(2, 22))
    assert np.all(kl.variances > 0)
    assert kl.variances.sum() == pytest.approx(
        zernike_variance(range(2, 22), outer_scale=0.1, diameter=1.0).sum(), rel=1e-10)
