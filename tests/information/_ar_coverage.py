"""Stationary AR(1) series and the coverage count of ``mutual_information_ci`` over seeds.

One copy for the coverage tests of fix51-b and fix52-b (and review35's floor tests).
Reference: an AR(1) series ``e_t = phi e_(t-1) + sqrt(1 - phi^2) w_t`` started from its
stationary law N(0, 1) is N(0, 1) at every frame; two of them mixed as ``rho e1 +
sqrt(1 - rho^2) e2`` are a bivariate normal pair of correlation rho, exact MI
``-0.5 ln(1 - rho^2)`` (Cover & Thomas 2006, Example 8.5.1). The coverage's binomial s.e.
at the nominal level is ``sqrt(0.95 * 0.05 / seeds)``.

Also the iid Gaussian triples of the histogram CMI interval's tests (fix53-b, fix54-c,
review36) and their coverage count: x = 0.8 z + u, y = 0.6 z + v with (u, v) of partial
correlation ``rho_p = sqrt(1 - exp(-2 cmi))``, exact CMI ``-0.5 ln(1 - rho_p^2)`` = cmi
(Cover & Thomas 2006, eq. 8.56).
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from modalinfo.information import conditional_mutual_information_ci, mutual_information_ci


def ar1(phi: float, n: int, cols: int, rng: np.random.Generator) -> np.ndarray:
    """``cols`` independent stationary AR(1) series of coefficient phi, shape (n, cols)."""
    w = rng.standard_normal((n, cols)) * math.sqrt(1.0 - phi * phi)
    e = np.empty_like(w)
    e[0] = rng.standard_normal(cols)
    for t in range(1, n):
        e[t] = phi * e[t - 1] + w[t]
    return e


def ar_pair(phi: float, rho: float, n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Two stationary AR(1) series of coefficient phi, innovations correlated rho."""
    e = ar1(phi, n, 2, np.random.default_rng(seed))
    return e[:, 0], rho * e[:, 0] + math.sqrt(1.0 - rho * rho) * e[:, 1]


def ar_pair_coverage(phi: float, rho: float, n: int, seeds: range, **ci_options
                     ) -> tuple[float, float]:
    """(share of seeds whose interval covers the exact MI, its s.e. at 0.95).

    Seed k draws ``ar_pair(phi, rho, n, k)`` and calls ``mutual_information_ci(x, y,
    seed=k, **ci_options)``; warnings (BlockBootstrapWarning at few effective pairs)
    are silenced, as the tests count the intervals given.
    """
    exact = -0.5 * math.log(1.0 - rho * rho)
    hits = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for k in seeds:
            x, y = ar_pair(phi, rho, n, k)
            res = mutual_information_ci(x, y, seed=k, **ci_options)
            hits += res.low <= exact <= res.high
    return hits / len(seeds), math.sqrt(0.95 * 0.05 / len(seeds))


def iid_triple(n: int, cmi: float, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """iid x = 0.8 z + u, y = 0.6 z + v, (u, v) of partial correlation giving ``cmi``."""
    rng = np.random.default_rng(seed)
    rp = math.sqrt(1.0 - math.exp(-2.0 * cmi))
    e = rng.standard_normal((n, 3))
    u, v, z = e[:, 0], rp * e[:, 0] + math.sqrt(1.0 - rp * rp) * e[:, 1], e[:, 2:]
    return (0.8 * z[:, 0] + u)[:, None], (0.6 * z[:, 0] + v)[:, None], z


def histogram_cmi_coverage(n: int, cmi: float, first_seed: int, seeds: int,
                           n_resamples: int = 49) -> tuple[float, float]:
    """(share of seeds whose histogram CMI interval covers ``cmi``, its s.e. at 0.95).

    Seed k (0 ... seeds - 1) draws ``iid_triple(n, cmi, first_seed + k)`` and calls
    ``conditional_mutual_information_ci(x, y, z, method="histogram",
    n_resamples=n_resamples, seed=k)``; warnings (the finite-sample bias rule's) are
    silenced, as the tests count the intervals given.
    """
    hits = 0
    for s in range(seeds):
        x, y, z = iid_triple(n, cmi, first_seed + s)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = conditional_mutual_information_ci(x, y, z, method="histogram",
                                                    n_resamples=n_resamples, seed=s)
        hits += res.low <= cmi <= res.high
    return hits / seeds, math.sqrt(0.95 * 0.05 / seeds)
