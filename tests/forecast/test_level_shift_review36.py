"""Mutation round 36 (review36): ``evaluate``'s train/test level rule (fix53-a).

Plants that escaped stop 60's tests (docs/MUTATION.md, "Round 36"): the test segment's
effective count not scaled to its length (all tests split at 0.5, where it is the
training one's), the rule run on test segments under ``MIN_SHIFT_INNOVATIONS`` frames or
on modes of fewer than ``MIN_SHIFT_EFFECTIVE`` effective training values, and the
long-memory count (``bartlett_sum_pairs``) dropped.

References (outside the code): AR(1) logs from ``scipy.signal.lfilter`` with the planted
shift set by numpy's means and sd to a chosen ``d``; the AR(1) effective count of a
mean, ``n (1 - phi) / (1 + phi)`` (analytic), and the normal quantile (scipy); a
fractional Gaussian noise (H 0.9) by the Davies-Harte circulant embedding (numpy FFT).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter
from scipy.stats import norm

from modalinfo.forecast import evaluate


def _ar1(seed: int, n: int, m: int, phi: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n + 5000, m)) * np.sqrt(1.0 - phi**2)
    return lfilter([1.0], [1.0, -phi], e, axis=0)[5000:]


def _set_shift(x: np.ndarray, n_train: int, d: float) -> np.ndarray:
    """Shift the test frames so that numpy's (mean_test - mean_train) / sd_train is d."""
    sd = x[:n_train].std(axis=0)
    now = (x[n_train:].mean(axis=0) - x[:n_train].mean(axis=0)) / sd
    x[n_train:] += (d - now) * sd
    return x


def test_the_test_segments_count_follows_its_length():
    # train = 0.9 of 20,000 AR(1) 0.99 frames: effective counts ~90 (training) and ~10
    # (test) -> the means' error 0.33 sd; a 0.6 sd shift is z ~ 1.8, under the 1 %
    # two-sided 2.58 (the test count taken as the training one's, 90: z ~ 4.0)
    n, phi, d = 20000, 0.99, 0.6
    x = _set_shift(_ar1(36, n, 1, phi), 18000, d)
    eff = lambda k: k * (1 - phi) / (1 + phi)  # noqa: E731
    z = d / np.sqrt(1 / eff(18000) + 1 / eff(2000))
    assert z < 0.8 * norm.isf(0.005)
    ev = evaluate({}, x, train=0.9, horizons=(1,))   # filterwarnings = error: silent
    np.testing.assert_allclose(ev.level_shift, [d], rtol=1e-9)
    assert ev.level_shifted_modes == ()


def test_a_test_segment_under_200_frames_is_not_judged():
    x = _set_shift(_ar1(37, 2150, 1, 0.5), 2000, 3.0)   # +3 sd over 150 test frames
    ev = evaluate({}, x, train=2000, horizons=(1,))
    assert np.isnan(ev.level_shift).all() and ev.level_shifted_modes == ()


def test_a_mode_of_under_10_effective_training_values_is_not_judged():
    # AR(1) 0.999 over 2,000 training frames: ~1 effective value of its mean
    x = _set_shift(_ar1(38, 4000, 1, 0.999), 2000, 3.0)
    ev = evaluate({}, x, train=0.5, horizons=(1,))
    assert np.isnan(ev.level_shift).all() and ev.level_shifted_modes == ()


def _fgn(n: int, hurst: float, rng: np.random.Generator) -> np.ndarray:
    k = np.arange(n + 1, dtype=float)
    g = 0.5 * (np.abs(k + 1) ** (2 * hurst) - 2 * k ** (2 * hurst)
               + np.abs(k - 1) ** (2 * hurst))
    c = np.concatenate([g, g[-2:0:-1]])
    lam = np.maximum(np.fft.fft(c).real, 0.0)
    w = rng.standard_normal(c.size) + 1j * rng.standard_normal(c.size)
    return np.fft.fft(np.sqrt(lam / c.size) * w).real[:n]


def test_long_memory_halves_differ_without_a_word():
    # a stationary fGn of H 0.9: the two halves' means differ by 0.53 sd here (0.29 sd rms
    # over seeds); its lag-1 count alone calls that ~5 standard errors. The seed is fixed:
    # the rule still names 2 of 24 such modes (seeds 0-11, docs/MUTATION.md round 36)
    rng = np.random.default_rng(1)
    x = np.stack([_fgn(20000, 0.9, rng) for _ in range(2)], axis=1)
    d = (x[10000:].mean(axis=0) - x[:10000].mean(axis=0)) / x[:10000].std(axis=0)
    assert abs(d[0]) > 0.5
    ev = evaluate({}, x, train=0.5, horizons=(1,))
    np.testing.assert_allclose(ev.level_shift, d, rtol=1e-9)
    assert ev.level_shifted_modes == ()


def test_a_mode_the_scale_rule_names_is_not_named_again_for_its_level():
    # the loop opens in the test frames: rms x10 and the mean 3 training sds off; the scale
    # rule names the mode, the level rule leaves it (its level follows from the new law)
    import warnings

    x = _ar1(39, 8000, 2, 0.9)
    sd = x[:4000, 0].std()
    x[4000:, 0] = x[4000:, 0] * 10.0 + 3.0 * sd
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        ev = evaluate({}, x, train=0.5, horizons=(1,))
    words = [str(w.message) for w in rec]
    assert ev.shifted_modes == (ev.labels[0],)
    assert ev.level_shifted_modes == ()
    assert not any("differ in level" in w for w in words)
    d = (x[4000:, 0].mean() - x[:4000, 0].mean()) / sd
    assert ev.level_shift[0] == pytest.approx(d, rel=1e-9)


def test_the_level_is_family_wise_over_the_modes():
    # 100 AR(1) 0.99 modes of 20,000 frames, mode 0's test frames 0.6 training sds up:
    # effective counts ~50 a segment, z ~ 3.0, beyond the 1 % two-sided 2.58 of one mode
    # but under the Bonferroni 3.48 of 100 (the seed's other modes all under 0.5 sd)
    n, phi, d = 20000, 0.99, 0.6
    x = _ar1(40, n, 100, phi)
    x[:, :1] = _set_shift(x[:, :1].copy(), n // 2, d)
    eff = (n // 2) * (1 - phi) / (1 + phi)
    z = d / np.sqrt(2.0 / eff)
    assert 1.1 * norm.isf(0.005) < z < 0.9 * norm.isf(0.005 / 100)
    ev = evaluate({}, x, train=0.5, horizons=(1,))   # filterwarnings = error: silent
    assert ev.level_shift[0] == pytest.approx(d, rel=1e-9)
    assert np.all(np.abs(ev.level_shift[1:]) < 0.5)
    assert ev.level_shifted_modes == ()
