"""The granulation scene's smoothing is a Gaussian of 0.07" sigma, as documented.

Reference: ``scipy.ndimage.gaussian_filter`` (periodic, ``mode="wrap"``) with
``sigma = 0.07" / pixel scale`` applied to the same scene with the smoothing switched
off (the module's ``_SMOOTH_ARCSEC`` set to 0 makes its Fourier filter exactly 1), both
normalised to mean 1 and the same rms contrast as the module documents. At 0.01"
pixels the sigma is 7 pixels: the sampled spatial kernel and the continuous Gaussian's
transfer function then agree to ~1e-9 (aliases at exp(-2 pi^2 sigma^2) ~ 1e-105,
truncation at 6 sigma ~ 2e-9), far below the tolerance; a smoothing of another width
(sigma 3.5 px, the transfer function exp(-pi^2 s^2 f^2 / 2)) differs by ~0.05 in these
normalised units.
"""

import numpy as np
import pytest
from scipy import ndimage

from closedloop.optics import granulation
from closedloop.optics.granulation import granulation_scene

PIXEL = 0.01     # [arcsec]
N_PIX = 256      # 2.56": two granules of 1.3" (rounded to 1.28")
CONTRAST = 0.1


def _normalised(img):
    return (img - img.mean()) / img.std()


def test_scene_is_the_unsmoothed_scene_through_a_gaussian_of_0_07_arcsec(monkeypatch):
    scene = granulation_scene(N_PIX, PIXEL, seed=3, contrast=CONTRAST)
    assert scene.mean() == pytest.approx(1.0, abs=1e-12)
    assert scene.std() == pytest.approx(CONTRAST, rel=1e-12)
    monkeypatch.setattr(granulation, "_SMOOTH_ARCSEC", 0.0)
    raw = granulation_scene(N_PIX, PIXEL, seed=3, contrast=CONTRAST)
    reference = ndimage.gaussian_filter(raw, sigma=0.07 / PIXEL, mode="wrap", truncate=6.0)
    diff = np.abs(_normalised(scene) - _normalised(reference)).max()
    assert diff < 1e-6, diff
    # the check can fail: the unsmoothed scene is far from the smoothed one
    assert np.abs(_normalised(scene) - _normalised(raw)).max() > 0.05
