"""The correlating WFS's optional Gaussian blur has the FWHM it is given.

Reference: the definition of a Gaussian's FWHM, ``FWHM = 2 sqrt(2 ln 2) sigma``, and
``scipy.ndimage.gaussian_filter`` (an independent, spatial-domain Gaussian, periodic
``mode="wrap"`` as the module's Fourier blur). The image formation after the blur is
linear, so a sensor given ``blur_fwhm_arcsec = b`` on a scene must form the same
reference image as an unblurred sensor given the scene already filtered by scipy with
``sigma = b / (2 sqrt(2 ln 2))`` pixels. The residual is the sampled Gaussian's aliasing
(measured 1.1e-5 of the image's rms contrast at sigma = 1.27 px; tolerance 2e-3); a FWHM
read as ``2 sqrt(ln 2) sigma`` (the 1/e half-width) blurs sqrt(2) too wide and misses
by 1.13.
"""

import math

import numpy as np
from scipy.ndimage import gaussian_filter

from closedloop.optics.correlating import CorrelatingSubapertures
from closedloop.optics.granulation import granulation_scene

PS = 0.25          # arcsec / pixel
D_SUB = 0.25       # m
P = 16             # pupil samples across
FIELD = 24         # image pixels across
FWHM = 0.75        # arcsec: 3 pixels


def test_blur_fwhm_matches_scipy_gaussian_of_the_same_fwhm():
    scene = granulation_scene(128, PS, seed=3, wavelength=500e-9)
    centre = (64, 64)
    blurred = CorrelatingSubapertures(scene, PS, D_SUB, P, FIELD, field_centre=centre,
                                      blur_fwhm_arcsec=FWHM).reference
    sigma_px = FWHM / PS / (2.0 * math.sqrt(2.0 * math.log(2.0)))
    pre = gaussian_filter(scene, sigma_px, mode="wrap", truncate=8.0)
    expected = CorrelatingSubapertures(pre, PS, D_SUB, P, FIELD,
                                       field_centre=centre).reference
    contrast = float(np.std(expected))
    assert contrast > 0
    err = float(np.max(np.abs(blurred - expected))) / contrast
    assert err < 2e-3, err
