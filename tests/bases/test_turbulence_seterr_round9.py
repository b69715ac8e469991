"""Von Karman quantities under np.seterr(all="raise") (round 9, rows se-*).

Reference: NumPy's error state changes how floating-point events are reported, never the
numbers. High-order Bessel functions at small arguments underflow to 0 in the von Karman
radial integrals; under ``np.seterr(all="raise")`` (a common debugging setting) that was a
FloatingPointError in ``zernike_covariance`` with an outer scale, ``KLBasis.from_turbulence``
and the synthetic KAOS-like logs. They must now give the same bits as under the default
error state.
"""

import numpy as np

from modalinfo.bases import zernike_covariance
from modalinfo.telemetry.synthetic import kaos_like


def test_same_bits_when_floating_point_events_raise():
    ref_cov = zernike_covariance(range(2, 30), outer_scale=20.0)
    ref_log = kaos_like(300, seed=0).coeffs
    old = np.seterr(all="raise")
    try:
        cov = zernike_covariance(range(2, 30), outer_scale=20.0)
        log = kaos_like(300, seed=0).coeffs
    finally:
        np.seterr(**old)
    assert np.array_equal(cov, ref_cov)
    assert np.array_equal(log, ref_log)
