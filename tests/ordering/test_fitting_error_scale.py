"""Fitting-error curves in bounded memory (issue 30, item 2).

References: the whole-array Parseval form ``_parseval`` (kept callable), numpy's
``sum``/``mean`` over frames and ``numpy.percentile`` along the frame axis, which the
one-pass kernel and the chunked bands must equal bit for bit (chunks made small enough
that several blocks and a ragged last block are used); the permuted basis with the
permuted coefficients (an order is only a relabelling); the expectation of the Parseval
curve for independent Gaussian coefficients of known variances, ``E dPhi(n) = sum_{k > n}
sigma_k^2``, within 5 standard errors ``sqrt(2 sum_{k > n} sigma_k^4 / T)``; and, for the
bands from a frame subsample, ``numpy.percentile`` of those frames (bit for bit) and the
binomial law of a sample quantile's rank (within 5 standard deviations
``sqrt(p (1 - p) / n)`` of the every-frame percentile).
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
def test_one_pass_parseval_equals_whole_array_bit_for_bit(n_modes):
    a = np.random.default_rng(1).standard_normal((1001, n_modes)) * 3.0
    want, want_total = fe._parseval(a)
    rows = np.array([0, 17, 1000])
    got, sums, got_total, picked = fe._parseval_pass(a, True, rows)
    assert np.array_equal(got, want) and np.array_equal(got_total, want_total)
    assert np.array_equal(sums, want.sum(axis=0)) and np.array_equal(picked, want[rows])
    none, sums2, total2, picked2 = fe._parseval_pass(a, False, rows)
    assert none is None
    assert np.array_equal(sums2, sums) and np.array_equal(total2, want_total)
    assert np.array_equal(picked2, picked)


def test_curves_not_kept_give_the_same_mean_and_subsampled_bands():
    a = np.random.default_rng(8).standard_normal((3001, 40)) * np.arange(40, 0, -1)
    basis = orthonormal_modes(60, 40, seed=9)
    kept = fitting_error(a, basis)
    assert kept.per_frame is not None and kept.band_frames is None
    light = fitting_error(a, basis, per_frame=False, band_frames=500)
    assert light.per_frame is None and light.band_frames == 500
    assert np.array_equal(light.mean, kept.mean) and np.array_equal(light.total, kept.total)
    rows = (np.arange(500) * 3001) // 500
    assert np.array_equal(light.bands, np.percentile(kept.per_frame[rows], kept.percentiles,
                                                     axis=0))
    assert light.n_frames == 3001 and light.n_modes[-1] == 40
    assert light.modes_to_reach(1.0) == kept.modes_to_reach(1.0)
    with pytest.raises(ValueError, match="per-frame curves of these 3001 frames were not kept"):
        light.curve(frame=3)
    # every frame asked for: exact bands without keeping the curves
    exact = fitting_error(a, basis, per_frame=False, band_frames=5000)
    assert exact.band_frames is None and np.array_equal(exact.bands, kept.bands)
    # waves^2: the kept path averages the T scaled curves, this one scales the average;
    # the two differ by the rounding of T scalings summed, at most T eps relative
    waves = fitting_error(a, basis, units="waves2", per_frame=False)
    kept_waves = fitting_error(a, basis, units="waves2")
    np.testing.assert_allclose(waves.mean, kept_waves.mean, rtol=3001 * np.finfo(float).eps)
    assert np.array_equal(waves.total, kept_waves.total)


def test_default_keeps_curves_below_the_limit_only(monkeypatch):
    a = np.random.default_rng(10).standard_normal((200, 6))
    basis = orthonormal_modes(30, 6, seed=11)
    assert fitting_error(a, basis).per_frame is not None
    monkeypatch.setattr(fe, "_KEEP_ELEMENTS", 1199)   # 200 x 6 = 1200 values
    monkeypatch.setattr(fe, "_BAND_FRAMES", 50)
    res = fitting_error(a, basis)
    assert res.per_frame is None and res.band_frames == 50
    assert fitting_error(a, basis, per_frame=True).per_frame.shape == (200, 6)
    with pytest.raises(TypeError, match="`per_frame` must be True, False or None"):
        fitting_error(a, basis, per_frame="yes")
    with pytest.raises(ValueError, match="`band_frames` must be"):
        fitting_error(a, basis, band_frames=0)


def test_subsampled_bands_within_the_sampling_error_of_a_quantile():
    n_frames, n_sub = 40_000, 2_000
    a = np.random.default_rng(12).standard_normal((n_frames, 5))
    basis = orthonormal_modes(20, 5, seed=13)
    full = fitting_error(a, basis, percentiles=(5.0, 50.0, 95.0))
    sub = fitting_error(a, basis, percentiles=(5.0, 50.0, 95.0), per_frame=False,
                        band_frames=n_sub)
    for i, p in enumerate(full.percentiles):
        sd = 100 * np.sqrt(p / 100 * (1 - p / 100) / n_sub)  # rank s.d., percentile points
        lo = np.percentile(full.per_frame, max(p - 5 * sd, 0), axis=0)
        hi = np.percentile(full.per_frame, min(p + 5 * sd, 100), axis=0)
        assert np.all((lo <= sub.bands[i]) & (sub.bands[i] <= hi)), p
        # and not trivially: the bands of another level are outside that range
        assert not np.allclose(sub.bands[i], full.bands[(i + 1) % 3])


def test_overflow_and_nan_are_named_after_the_deferred_checks():
    basis = orthonormal_modes(30, 3, seed=14)
    big = np.ones((4, 3))
    big[2, 1] = 1e160          # squares overflow float64
    with pytest.raises(ValueError, match="`coeffs_or_log`: column 1 reaches 1e\\+160"):
        fitting_error(big, basis)
    nan = np.ones((4, 3))
    nan[1, 2] = np.nan
    with pytest.raises(ValueError, match="`coeffs_or_log` must be finite"):
        fitting_error(nan, basis, method="gram")


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
    result = fitting_error(a, orthonormal_modes(250, n_modes, seed=7), per_frame=False)
    assert result.method == "parseval" and result.per_frame is None
    tail = np.cumsum(var[::-1])[::-1]  # tail[j] = sum_{k >= j}
    expected = np.append(tail[1:], 0.0)
    stderr = np.sqrt(2 * np.append(np.cumsum(var[::-1] ** 2)[::-1][1:], 0.0) / n_frames)
    assert np.all(np.abs(result.mean - expected) <= 5 * stderr)
    assert result.mean_total == pytest.approx(tail[0], rel=5 * np.sqrt(2 * np.sum(var**2)
                                                                      / n_frames) / tail[0])
