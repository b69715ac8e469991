"""Coverage of ``mutual_information_ci`` where stop 57 left it unmeasured (issue 27, fix51-b).

The Gaussian-method interval with the (default) moving-block bootstrap is the Fisher-z
interval ``z -+ z_0.975 s_z`` (``z = atanh|r|``, ``I = ln cosh z``) with ``s_z`` the larger
of the block replicates' s.d. of z and ``1 / sqrt(n_eff - 3)``, Bartlett's effective pairs
``n_eff = n (1 - rx ry) / (1 + rx ry)``, or, where fewer (long memory, round 52 PART a),
Bartlett's full sum ``n / (1 + 2 sum_{k <= n/10} (1 - k/n) rx(k) ry(k))`` of the biased
sample autocorrelations.

References, from outside the package:
- the exact MI of a pair of stationary AR(1) series of one coefficient phi whose
  innovations correlate rho (then ``(x_t, y_t)`` is bivariate normal with correlation
  rho): ``-0.5 ln(1 - rho^2)`` (Cover & Thomas 2006, Example 8.5.1); the binomial s.e.
  ``sqrt(0.95 * 0.05 / seeds)`` of the nominal level;
- the interval: numpy / scipy only (``scipy.stats.rankdata``, ``scipy.special.ndtri``, the
  lag-1 sample autocorrelation ``sum x_t x_(t+1) / sum x_t^2`` of the centred series with
  Kendall's (1954) bias correction ``r + (1 + 3 r) / n``, Bartlett's (1935) count),
  from the package's own replicates (its block indices are its own).
"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.special import ndtri

from modalinfo.information import mutual_information_ci

from ._ar_coverage import ar_pair as _ar_pair
from ._ar_coverage import ar_pair_coverage


def _lag1(a: np.ndarray) -> float:
    c = a - a.mean()
    r = float(np.dot(c[:-1], c[1:]) / np.dot(c, c))
    return min(r + (1.0 + 3.0 * r) / a.size, 1.0 - 1e-12)  # Kendall 1954


def _n_eff(x: np.ndarray, y: np.ndarray, cross: bool = False) -> float:
    """The fewer of Bartlett's lag-1 count and his full sum to lag n / 10 (numpy only).

    ``cross`` (the CMI intervals, fix54-c): times :func:`_cross_factor`, at most n.
    """
    n = x.shape[0]
    p = min(max(_lag1(x) * _lag1(y), 0.0), 1.0 - 1e-12)
    k_max = max(1, min(n - 1, n // 10))

    def acf(a: np.ndarray) -> np.ndarray:
        c = a - a.mean()
        return np.array([np.dot(c[:-k], c[k:]) for k in range(1, k_max + 1)]) / np.dot(c, c)

    total = 1.0 + 2.0 * float(np.sum((1.0 - np.arange(1, k_max + 1) / n) * acf(x) * acf(y)))
    full = n / total if total > 1.0 else float(n)
    count = min(n * (1.0 - p) / (1.0 + p), full)
    return min(count * _cross_factor(x, y), float(n)) if cross else count


def _cross_factor(x: np.ndarray, y: np.ndarray) -> float:
    """Bartlett's (1946) full variance of r over the product form's, held to [1, 2] (fix54-c).

    ``(1 - r^2)^2 S0 / S`` with ``S0 = sum_k w rxx ryy`` and ``S = sum_k w [rxx ryy +
    rxy(k) rxy(-k) - 2 r rxy(k) (rxx + ryy) + r^2 (rxx^2 / 2 + ryy^2 / 2 + rxy(k)^2)]``
    over |k| <= n / 10, ``w = 1 - |k| / n``, biased sample correlations by direct sums.
    """
    n = x.shape[0]
    k_max = max(1, min(n - 1, n // 10))
    a, b = x - x.mean(), y - y.mean()
    a, b = a / math.sqrt(np.dot(a, a) / n), b / math.sqrt(np.dot(b, b) / n)

    def corr(u: np.ndarray, v: np.ndarray, k: int) -> float:  # sum u_t v_(t+k) / n
        return float(np.dot(u[: n - k], v[k:]) if k >= 0 else np.dot(u[-k:], v[: n + k])) / n

    s0 = s = 0.0
    r = corr(a, b, 0)
    for k in range(-k_max, k_max + 1):
        w = 1.0 - abs(k) / n
        rxx, ryy = corr(a, a, abs(k)), corr(b, b, abs(k))
        rxy, ryx = corr(a, b, k), corr(a, b, -k)
        s0 += w * rxx * ryy
        s += w * (rxx * ryy + rxy * ryx - 2.0 * r * rxy * (rxx + ryy)
                  + r * r * (0.5 * rxx * rxx + 0.5 * ryy * ryy + rxy * rxy))
    if not (s > 0.0 and s0 > 0.0):
        return 1.0
    return min(max((1.0 - r * r) ** 2 * s0 / s, 1.0), 2.0)


def _numpy_block_fisher(x: np.ndarray, y: np.ndarray, replicates: np.ndarray
                        ) -> tuple[float, float, float]:
    """(estimate, low, high) in nats, numpy / scipy only, from the given replicates."""
    n = x.shape[0]
    u, v = ndtri(stats.rankdata(x) / (n + 1.0)), ndtri(stats.rankdata(y) / (n + 1.0))
    r = abs(float(np.corrcoef(u, v)[0, 1]))
    n_eff = _n_eff(x, y)
    s_boot = float(np.std(np.arctanh(np.sqrt(1.0 - np.exp(-2.0 * replicates))), ddof=1))
    s_z = max(s_boot, 1.0 / math.sqrt(max(n_eff - 3.0, 1.0)))
    half = stats.norm.ppf(0.975) * s_z
    z = math.atanh(r)
    low = 0.0 if z - half <= 0.0 else math.log(math.cosh(z - half))
    return -0.5 * math.log(1.0 - r * r), low, math.log(math.cosh(z + half))


@pytest.mark.parametrize("phi, rho, seed", [(0.9, 0.6, 1), (0.97, 0.0, 2), (0.5, 0.3, 3)])
def test_block_gaussian_default_is_the_bartlett_fisher_interval(phi: float, rho: float,
                                                               seed: int) -> None:
    """Default gaussian interval, block bootstrap = numpy's Fisher interval, 1e-12."""
    x, y = _ar_pair(phi, rho, 500, 52000 + seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # BlockBootstrapWarning below 50 effective pairs
        res = mutual_information_ci(x, y, method="gaussian", n_resamples=49, seed=seed)
    theta, low, high = _numpy_block_fisher(x, y, res.bootstrap_distribution)
    assert res.interval == "fisher"
    assert res.estimate == pytest.approx(theta, abs=1e-12)
    assert (res.low, res.high) == pytest.approx((low, high), abs=1e-12)


def test_block_coverage_ar09_n500() -> None:
    """AR(1) 0.9 pairs, n = 500 (~52 effective pairs), rho = 0.6: coverage >= 0.95 - 3 s.e.

    300 seeds (52000..52299, B = 99): 0.95 - 3 s.e. = 0.912. The former "normal"
    interval covered 0.880 on 500 other seeds (B = 199, fix51-b's numpy copy, equal to the
    package's to 1e-15) and 0.887 on these (fails before); the Bartlett-floored Fisher
    interval 0.956 and 0.953. False-failure rate at a true 0.95: 0.1 % for a fresh seed
    set; these seeds are fixed.
    """
    # BlockBootstrapWarning (~52 effective pairs) silenced by the helper
    cov, se = ar_pair_coverage(0.9, 0.6, 500, range(52000, 52300), method="gaussian",
                               n_resamples=99)
    assert cov >= 0.95 - 3.0 * se, (cov, se)


def _bartlett_mi_sd(x: np.ndarray, y: np.ndarray) -> float:
    """|r| / sqrt(n_eff - 3): the delta method on I = ln cosh z of Fisher's s.d. of z."""
    n = x.shape[0]
    u, v = ndtri(stats.rankdata(x) / (n + 1.0)), ndtri(stats.rankdata(y) / (n + 1.0))
    r = abs(float(np.corrcoef(u, v)[0, 1]))
    n_eff = _n_eff(x, y)
    return r / math.sqrt(max(n_eff - 3.0, 1.0))


@pytest.mark.parametrize("method, seed", [("histogram", 4), ("kde", 5), ("histogram", 6)])
def test_block_normal_interval_takes_bartletts_floor(method: str, seed: int) -> None:
    """Histogram / kde, block: half-width z_0.975 max(s_boot, |r| / sqrt(n_eff - 3))."""
    x, y = _ar_pair(0.97, 0.6, 500, 52000 + seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # BlockBootstrapWarning: ~16 effective pairs
        res = mutual_information_ci(x, y, method=method, n_resamples=49, seed=seed)
    half = stats.norm.ppf(0.975) * max(float(np.std(res.bootstrap_distribution, ddof=1)),
                                       _bartlett_mi_sd(x, y))
    assert res.interval == "normal"
    assert res.low == pytest.approx(res.estimate - half, abs=1e-12)
    if res.note:  # the histogram's grid-loss raise of the upper end (round 15 PART a)
        assert res.high > res.estimate + half
    else:
        assert res.high == pytest.approx(res.estimate + half, abs=1e-12)


def test_histogram_block_coverage_ar097_n500() -> None:
    """Histogram, AR(1) 0.97 pairs, n = 500 (~16 effective pairs), rho = 0.6.

    200 seeds (52000..52199, B = 99): coverage >= 0.95 - 3 s.e. = 0.904. Before the
    floor the block "normal" interval covered 0.81 on these (fails before; 0.82 over 150
    other seeds, B = 199); after 0.97 (0.96 over the 150; conservative: the floor is
    0.174 nats where the estimates' s.d. over seeds is 0.141). False-failure rate at a
    true 0.95: 0.1 %; these seeds are fixed.
    """
    # BlockBootstrapWarning (~16 effective pairs) silenced by the helper
    cov, se = ar_pair_coverage(0.97, 0.6, 500, range(52000, 52200), n_resamples=99)
    assert cov >= 0.95 - 3.0 * se, (cov, se)
