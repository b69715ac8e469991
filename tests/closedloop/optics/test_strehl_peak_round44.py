"""fft_strehl reads the PSF's peak between its samples (adversarial round 44 PART a, S18, S47).

Reference: the Strehl ratio of a pure tilt is 1 (the PSF moves, its peak is the
unaberrated one; the docstring: "wherever it is"), and a numpy FFT zero-padded 8 times
by hand bounds the peak from below. Before the fix `fft_strehl` returned the largest FFT
sample: 0.962 for a tilt moving the PSF half a sample at padding 4, 0.520 at padding 1.
"""
import numpy as np
import pytest

from closedloop.optics.science import fft_strehl


def _disc(n=64):
    yy, xx = np.mgrid[:n, :n] - (n - 1) / 2
    return np.hypot(xx, yy) <= n / 2, xx, yy


@pytest.mark.parametrize("padding, shift", [(4, 0.5), (1, 0.5), (2, 0.37), (4, 3.0)])
def test_a_pure_tilt_has_strehl_one_wherever_the_peak_falls(padding, shift):
    mask, xx, yy = _disc()
    # moves the PSF `shift` samples of lambda / (padding D) along x and 0.3 shift along y
    phase = 2 * np.pi * shift * (xx + 0.3 * yy) / (64 * padding)
    assert fft_strehl(phase, mask, padding=padding) == pytest.approx(1.0, abs=1e-8)


def test_an_aberrated_peak_is_at_least_a_finer_grids_and_close_to_it():
    mask, xx, yy = _disc()
    rng = np.random.default_rng(3)
    phase = 0.4 * (rng.standard_normal() * (xx**2 + yy**2) / 32**2
                   + rng.standard_normal() * xx * yy / 32**2) + 2 * np.pi * 0.45 * xx / 256
    field = np.zeros((512, 512), complex)
    field[:64, :64] = np.where(mask, np.exp(1j * phase), 0)
    fine = (np.abs(np.fft.fft2(field)) ** 2).max() / mask.sum() ** 2
    s = fft_strehl(phase, mask)
    # the padding-8 grid is within (pi 0.5 / 8)^2 ~ 4 % of the peak for this PSF's width
    assert fine <= s + 1e-12
    assert s <= fine * 1.04
