"""Products past float64's range are refused, not returned as inf / NaN / lost digits.

Round 40 PART a, L06, L08, L11, L30, L31. References: numpy's float64 / float32 limits
(``numpy.finfo``: max 1.8e308 / 3.4e38, smallest normal 2.2e-308), numpy's biased
autocovariance ``np.correlate`` / n and ``numpy.linalg.eigvalsh`` of the mean-square
matrix on the same data at scale 1, multiplied by the exact scale squared.
Before: ``sample_autocovariance(x * 1e160)`` returned ``[inf, nan, nan]`` (numpy's
RuntimeWarnings only) and lost 1e-5 of its values at 1e-160 (subnormal products);
``KLBasis.from_data`` raised ``LinAlgError: Eigenvalues did not converge`` at 1e160 and
lost 2e-3 of its modes at 1e-160; ``ModalLog.to_units('nm')`` of a log of 1e307 rad
(float32: 1e37) returned a log of inf.
"""

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis
from modalinfo.forecast import sample_autocovariance
from modalinfo.telemetry import ModalLog


def _series(n=3000, seed=0):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n)
    x = np.empty(n)
    x[0] = e[0]
    for t in range(1, n):
        x[t] = 0.9 * x[t - 1] + e[t]
    return x


def _numpy_acv(x, k):
    d = x - x.mean()
    return np.array([np.dot(d[: d.size - j], d[j:]) / d.size for j in range(k + 1)])


@pytest.mark.parametrize("scale", [1e160, 1e-160])
def test_autocovariance_refuses_out_of_range(scale):
    with pytest.raises(ValueError, match="`x`"):
        sample_autocovariance(_series() * scale, 3)


@pytest.mark.parametrize("scale", [2.0**460, 2.0**-430])  # 3e138, 3e-130: exact scales
def test_autocovariance_within_range_is_numpy_times_scale_squared(scale):
    x = _series()
    got = sample_autocovariance(x * scale, 3) / scale**2
    np.testing.assert_allclose(got, _numpy_acv(x, 3), rtol=1e-12)


def _coeffs():
    rng = np.random.default_rng(5)
    c = rng.standard_normal((2000, 10)) * np.linspace(1.0, 0.2, 10)
    c[:, 1] += 0.5 * c[:, 0]
    return c


@pytest.mark.parametrize("scale", [1e160, 1e-160])
def test_data_kl_refuses_out_of_range(scale):
    zb = ZernikeBasis(Pupil(16), range(2, 12))
    with pytest.raises(ValueError, match="`coeffs`"):
        KLBasis.from_data(zb, _coeffs() * scale)


def test_data_kl_at_1e150_is_numpy_times_scale_squared():
    zb = ZernikeBasis(Pupil(16), range(2, 12))
    c = _coeffs()
    scale = 2.0**500  # 3.3e150, exact
    ref = np.sort(np.linalg.eigvalsh(c.T @ c / c.shape[0]))[::-1]
    got = KLBasis.from_data(zb, c * scale).variances / scale**2
    np.testing.assert_allclose(got, ref, rtol=1e-10)


@pytest.mark.parametrize("dtype, scale", [(np.float64, 1e307), (np.float32, 1e37)])
def test_to_units_refuses_an_overflowing_conversion(dtype, scale):
    c = (np.random.default_rng(0).standard_normal((50, 3)) * scale).astype(dtype)
    log = ModalLog(c, rate=1000.0, wavelength=5e-7)
    with pytest.raises(ValueError, match="`units`"):
        log.to_units("nm")


def test_to_units_within_range_is_the_product():
    c = (np.random.default_rng(0).standard_normal((50, 3)) * 1e35).astype(np.float32)
    got = np.asarray(ModalLog(c, rate=1000.0, wavelength=5e-7).to_units("nm").coeffs)
    factor = np.float32(5e-7 * 1e9 / (2 * np.pi))
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, c * factor, rtol=1e-6)
