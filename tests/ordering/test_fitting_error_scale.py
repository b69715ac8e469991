"""Fitting-error curves in bounded memory (issue 30, item 2).

References: the whole-array Parseval form ``_parseval`` (kept callable) and
``numpy.percentile`` along the frame axis, which the chunked computations must equal bit
for bit, over chunks made small enough that several blocks and a ragged last block are
used; the permuted basis with the permuted coefficients (an order is only a relabelling);
and the expectation of the Parseval curve for independent Gaussian coefficients of known
variances, ``E dPhi(n) = sum_{k > n} sigma_k^2``, within 5 standard errors
``sqrt(2 sum_{k > n} sigma_k^4 / T)``.
"""

import importlib

import numpy as np
import pytest

from modalinfo.ordering import fitting_error

fe = importlib.import_module("modalinfo.ordering.fitting_error")


def orthonormal_modes(n_pix, n_modes, seed=0):
    """A random basis orthonormal on the pixels: Q.T @ Q / n_pix = I."""
    q, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((n_pix, n_modes)))
    return q * np.sqrt(n_pix)


@pytest.mark.parametrize("n_modes", [1, 2, 37])
def test_chunked_parseval_equals_whole_array_bit_for_bit(monkeypatch, n_modes):
    monkeypatch.setattr(fe, "_CHUNK_ELEMENTS", 500)  # 13 frames per block at 37 modes
    a = np.random.default_rng(1).standard_normal((1001, n_modes)) * 3.0
    want, want_total = fe._parseval(a)
    got, got_total = fe._parseval_chunked(a)
    assert np.array_equal(got, want) and np.array_equal(got_total, want_total)


@pytest.mark.parametrize("levels", [(), (50.0,), (0.0, 5.0, 37.5, 95.0, 100.0)])
def test_chunked_bands_equal_numpy_percentile_bit_for_bit(monkeypatch, levels):
    monkeypatch.setattr(fe, "_CHUNK_ELEMENTS", 3000)  # 2 modes per block at 1,001 frames
    x = np.random.default_rng(2).gamma(2.0, size=(1001, 37))
    got = fe._bands(x, levels)
    want = np.percentile(x, levels, axis=0) if levels else np.empty((0, 37))
    assert got.shape == (len(levels), 37)
    assert np.array_equal(got, want)


@pytest.mark.parametrize("method", ["parseval", "gram"])
def test_order_is_a_relabelling(method):
    basis = orthonormal_modes(300, 40, seed=3)
    a = np.random.default_rng(4).standard_normal((500, 40))
    perm = np.random.default_rng(5).permutation(40)
    ordered = fitting_error(a, basis, perm, method=method, units="waves2")
    relabelled = fitting_error(a[:, perm], basis[:, perm], method=method, units="waves2")
    assert np.array_equal(ordered.per_frame, relabelled.per_frame)
    assert np.array_equal(ordered.bands, relabelled.bands)
    assert np.array_equal(ordered.total, relabelled.total)


def test_parseval_curve_matches_its_expectation_at_200_modes():
    n_modes, n_frames = 200, 10_000
    var = np.arange(1, n_modes + 1) ** (-11 / 6)  # Kolmogorov-like K-L variance decay
    a = np.random.default_rng(6).standard_normal((n_frames, n_modes)) * np.sqrt(var)
    result = fitting_error(a, orthonormal_modes(250, n_modes, seed=7))
    assert result.method == "parseval"
    tail = np.cumsum(var[::-1])[::-1]  # tail[j] = sum_{k >= j}
    expected = np.append(tail[1:], 0.0)
    stderr = np.sqrt(2 * np.append(np.cumsum(var[::-1] ** 2)[::-1][1:], 0.0) / n_frames)
    assert np.all(np.abs(result.mean - expected) <= 5 * stderr)
    assert result.mean_total == pytest.approx(tail[0], rel=5 * np.sqrt(2 * np.sum(var**2)
                                                                      / n_frames) / tail[0])
