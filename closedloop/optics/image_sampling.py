"""Sampling of a correlating Shack-Hartmann's subaperture image: PSF, pupil, convolution.

Three sizes, from the optics alone (no image formed), shared by the image formation
(:class:`closedloop.optics.correlating.CorrelatingSubapertures`), the loop's sensor
(:mod:`closedloop.optics.correlating_sensor`) and its resource estimate: the PSF's margin
and the convolution's support, the pupil oversampling that keeps the PSF from repeating
inside it, and the PSF samples per detector pixel that Nyquist sample it.
"""

from __future__ import annotations

import math

from scipy.fft import next_fast_len

__all__ = ["convolution_support", "pupil_oversampling_needed", "psf_subsampling"]

_ARCSEC = math.pi / (180.0 * 3600.0)


def convolution_support(field_pixels: int, pixel_scale_arcsec: float,
                        subaperture_diameter: float, wavelength: float,
                        max_shift: int) -> tuple[int, int]:
    """Return the PSF's margin and the convolution's size [pixels] of a subaperture image.

    The PSF is computed over +-(4 lambda/d + max_shift + 1) pixels (its core and first
    rings wherever a measurable tilt puts it; beyond ~4 lambda/d the sinc^2 wings of a
    square subaperture hold a few per cent of the light), then padded into the
    convolution support: the field plus that half-width on each side, rounded up to a
    size with small prime factors (134 = 2 x 67 is 4x slower to transform than 135). A
    scene must be at least the support across.

    Returns
    -------
    margin, support : int
    """
    lam_d = wavelength / subaperture_diameter / _ARCSEC / pixel_scale_arcsec
    margin = int(math.ceil(4.0 * lam_d)) + int(max_shift) + 1
    return margin, next_fast_len(int(field_pixels) + 2 * margin, real=True)


def pupil_oversampling_needed(psf_pixels: int, pixel_scale_arcsec: float, du: float,
                              wavelength: float) -> int:
    """Return the smallest pupil oversampling ``q`` whose PSF does not repeat in its support.

    A PSF from pupil samples ``du`` apart repeats every ``lambda / du`` on the sky; the
    phase is interpolated onto ``q`` times finer samples so that the repeat lies beyond
    ``psf_pixels`` detector pixels.
    """
    return max(1, math.ceil(psf_pixels * pixel_scale_arcsec * _ARCSEC * du / wavelength))


def psf_subsampling(pixel_scale_arcsec: float, subaperture_diameter: float,
                    wavelength: float) -> int:
    """Return the PSF samples per detector pixel that Nyquist sample it (``lambda/d >= 2``)."""
    return max(1, math.ceil(2.0 * pixel_scale_arcsec * _ARCSEC * subaperture_diameter
                            / wavelength))
