"""Tests of closedloop.optics.phase_screen: the tilt tail's variance at any outer scale.

Reference: the von Karman phase PSD ``W(f) = 0.0229 r0^(-5/3) (f^2 + L0^-2)^(-11/6)``
(Roddier 1981) integrated here with SciPy's ``quad`` split at the knee ``f = 1/L0``
and at every decade above it (so the adaptive rule sees the knee at any scale), in
Cartesian-by-rows form, independently of the module's polar form; and the Kolmogorov
limit ``3 R^(1/3)`` of the radial integral.
Adversarial round 5, row k04: ``L0 = 1e9 m`` printed SciPy's IntegrationWarning and
``L0 = 1e6 m`` was 0.6-1.5 % off with no warning (the knee inside ``[0, R]`` was missed).
"""

import math
import warnings

import numpy as np
import pytest
from scipy import integrate

from closedloop.optics.phase_screen import _tail_gradient_variance
from modalinfo.bases.turbulence import KOLMOGOROV_PSD_CONSTANT


def _reference(h: float, r0: float, outer_scale: float) -> float:
    """4 pi^2 int int_{|fx|, |fy| < h} fx^2 W(f), rows in fy, split at every decade."""
    c = KOLMOGOROV_PSD_CONSTANT * r0 ** (-5 / 3)
    k0 = 1.0 / outer_scale
    splits = [float(k0 * 10.0**e) for e in range(20) if k0 * 10.0**e < h] or None

    def row(fy: float) -> float:
        value, _ = integrate.quad(lambda fx: fx * fx * c * (fx * fx + fy * fy + k0 * k0)
                                  ** (-11 / 6), 0.0, h, points=splits, limit=400,
                                  epsabs=0.0, epsrel=1e-11)
        return value

    value, _ = integrate.quad(row, 0.0, h, points=splits, limit=400, epsabs=0.0,
                              epsrel=1e-10)
    return 4 * math.pi**2 * 4 * value


@pytest.mark.parametrize("outer_scale", [1e9, 1e6, 1e3, 20.0])
@pytest.mark.parametrize("h", [0.01, 0.5, 10.0])
def test_the_tail_variance_matches_an_integration_split_at_the_knee(h, outer_scale):
    r0 = 0.1
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no IntegrationWarning reaches the user
        got = _tail_gradient_variance(h, r0, outer_scale)
    assert got == pytest.approx(_reference(h, r0, outer_scale), rel=1e-6)


def test_a_huge_outer_scale_tends_to_kolmogorov_from_below():
    h, r0 = 0.01, 0.1
    kolmogorov = _tail_gradient_variance(h, r0, np.inf)
    big = _tail_gradient_variance(h, r0, 1e9)
    # the radial integral loses ~3.6 c k0^(1/3) of 3 c R^(1/3): relative ~1.2 (k0 R)^(1/3),
    # 1/L0 = 1e-9 / m and R ~ 0.01 / m: ~5e-3
    assert 0.0 < (kolmogorov - big) / kolmogorov < 1e-2
