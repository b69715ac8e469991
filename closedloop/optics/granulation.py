"""Synthetic quiet-Sun granulation: the extended scene a solar Shack-Hartmann images.

The model is cellular, as granulation is: bright granules (upflows) separated by a
connected network of narrow dark intergranular lanes (downflows). Granule centres sit on
a jittered square lattice of pitch ``granule_scale_arcsec`` over a periodic field (a
lattice rather than Poisson points, because observed granules have a preferred size of
~1-1.5", where the spatial power spectrum of granulation peaks). Each pixel's intensity
is a lane profile ``1 - exp(-(d2 - d1) / w)``, where ``d1`` and ``d2`` are the distances
to the nearest and second-nearest centre (``d2 - d1`` is zero on the Voronoi edge: the
lane) and ``w`` the lane half-width (0.08 of the pitch), times a per-granule brightness
(uniform in [0.6, 1]) and a brightening towards the granule's centre; lanes narrower
than a pixel are integrated on a finer grid. The map is then smoothed by a Gaussian of
0.07" sigma (0.16" FWHM, so that it has no structure sharper than the lanes) and
scaled to the requested rms contrast around a mean of 1.

Contrast. The rms continuum contrast of granulation at full resolution is 14.4 % at
630 nm in MURaM radiative MHD simulations (Danilovic et al. 2008, A&A 484, L17; the
Hinode SP observed 7.0 %, the simulation degraded by Hinode's optics gives 7.5 %).
Temperature fluctuations ``dT/T`` map to intensity as ``(hc / lambda k T) dT/T`` in the
Wien limit, so the contrast scales as ``1 / lambda``; :func:`granulation_contrast`
uses that law anchored at Danilovic et al.'s value (it gives 18 % at 500 nm and 21 %
at 430 nm, the G-band; Wedemeyer-Boehm & Rouppe van der Voort 2009, A&A 503, 225,
compare simulated and Hinode contrasts at several wavelengths: the law is a first-order
stand-in for such a table, not a fit to it). This is the
*intrinsic* contrast; the WFS sees far less after its subaperture's diffraction
(``lambda / d`` ~ 0.4" for a 25 cm subaperture at 500 nm), which the image formation
applies.

Periodicity matters: subaperture fields are cut from the scene anywhere, and the
Fourier shift used by the tests must not meet an edge.
"""

from __future__ import annotations

import math
import numbers
import os

import numpy as np
from scipy.spatial import cKDTree

from modalinfo.common.memory import free_memory_bytes
from modalinfo.common.validation import as_scalar

__all__ = ["granulation_contrast", "granulation_scene", "load_scene", "GRANULE_SCALE_ARCSEC"]

#: default granule scale [arcsec]: the pitch of granule centres (~1 Mm on the Sun)
GRANULE_SCALE_ARCSEC = 1.3
#: anchor of the contrast law: rms contrast 14.4 % at 630 nm (Danilovic et al. 2008)
_CONTRAST_630 = 0.144
#: Gaussian smoothing of the cellular pattern [arcsec, sigma] (0.16" FWHM)
_SMOOTH_ARCSEC = 0.07
#: lane half-width as a fraction of the granule scale (lanes ~0.1-0.2 Mm wide)
_LANE_FRACTION = 0.08
#: peak working memory per supersampled pixel [bytes]: the query points, both
#: neighbours' distances and indices, and the lane/centre temporaries (measured with
#: tracemalloc: 80-129 bytes at 256-1024 pixels, 1-5x supersampled; rounded up)
_BYTES_PER_FINE_PIXEL = 160
#: lattice jitter as a fraction of the pitch (keeps granules distinct but irregular)
_JITTER = 0.35


def granulation_contrast(wavelength: float) -> float:
    """Return the rms continuum contrast of granulation at full resolution.

    ``0.144 * (630 nm / wavelength)``: Danilovic et al. (2008)'s MURaM value at 630 nm,
    scaled by the Wien law (contrast proportional to ``1 / lambda``).

    Parameters
    ----------
    wavelength : float
        Wavelength [m], in the visible (300-1100 nm).

    Returns
    -------
    float
        rms contrast (standard deviation over mean intensity), dimensionless.
    """
    wavelength = as_scalar(wavelength)  # a 0-d array is its number (left25-api)
    if isinstance(wavelength, bool) or not isinstance(wavelength, numbers.Real) \
            or not 300e-9 <= wavelength <= 1100e-9:  # np.float32 was refused (audit 9)
        raise ValueError(f"`wavelength` must be a number in [300e-9, 1100e-9] m; "
                         f"got {wavelength!r}.")
    return _CONTRAST_630 * 630e-9 / float(wavelength)


def _check_positive(name: str, value, *, integer: bool = False, minimum=None) -> None:
    kind = int if integer else (int, float)
    if isinstance(value, bool) or not isinstance(value, kind) or not math.isfinite(value):
        raise TypeError(f"`{name}` must be a finite {'int' if integer else 'number'}; "
                        f"got {value!r}.")
    if minimum is None and value <= 0:
        raise ValueError(f"`{name}` must be > 0; got {value!r}.")
    if minimum is not None and value < minimum:
        raise ValueError(f"`{name}` must be >= {minimum}; got {value!r}.")


def granulation_scene(n_pix: int, pixel_scale_arcsec: float, *, seed: int,
                      granule_scale_arcsec: float = GRANULE_SCALE_ARCSEC,
                      contrast: float | None = None,
                      wavelength: float = 500e-9) -> np.ndarray:
    """Return a seeded, periodic quiet-Sun intensity map, mean 1.

    Parameters
    ----------
    n_pix : int
        Pixels per side (the map is ``n_pix x n_pix``), >= 8.
    pixel_scale_arcsec : float
        Pixel size on the sky [arcsec].
    seed : int
        Seed of the granule lattice's jitter and brightnesses.
    granule_scale_arcsec : float
        Pitch of the granule centres [arcsec] (default 1.3"); the field must hold at
        least 2 granules across. The pitch is rounded so that a whole number of granules
        fits the field (the map is periodic).
    contrast : float, optional
        rms contrast (std / mean) of the map, in (0, 0.5]; default
        :func:`granulation_contrast` at ``wavelength``.
    wavelength : float
        Wavelength [m] for the default contrast.

    Returns
    -------
    (n_pix, n_pix) ndarray
        Intensity, mean 1, rms contrast ``contrast``, periodic along both axes
        (x along columns, y along rows).
    """
    _check_positive("n_pix", n_pix, integer=True, minimum=8)
    _check_positive("pixel_scale_arcsec", pixel_scale_arcsec)
    _check_positive("granule_scale_arcsec", granule_scale_arcsec)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"`seed` must be an int; got {seed!r}.")
    if contrast is None:
        contrast = granulation_contrast(wavelength)
    _check_positive("contrast", contrast)
    if contrast > 0.5:
        raise ValueError(f"`contrast` must be <= 0.5 (granulation is 5-25 %); got {contrast!r}.")
    box = n_pix * pixel_scale_arcsec
    n_cells = int(round(box / granule_scale_arcsec))
    if n_cells < 2:
        raise ValueError(f"the field ({box:g}\") must hold at least 2 granules of "
                         f"`granule_scale_arcsec` = {granule_scale_arcsec!r}; "
                         f"use more pixels or a smaller scale.")
    if granule_scale_arcsec < 2.0 * pixel_scale_arcsec:
        raise ValueError(f"`granule_scale_arcsec` = {granule_scale_arcsec!r} must span at "
                         f"least 2 pixels of {pixel_scale_arcsec!r}\".")
    pitch = box / n_cells
    # supersample by an integer factor so that lanes narrower than a pixel are integrated
    sub = min(max(1, int(math.ceil(pixel_scale_arcsec / (_LANE_FRACTION * pitch)))), 8)
    fine = n_pix * sub
    need = _BYTES_PER_FINE_PIXEL * fine ** 2
    free = free_memory_bytes()
    if need > free:
        raise ValueError(f"a {n_pix} x {n_pix} scene (supersampled {sub}x) needs about "
                         f"{need / 2**30:.1f} GiB and {free / 2**30:.1f} GiB is free; use "
                         "fewer pixels (`n_pix`).")
    rng = np.random.default_rng(seed)
    cy, cx = np.meshgrid(np.arange(n_cells), np.arange(n_cells), indexing="ij")
    centres = np.column_stack([cx.ravel(), cy.ravel()]) + 0.5
    centres = (centres + rng.uniform(-_JITTER, _JITTER, centres.shape)) * pitch
    centres %= box
    brightness = rng.uniform(0.6, 1.0, centres.shape[0])
    v = (np.arange(fine) + 0.5) * (box / fine)
    yy, xx = np.meshgrid(v, v, indexing="ij")
    tree = cKDTree(centres, boxsize=box)
    dist, idx = tree.query(np.column_stack([xx.ravel(), yy.ravel()]), k=2)
    lane = 1.0 - np.exp(-(dist[:, 1] - dist[:, 0]) / (_LANE_FRACTION * pitch))
    # granules are brightest at their centre and fade towards the lanes
    centre = 1.0 - 0.3 * (dist[:, 0] / (0.5 * pitch)) ** 2
    img = (brightness[idx[:, 0]] * lane * np.clip(centre, 0.0, None)).reshape(fine, fine)
    img = img.reshape(n_pix, sub, n_pix, sub).mean(axis=(1, 3))
    # periodic Gaussian smoothing in Fourier space (the simulations' resolution)
    f = np.fft.fftfreq(n_pix, d=pixel_scale_arcsec)
    gauss = np.exp(-2.0 * (math.pi * _SMOOTH_ARCSEC) ** 2 * (f[:, None] ** 2 + f[None, :] ** 2))
    img = np.fft.ifft2(np.fft.fft2(img) * gauss).real
    img -= img.mean()
    img *= contrast / img.std()
    img += 1.0
    return img


def load_scene(path: str | os.PathLike, *, contrast: float | None = None) -> np.ndarray:
    """Read a user's scene (``.npy``, or ``.fits``/``.fit``/``.fits.gz``, first image HDU).

    The image is used as it is sampled (its pixel scale is the caller's), normalised to
    mean 1; with ``contrast`` its fluctuations are rescaled to that rms contrast.
    Subaperture fields are cut from it with wrap-around, so a periodic image is best.

    Parameters
    ----------
    path : str or os.PathLike
        File to read.
    contrast : float, optional
        rms contrast to impose, in (0, 0.5].

    Returns
    -------
    (ny, nx) ndarray
        Intensity, mean 1.
    """
    name = os.fspath(path)
    lower = name.lower()
    if not os.path.isfile(name):
        raise ValueError(f"`path` must be an existing file; got {name!r}.")
    if lower.endswith(".npy"):
        img = np.load(name, allow_pickle=False)
    elif lower.endswith((".fits", ".fit", ".fits.gz", ".fts")):
        from astropy.io import fits

        with fits.open(name) as hdul:
            data = next((h.data for h in hdul if h.data is not None and h.data.ndim >= 2), None)
        if data is None:
            raise ValueError(f"`path` {name!r} holds no image HDU.")
        img = np.asarray(data)
    else:
        raise ValueError(f"`path` must end in .npy, .fits, .fit, .fts or .fits.gz; got {name!r}.")
    img = np.squeeze(np.asarray(img, dtype=np.float64))
    if img.ndim != 2:
        raise ValueError(f"the scene in {name!r} must be a 2-D image; got shape {img.shape}.")
    if min(img.shape) < 8:
        raise ValueError(f"the scene in {name!r} must be at least 8 x 8 pixels; got {img.shape}.")
    if not np.all(np.isfinite(img)):
        raise ValueError(f"the scene in {name!r} must be finite; it holds NaN or inf.")
    if img.min() < 0.0 or img.mean() <= 0.0:
        raise ValueError(f"the scene in {name!r} must be an intensity (>= 0, mean > 0); "
                         f"got min {img.min():g}, mean {img.mean():g}.")
    img = img / img.mean()
    if contrast is not None:
        _check_positive("contrast", contrast)
        if contrast > 0.5:
            raise ValueError(f"`contrast` must be <= 0.5; got {contrast!r}.")
        std = img.std()
        if std == 0.0:
            raise ValueError(f"the scene in {name!r} is constant: it has no contrast to rescale.")
        img = 1.0 + (img - 1.0) * (contrast / std)
    return img
