"""Long-memory reading of the level rules, read against exact fGn (review37, issue 27).

References (outside the code under test):
- the exact autocovariance of fractional Gaussian noise (fGn),
  ``0.5 (|k + 1|^2H - 2 |k|^2H + |k - 1|^2H)`` (Mandelbrot & Van Ness 1968), its
  Toeplitz matrix (``scipy.linalg.toeplitz``) and the orthonormal DCT-II basis
  (``scipy.fft.dct``): the exact variances of a record's cosine terms, and of the
  difference of two segment means, as quadratic forms ``w' Gamma w``;
- the local Whittle estimate's standard error ``1 / (2 sqrt(m))`` (Robinson 1995,
  Ann. Statist. 23, 1630), of which ``long_memory`` adds ``MEMORY_MARGIN_SE`` = 2
  (docs/ADVERSARIAL.md, fix54-a).

The cosine terms given to ``long_memory`` are their exact fGn variances (no noise), so
its estimate must be the fGn's own ``d = H - 1/2`` to the grid's 0.01. No random draw.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.fft import dct
from scipy.linalg import toeplitz

from modalinfo._stats import long_memory, mean_difference_variance


def _fgn_acvf(n: int, hurst: float) -> np.ndarray:
    k = np.arange(n, dtype=float)
    return 0.5 * (np.abs(k + 1) ** (2 * hurst) - 2 * k ** (2 * hurst)
                  + np.abs(k - 1) ** (2 * hurst))


def _cosine_variances(n: int, hurst: float, terms: int) -> np.ndarray:
    """Exact variances of the orthonormal DCT-II terms j = 0 .. terms - 1 of fGn."""
    gamma = toeplitz(_fgn_acvf(n, hurst))
    basis = dct(np.eye(n), type=2, norm="ortho", axis=0)[:terms]
    return np.einsum("ij,jk,ik->i", basis, gamma, basis)


@pytest.mark.parametrize(("hurst", "before", "after"), [(0.7, 1500, 500), (0.9, 1000, 1000)])
def test_mean_difference_variance_against_another_records_first_term(hurst, before, after):
    # V measured on the whole record of before + after frames (not the first segment)
    n = before + after
    gamma = toeplitz(_fgn_acvf(n, hurst))
    w = np.r_[-np.ones(before) / before, np.ones(after) / after]
    first = dct(np.eye(n), type=2, norm="ortho", axis=0)[1]
    var_first = first @ gamma @ first
    law = var_first * mean_difference_variance(hurst - 0.5, before, after, record=n)
    np.testing.assert_allclose(law, w @ gamma @ w, rtol=2e-3)


@pytest.mark.parametrize(("hurst", "m"), [(0.7, 25), (0.6, 100)])
def test_long_memory_reads_fgns_d_and_adds_two_standard_errors(hurst, m):
    n = 2000
    power = _cosine_variances(n, hurst, m + 2)[1:]   # j = 1 .. m + 1, exact
    got = long_memory(power)
    assert got.terms == m
    assert got.estimate == pytest.approx(hurst - 0.5, abs=0.0101)
    margin = 2.0 * 0.5 / math.sqrt(m)            # two of Robinson's standard errors
    assert got.d == pytest.approx(got.estimate + margin, abs=0.0051)
    # the scale is L_1's variance under the d used: the exact terms over the exact
    # shares v_j / v_1 of fGn at H = 1/2 + d
    used = _cosine_variances(n, 0.5 + got.d, m + 2)[1:]
    want = float(np.mean(power[1:] / (used[1:] / used[0])))
    assert got.scale == pytest.approx(want, rel=5e-3)


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_the_memory_band_is_where_the_ar_spectrum_keeps_half_its_first_value(seed):
    # AR(1) 0.99 of 10,000 frames: its spectrum (1 - 2 phi cos l + phi^2)^-1 stays
    # within MEMORY_FLATNESS = 0.5 of f(pi / n) up to j = 32 (closed form below);
    # the fitted AR(p)'s band reads 31-37 on these seeds: a band x0.7-x1.4 of it
    from scipy.signal import lfilter

    from modalinfo._stats import _low_frequency

    n, phi = 10_000, 0.99
    rng = np.random.default_rng(seed)
    x = lfilter([1.0], [1.0, -phi], rng.standard_normal(n + 3000))[3000:]
    j = np.arange(1, 500)
    ratio = ((1 - 2 * phi * np.cos(np.pi / n) + phi ** 2)
             / (1 - 2 * phi * np.cos(np.pi * j / n) + phi ** 2))
    band = int(j[np.argmin(ratio >= 0.5)]) - 1           # last j within half
    got = _low_frequency(x[:, None])[0].memory.terms
    assert 0.7 * band <= got <= 1.4 * band
