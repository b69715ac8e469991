"""The Fisher-z interval of ``mutual_information_ci`` (issue 27, round 49 S01 / S04 / S05; fix50-a).

The Gaussian MI is ``I = -0.5 ln(1 - r^2) = ln cosh z`` with Fisher's ``z = atanh |r|``
(Cover & Thomas 2006, Example 8.5.1; Fisher 1921). The default interval of
``method="gaussian"`` (``interval="auto"`` -> ``"fisher"``) is ``z -+ z_0.975 s_z``, with
``s_z`` the bootstrap replicates' s.d. of z or, for the iid bootstrap at n <= 2000, the
delete-one jackknife s.d. of z where larger (Efron & Stein 1981), mapped back by
``ln cosh`` and clipped at 0.

References, from outside the package:
- the interval: numpy / scipy (``scipy.stats.rankdata``, ``scipy.special.ndtri``, numpy's
  Pearson correlation, ``np.arctanh``, ``np.log(np.cosh)``) on the same
  ``rng.integers(0, n, (B, n))`` draws, to 1e-12;
- the coverage: the exact MI of a bivariate normal pair, ``-0.5 ln(1 - rho^2)``, and the
  binomial s.e. ``sqrt(0.95 * 0.05 / seeds)`` of the nominal level.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats
from scipy.special import ndtri

from modalinfo.information import mutual_information_ci

Z975 = stats.norm.ppf(0.975)


def _pair(rho: float, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    e = np.random.default_rng(seed).standard_normal((n, 2))
    return e[:, 0], rho * e[:, 0] + math.sqrt(1.0 - rho * rho) * e[:, 1]


def _copula_r_rows(xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    """Pearson correlation of each row pair's normal scores Phi^-1(rank / (m + 1))."""
    m = xs.shape[-1]
    u = ndtri(stats.rankdata(xs, axis=-1) / (m + 1.0))
    v = ndtri(stats.rankdata(ys, axis=-1) / (m + 1.0))
    u = u - u.mean(-1, keepdims=True)
    v = v - v.mean(-1, keepdims=True)
    return (u * v).sum(-1) / np.sqrt((u * u).sum(-1) * (v * v).sum(-1))


def _numpy_fisher(x: np.ndarray, y: np.ndarray, b: int, seed: int,
                  level: float = 0.95) -> tuple[float, float, float]:
    """(estimate, low, high) in nats of the Fisher interval, numpy / scipy only."""
    n = x.shape[0]
    idx = np.random.default_rng(seed).integers(0, n, size=(b, n))
    r = abs(float(_copula_r_rows(x[None], y[None])[0]))
    rb = np.abs(_copula_r_rows(x[idx], y[idx]))
    keep = ~np.eye(n, dtype=bool)  # row i: every sample but i
    zj = np.arctanh(np.abs(np.array([_copula_r_rows(x[k][None], y[k][None])[0]
                                     for k in keep])))
    s_jack = math.sqrt((n - 1) / n * np.sum((zj - zj.mean()) ** 2))
    half = stats.norm.ppf(0.5 + level / 2.0) * max(np.std(np.arctanh(rb), ddof=1), s_jack)
    z_lo, z_hi = np.arctanh(r) - half, np.arctanh(r) + half
    low = 0.0 if z_lo <= 0.0 else float(np.log(np.cosh(z_lo)))
    return -0.5 * math.log(1.0 - r * r), low, float(np.log(np.cosh(z_hi)))


@pytest.mark.parametrize("rho, seed", [(0.6, 3), (0.9, 4), (0.0, 5)])
def test_default_gaussian_interval_is_the_numpy_fisher_interval(rho: float, seed: int) -> None:
    """Default interval of method="gaussian" = the numpy Fisher-z interval, 1e-12."""
    n, b = 200, 99
    x, y = _pair(rho, n, 1000 + seed)
    res = mutual_information_ci(x, y, method="gaussian", bootstrap="iid",
                                n_resamples=b, seed=seed)
    theta, low, high = _numpy_fisher(x, y, b, seed)
    assert res.interval == "fisher"
    assert res.estimate == pytest.approx(theta, abs=1e-12)
    assert (res.low, res.high) == pytest.approx((low, high), abs=1e-12)
    bits = mutual_information_ci(x, y, method="gaussian", units="bits", bootstrap="iid",
                                 n_resamples=b, seed=seed, interval="fisher",
                                 confidence_level=0.9)
    _, low9, high9 = _numpy_fisher(x, y, b, seed, level=0.9)
    ln2 = math.log(2.0)
    assert (bits.low, bits.high) == pytest.approx((low9 / ln2, high9 / ln2), abs=1e-12)


def test_fisher_is_refused_where_it_has_no_meaning() -> None:
    """interval="fisher" names the argument for a non-Gaussian method; "auto" -> normal."""
    x, y = _pair(0.6, 200, 11)
    with pytest.raises(ValueError, match="`interval`='fisher'.*method.*'histogram'"):
        mutual_information_ci(x, y, method="histogram", interval="fisher", n_resamples=19)
    res = mutual_information_ci(x, y, method="histogram", bootstrap="iid", n_resamples=19,
                                seed=0)
    assert res.interval == "normal"
    # "auto" takes Fisher where a second spread is taken: the jackknife's (iid, n <= 2000;
    # without it an independent pair's Fisher interval covered 0.928, fix50-a) or the
    # effective pairs' (block bootstrap, fix51-b)
    block = mutual_information_ci(x, y, method="gaussian", n_resamples=19, seed=0)
    x2, y2 = _pair(0.6, 2001, 12)
    big = mutual_information_ci(x2, y2, method="gaussian", bootstrap="iid", n_resamples=10,
                                seed=0)
    assert (block.interval, big.interval) == ("fisher", "normal")


def _coverage(rho: float, n: int, b: int, seeds: range) -> float:
    """Share of seeds whose default gaussian iid interval holds the exact MI."""
    exact = -0.5 * math.log(1.0 - rho * rho)  # nats, Cover & Thomas Example 8.5.1
    hits = 0
    for k in seeds:
        x, y = _pair(rho, n, 20000 + k)
        res = mutual_information_ci(x, y, method="gaussian", bootstrap="iid",
                                    n_resamples=b, seed=k)
        hits += res.low <= exact <= res.high
    return hits / len(seeds)


def test_coverage_n50_rho06() -> None:
    """300 seeds at n = 50: coverage >= 0.95 - 2 s.e. (0.925).

    The former "normal" interval covers 0.903 on these seeds (0.908 on 1,000, fix50-a's
    numpy copy), so this fails before; the Fisher interval covers 0.953 (0.951 on 1,000).
    False-failure rate at a true 0.95: 2.3 % for a fresh seed set; these seeds are fixed.
    """
    seeds = range(300, 600)
    cov = _coverage(0.6, 50, 99, seeds)
    se = math.sqrt(0.95 * 0.05 / len(seeds))
    assert cov >= 0.95 - 2.0 * se, (cov, se)


@pytest.mark.slow
def test_coverage_n200_rho06() -> None:
    """600 seeds at n = 200 (rho = 0.6, B = 199): coverage >= 0.95 - 2 s.e. (0.932).

    Over 2,000 seeds the numpy copy measured 0.9445 (Fisher) against 0.9295 ("normal",
    B = 999); false-failure rate at a true 0.945: ~9 % for a fresh seed set (fixed here).
    """
    seeds = range(600)
    cov = _coverage(0.6, 200, 199, seeds)
    se = math.sqrt(0.95 * 0.05 / len(seeds))
    assert cov >= 0.95 - 2.0 * se, (cov, se)
