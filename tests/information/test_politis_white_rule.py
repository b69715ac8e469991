"""Politis-White block length: the bandwidth rule's threshold, recomputed from the papers.

Reference: a second implementation written here from Politis & White (2004,
Econometric Rev. 23, 53, Sect. 3.2: ``m_hat`` the smallest m after which ``K_N =
max(5, log10 n)`` sample autocorrelations are all below ``c sqrt(log10 n / n)``, c = 2;
``M = 2 m_hat``; the flat-top window lambda(t) = 1 for |t| <= 1/2, 2 (1 - |t|) to 1)
and Patton, Politis & White (2009, Econometric Rev. 28, 372: ``b = (2 G^2 / D)^(1/3)
n^(1/3)``, ``D = (4/3) g(0)^2`` for the circular/moving block), with the sample
autocovariances from ``numpy.correlate`` (biased, over n). On these AR(1) series
(phi = 0.6, n = 1000) the threshold's logarithm decides ``m_hat``: with the natural
logarithm (1.5 times the threshold) ``m_hat`` and the length change (checked here, so
the comparison can fail for that slip). The AR(1) optimum test in
``test_resampling.py`` allows 6 % and cannot see it.
"""

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.information.resampling import politis_white_length


def _reference(x: np.ndarray, log=math.log10) -> tuple[float, int]:
    n = x.size
    e = x - x.mean()
    kn = max(5, int(math.log10(n)))
    m_max = min(int(math.ceil(math.sqrt(n))) + kn, n - 1)
    acv = np.correlate(e, e, mode="full")[n - 1 : n + m_max] / n
    rho = np.abs(acv / acv[0])
    c = 2.0 * math.sqrt(log(n) / n)
    m_hat = next(j for j in range(m_max - kn + 1) if np.all(rho[j + 1 : j + 1 + kn] < c))
    m = min(2 * max(m_hat, 1), m_max)
    k = np.arange(-m, m + 1)
    lam = np.where(np.abs(k / m) <= 0.5, 1.0, 2.0 * (1.0 - np.abs(k / m)))
    a = acv[np.abs(k)]
    g = np.sum(lam * np.abs(k) * a)
    g0 = np.sum(lam * a)
    b = (2.0 * g * g / (4.0 / 3.0 * g0 * g0)) ** (1.0 / 3.0) * n ** (1.0 / 3.0)
    return float(min(max(b, 1.0), math.ceil(min(3.0 * math.sqrt(n), n / 3.0)))), m_hat


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_length_follows_the_log10_threshold_of_the_papers(seed):
    x = lfilter([1.0], [1.0, -0.6], np.random.default_rng(seed).standard_normal(1000))
    want, m_hat = _reference(x)
    other, m_other = _reference(x, math.log)
    assert m_other != m_hat and abs(other - want) > 0.05 * want  # the case is decisive
    assert politis_white_length(x) == pytest.approx(want, rel=1e-9)
