"""Image formation and measurement of a correlating (solar) Shack-Hartmann, standalone.

Each subaperture images the WFS's field of an extended scene (granulation). The field
(``field_pixels`` across, at ``pixel_scale_arcsec``) is split into ``n_patches x
n_patches`` sub-directions (isoplanatic patches, as SAOS and DASP do); a patch's light
crossed the atmosphere along its own direction, so it carries its own phase over the
subaperture. The subaperture image is

    I(x) = sum_d w_d(x) [S_blur * PSF_{d,s}](x),

where ``S_blur`` is the scene with the fixed blur applied once (the detector pixel's
MTF ``sinc(f p)`` and an optional Gaussian for the optics), ``PSF_{d,s}`` the diffraction
PSF of subaperture ``s`` with the phase of direction ``d`` (a matrix Fourier transform
of the square pupil, sampled ``k`` times finer than the detector's pixels so that it is
Nyquist sampled), ``*`` a cyclic convolution on the field plus a margin (the scene's
real FFT times the PSF's OTF at the same frequencies, a direct Fourier sum: the OTF of
a PSF point-sampled at 0.5" pixels is aliased and does not move with sub-pixel tilts),
and ``w_d`` smooth weights: a
product of ``cos^2`` ramps between neighbouring patch centres (a partition of unity, so
a uniform phase gives the single-patch image).

Detector: the image is scaled to the photon budget
(:class:`~closedloop.optics.photon_budget.PhotonBudget`), optional
fixed per-pixel gain and offset errors (flat-field and bias residuals) are applied, then
Poisson photon noise and Gaussian read noise are drawn from ``rng`` (above a mean of
1000 e- per pixel, the usual case, both as one Gaussian of variance ``mean + RON^2``).

Measurement: :func:`closedloop.optics.shifts.measure_shifts` of each subaperture image
against a reference: the stored noise-free image of an unaberrated subaperture, or (as
solar systems do) the image of one subaperture of the same frame, which makes the slopes
relative to that subaperture (the global tip-tilt then comes from a separate correlation
tracker). A shift ``s`` pixels is the wavefront tilt ``s * pixel_scale`` [rad on the sky]
and the phase gradient ``2 pi s pixel_scale / lambda`` [rad/m] at ``lambda`` (the geometric
SH of :mod:`closedloop.optics.wfs` reports gradients in rad/m of the phase at the loop's
``r0_wavelength``: multiply by ``wavelength / r0_wavelength``).

The photon budget is :mod:`closedloop.optics.photon_budget`; the sizes of the PSF, the
pupil oversampling and the convolution support are :mod:`closedloop.optics.image_sampling`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from closedloop.optics.image_sampling import (
    convolution_support,
    psf_subsampling,
    pupil_oversampling_needed,
)
from closedloop.optics.photon_budget import PhotonBudget
from closedloop.optics.shifts import measure_shifts
from modalinfo.common.validation import check_int, check_real

__all__ = ["CorrelatingMeasurement", "CorrelatingSubapertures"]

_ARCSEC = math.pi / (180.0 * 3600.0)
#: mean signal [e-] above which photon noise is drawn as a Gaussian (skewness < 3 %)
_GAUSSIAN_ABOVE = 1000.0


@dataclass(frozen=True)
class CorrelatingMeasurement:
    """One frame of the correlating SH.

    Attributes
    ----------
    images : (n_sub, N, N) ndarray
        Detector images [e-] (noise-free when no ``rng`` was given).
    shifts : (n_sub, 2) ndarray
        Measured shifts ``(x, y)`` [pixels] against the reference.
    slopes : (n_sub, 2) ndarray
        Wavefront gradients ``(x, y)`` [rad/m] of the phase at the WFS wavelength.
    at_edge : (n_sub,) ndarray of bool
        Shift at the edge of the search range (unreliable).
    mismatch : (n_sub,) ndarray of float
        Smallest over median of each difference surface (``ShiftResult.mismatch``): near
        0 for a true match, near 1 when no lag matches (a noisy dark frame, a shift well
        beyond ``max_shift`` read as a look-alike inside it).
    """

    images: np.ndarray
    shifts: np.ndarray
    slopes: np.ndarray
    at_edge: np.ndarray
    mismatch: np.ndarray | None = None


def _cos2_weights(n: int, n_patches: int) -> np.ndarray:
    """``(n_patches, n)`` 1-D blending weights: cos^2 ramps between patch centres, sum 1."""
    if n_patches == 1:
        return np.ones((1, n))
    spacing = n / n_patches
    centres = (np.arange(n_patches) + 0.5) * spacing - 0.5
    x = np.arange(n, dtype=np.float64)
    d = np.abs(x[None, :] - centres[:, None]) / spacing
    w = np.where(d < 1.0, np.cos(0.5 * np.pi * d) ** 2, 0.0)
    # beyond the outermost centres only one patch remains: it takes the whole weight
    w[0, x <= centres[0]] = 1.0
    w[-1, x >= centres[-1]] = 1.0
    return w / w.sum(axis=0, keepdims=True)


def _linear_upsampling(p: int, q: int) -> np.ndarray:
    """``(p q, p)`` linear interpolation from ``p`` pixel-centre samples to ``p q`` finer ones.

    Fine sample ``i`` sits at ``(i + 0.5) / q - 0.5`` coarse pixels; beyond the outer
    centres the end segments are extended (linear extrapolation), so a plane stays a plane.
    """
    pos = (np.arange(p * q) + 0.5) / q - 0.5
    i0 = np.clip(np.floor(pos).astype(np.int64), 0, p - 2)
    t = pos - i0
    out = np.zeros((p * q, p))
    out[np.arange(p * q), i0] = 1.0 - t
    out[np.arange(p * q), i0 + 1] += t
    return out


def _check_arguments(scene, pixel_scale_arcsec, subaperture_diameter, n_pupil, field_pixels,
                     n_patches, max_shift, blur_fwhm_arcsec, gain_rms, offset_rms) -> tuple:
    """Refuse what :class:`CorrelatingSubapertures` cannot image.

    Return the scene as float64 and the nine numbers as Python floats and ints, in order.
    """
    scene = np.asarray(scene, dtype=np.float64)
    if scene.ndim != 2 or not np.all(np.isfinite(scene)):
        raise ValueError(f"`scene` must be a finite 2-D array; got shape {scene.shape}.")
    # validation.check_real / check_int (the one copy): a 0-d array or NumPy scalar is its
    # number; bool, complex, str refused (TypeError); nan, inf and out-of-range values
    # refused (ValueError), each naming the argument
    pixel_scale_arcsec, subaperture_diameter = (
        check_real(v, name, minimum=0.0, strict_min=True)
        for name, v in (("pixel_scale_arcsec", pixel_scale_arcsec),
                        ("subaperture_diameter", subaperture_diameter)))
    n_pupil, field_pixels, n_patches, max_shift = (
        check_int(v, name, minimum=low)
        for name, v, low in (("n_pupil", n_pupil, 2), ("field_pixels", field_pixels, 8),
                             ("n_patches", n_patches, 1), ("max_shift", max_shift, 1)))
    if n_patches > field_pixels // 4:
        raise ValueError(f"`n_patches` must be <= field_pixels // 4 = {field_pixels // 4} "
                         f"(a patch needs a few pixels); got {n_patches}.")
    blur_fwhm_arcsec, gain_rms, offset_rms = (
        check_real(v, name, minimum=0.0)
        for name, v in (("blur_fwhm_arcsec", blur_fwhm_arcsec), ("gain_rms", gain_rms),
                        ("offset_rms", offset_rms)))
    return (scene, pixel_scale_arcsec, subaperture_diameter, n_pupil, field_pixels, n_patches,
            max_shift, blur_fwhm_arcsec, gain_rms, offset_rms)


class CorrelatingSubapertures:
    """The subaperture images and shift measurements of one correlating SH.

    Parameters
    ----------
    scene : (ny, nx) ndarray
        Intensity (mean ~1), sampled at ``pixel_scale_arcsec``; periodic (cut with wrap).
    pixel_scale_arcsec : float
        Detector pixel on the sky [arcsec]; also the scene's sampling.
    subaperture_diameter : float
        Side of the square subaperture [m].
    n_pupil : int
        Pupil samples across a subaperture (the phase's ``p``), >= 2.
    field_pixels : int
        Detector pixels across a subaperture image (its field of view), >= 8.
    n_patches : int
        Sub-directions across the field (``n_patches**2`` in all), >= 1.
    budget : PhotonBudget
        Photon budget and detector (its wavelength is the WFS's).
    field_centre : (2,) sequence of float
        Scene pixel ``(x, y)`` at the field's centre.
    blur_fwhm_arcsec : float
        Extra fixed Gaussian blur of the optics [arcsec FWHM] (0: pixel MTF only).
    gain_rms, offset_rms : float
        Fixed per-pixel gain errors (relative) and offset errors [e-] of each
        subaperture's pixels, drawn from ``detector_seed`` (:meth:`detector_maps`).
    detector_seed : int
    method, interpolation, max_shift, window, normalize
        Passed to :func:`closedloop.optics.shifts.measure_shifts` (``normalize``: divide
        each image by its mean first, against intensity differences between
        subapertures).
    pupil_oversampling : int, optional
        Fine pupil samples per phase sample for the PSF (linear interpolation of the
        phase); default the smallest for which the PSF does not alias within its support.

    Attributes
    ----------
    reference : (N, N) ndarray
        Stored noise-free image of a flat wavefront [e-], without detector errors (as a
        flat-fielded, dark-subtracted reference).
    weights : (n_dir, N, N) ndarray
        Blending weights of the sub-directions (sum 1 at every pixel).
    directions_arcsec : (n_dir, 2) ndarray
        Patch centres ``(x, y)`` relative to the field's centre [arcsec]; direction
        ``d = iy * n_patches + ix``.
    electrons_per_pixel : float
        Mean signal [e-] (the photon budget, capped at the well's fill level).
    attenuation : float
        Fraction of the Sun's photons kept to stay within the well (1: none needed).
    support, psf_pixels, margin : int
        Convolution size, PSF support and margin [pixels].
    psf_subsampling : int
        PSF samples per detector pixel (Nyquist sampling of the subaperture's PSF).
    pupil_oversampling : int
        Fine pupil samples per phase sample.
    """

    def __init__(self, scene: np.ndarray, pixel_scale_arcsec: float, subaperture_diameter: float,
                 n_pupil: int, field_pixels: int, *, n_patches: int = 1,
                 budget: PhotonBudget | None = None, field_centre=None,
                 blur_fwhm_arcsec: float = 0.0, gain_rms: float = 0.0, offset_rms: float = 0.0,
                 detector_seed: int = 0, method: str = "sdf",
                 interpolation: str = "2d-quadratic", max_shift: int = 3,
                 window: int | None = None, pupil_oversampling: int | None = None,
                 normalize: bool = False):
        # checked and converted by validation.check_real / check_int: Python floats and ints
        (scene, pixel_scale_arcsec, subaperture_diameter, n_pupil, field_pixels, n_patches,
         max_shift, blur_fwhm_arcsec, gain_rms, offset_rms) = _check_arguments(
            scene, pixel_scale_arcsec, subaperture_diameter, n_pupil, field_pixels, n_patches,
            max_shift, blur_fwhm_arcsec, gain_rms, offset_rms)
        self.budget = PhotonBudget() if budget is None else budget
        self.wavelength = self.budget.wavelength
        self.pixel_scale_arcsec = float(pixel_scale_arcsec)
        self.subaperture_diameter = float(subaperture_diameter)
        self.n_pupil = int(n_pupil)
        self.field_pixels = int(field_pixels)
        self.n_patches = int(n_patches)
        self.method = method
        self.interpolation = interpolation
        self.max_shift = int(max_shift)
        self.window = window
        self.normalize = normalize
        du = subaperture_diameter / n_pupil
        self._set_sampling(du, pupil_oversampling, scene.shape)
        self._patch = self._blurred_patch(scene, blur_fwhm_arcsec, field_centre)
        self._patch_ft = np.fft.rfft2(self._patch)
        self._set_patches(du)
        area = subaperture_diameter ** 2
        self.electrons_per_pixel = self.budget.electrons(area, self.pixel_scale_arcsec)
        self.attenuation = self.electrons_per_pixel / self.budget.unattenuated_electrons(
            area, self.pixel_scale_arcsec)
        self.gain_rms = float(gain_rms)
        self.offset_rms = float(offset_rms)
        self.detector_seed = detector_seed
        self._maps: dict[int, tuple] = {}
        flat = np.zeros((self.n_patches ** 2, 1, self.n_pupil, self.n_pupil))
        # the stored reference is an ideal (flat-fielded, dark-subtracted) image
        self.reference = self._form(self._check_phase(flat))[0]
        # the measurement's options are checked now, not at the first frame, on a ramp of
        # the reference's shape: a flat scene (detector tests) has a constant reference,
        # which measure_shifts refuses only when asked to measure against it
        ramp = np.indices(self.reference.shape).sum(axis=0).astype(np.float64)
        measure_shifts(ramp, ramp, method=method, interpolation=interpolation,
                       max_shift=max_shift, window=window, normalize=normalize)

    def _set_sampling(self, du: float, pupil_oversampling, scene_shape) -> None:
        """Set the PSF's support, the convolution's size and the pupil's oversampling."""
        subaperture_diameter, max_shift = self.subaperture_diameter, self.max_shift
        # the PSF's margin and the convolution's size (see convolution_support)
        self.margin, m = convolution_support(self.field_pixels, self.pixel_scale_arcsec,
                                             subaperture_diameter, self.wavelength, max_shift)
        mp = 2 * self.margin + 1
        self.psf_pixels = mp
        # a PSF from pupil samples du apart repeats every lambda / du on the sky: the phase
        # is interpolated linearly (exact for tilts) onto q x finer samples so that the
        # repeat lies beyond the PSF's support
        q_min = pupil_oversampling_needed(mp, self.pixel_scale_arcsec, du, self.wavelength)
        if pupil_oversampling is None:
            pupil_oversampling = q_min
        if not isinstance(pupil_oversampling, (int, np.integer)) or pupil_oversampling < q_min:
            raise ValueError(f"`pupil_oversampling` must be an int >= {q_min} (the PSF of "
                             f"pupil samples {du:.3g} m apart must not repeat within the "
                             f"{mp * self.pixel_scale_arcsec:.3g}\" PSF support); "
                             f"got {pupil_oversampling!r}.")
        self.pupil_oversampling = int(pupil_oversampling)
        self.support = m
        if min(scene_shape) < m:
            raise ValueError(f"`scene` must be at least {m} pixels across (field + margins); "
                             f"got {scene_shape}.")

    def _blurred_patch(self, scene: np.ndarray, blur_fwhm_arcsec: float,
                       field_centre) -> np.ndarray:
        """Return the scene blurred once (pixel MTF, optional Gaussian), cropped to the support."""
        m = self.support
        # the fixed blur, once: pixel MTF and the optional Gaussian
        fy = np.fft.fftfreq(scene.shape[0])
        fx = np.fft.fftfreq(scene.shape[1])
        mtf = np.outer(np.sinc(fy), np.sinc(fx))
        if blur_fwhm_arcsec > 0:
            fwhm_px = blur_fwhm_arcsec / self.pixel_scale_arcsec
            sig = fwhm_px / (2.0 * math.sqrt(2.0 * math.log(2.0)))
            mtf *= np.exp(-2.0 * (math.pi * sig) ** 2 * (fy[:, None] ** 2 + fx[None, :] ** 2))
        blurred = np.fft.ifft2(np.fft.fft2(scene) * mtf).real
        if field_centre is None:
            field_centre = (scene.shape[1] / 2.0, scene.shape[0] / 2.0)
        cx, cy = (int(round(float(v))) for v in field_centre)
        # patch index g + N // 2 (the cropped field's centre pixel) is the scene's (cx, cy)
        first = self.margin + self.field_pixels // 2
        rows = (cy - first + np.arange(m)) % scene.shape[0]
        cols = (cx - first + np.arange(m)) % scene.shape[1]
        return np.ascontiguousarray(blurred[np.ix_(rows, cols)])

    def _set_patches(self, du: float) -> None:
        """Set the PSFs' MFT, the sub-directions' blending weights and their directions."""
        mp, q = self.psf_pixels, self.pupil_oversampling
        # the PSF is sampled k times finer than the detector, so that it is Nyquist
        # sampled (lambda / d >= 2 samples): the detector's pixels undersample it (lambda/d
        # = 0.83 px for 25 cm at 500 nm and 0.5"), and the OTF of a point-sampled PSF is
        # aliased: a sub-pixel tilt then does not shift the image (measured: 0.15 and 0.3
        # px tilts gave -0.01 and 0.003 px)
        k = psf_subsampling(self.pixel_scale_arcsec, self.subaperture_diameter,
                            self.wavelength)
        self.psf_subsampling = k
        x = (np.arange(mp * k) - (mp * k) // 2) / k             # [detector pixels]
        # MFT matrix: A[k, j] = exp(-2 pi i alpha_k u_j / lambda), PSF centred at x = 0
        self._upsample = _linear_upsampling(self.n_pupil, q)
        u = (np.arange(self.n_pupil * q) - (self.n_pupil * q - 1) / 2.0) * (du / q)
        alpha = x * self.pixel_scale_arcsec * _ARCSEC
        self._mft = np.exp(-2j * math.pi * np.outer(alpha, u) / self.wavelength)
        # the PSF's OTF at the convolution's frequencies (cycles per detector pixel, up to
        # the detector's Nyquist: the scene, sampled at the pixels, has nothing beyond)
        m = self.support
        self._dft_y = np.exp(-2j * math.pi * np.outer(np.fft.fftfreq(m), x))
        self._dft_x = np.exp(-2j * math.pi * np.outer(np.fft.rfftfreq(m), x))
        w1 = _cos2_weights(self.field_pixels, self.n_patches)
        # (n_dir, N, N), direction d = iy * n_patches + ix (row-major, y along rows)
        self.weights = np.einsum("ay,bx->abyx", w1, w1).reshape(
            self.n_patches ** 2, self.field_pixels, self.field_pixels)
        spacing = self.field_pixels / self.n_patches * self.pixel_scale_arcsec
        v = ((np.arange(self.n_patches) + 0.5) * spacing
             - self.field_pixels * self.pixel_scale_arcsec / 2.0)
        yy, xx = np.meshgrid(v, v, indexing="ij")
        self.directions_arcsec = np.column_stack([xx.ravel(), yy.ravel()])

    # ------------------------------------------------------------------ image formation
    def psfs(self, phase: np.ndarray, amplitude: np.ndarray | None = None) -> np.ndarray:
        """PSFs, unit sum: ``(..., mp k, mp k)`` for phase ``(..., p, p)``.

        Sampled ``k = psf_subsampling`` times finer than the detector's pixels (Nyquist
        for the subaperture), over ``mp = psf_pixels`` pixels, centred at index
        ``(mp k) // 2``.

        Parameters
        ----------
        phase : (..., p, p) ndarray
            [rad] at the WFS wavelength, rows along y.
        amplitude : (..., p q, p q) ndarray, optional
            Pupil amplitude on the fine samples (``q = pupil_oversampling``), e.g. 0 where
            the subaperture is not illuminated (vignetted); default 1 everywhere. The PSF
            is normalised to unit sum either way (the flux of a vignetted subaperture is
            not lowered); a PSF with no light at all is zero.
        """
        fine = self._upsample @ np.asarray(phase, dtype=np.float64) @ self._upsample.T
        field_ = np.exp(1j * fine)
        if amplitude is not None:
            field_ = field_ * amplitude
        amp = self._mft @ field_ @ self._mft.T
        psf = amp.real ** 2 + amp.imag ** 2
        total = psf.sum(axis=(-2, -1), keepdims=True)
        # a direction that lights none of the subaperture (amplitude 0) leaves it dark
        return psf / np.where(total > 0, total, 1.0)

    def _check_phase(self, phase) -> np.ndarray:
        phase = np.asarray(phase, dtype=np.float64)
        want = (self.n_patches ** 2, self.n_pupil, self.n_pupil)
        if phase.ndim != 4 or (phase.shape[0],) + phase.shape[2:] != want:
            raise ValueError(f"`phase` must be (n_dir={want[0]}, n_sub, {self.n_pupil}, "
                             f"{self.n_pupil}); got {phase.shape}.")
        if not np.all(np.isfinite(phase)):
            raise ValueError("`phase` must be finite; it holds NaN or inf.")
        return phase

    def images(self, phase, rng: np.random.Generator | None = None,
               amplitude: np.ndarray | None = None) -> np.ndarray:
        """Detector images ``(n_sub, N, N)`` [e-] for the phases ``(n_dir, n_sub, p, p)``.

        Parameters
        ----------
        phase : (n_dir, n_sub, p, p) array_like
            Phase over each subaperture for each sub-direction [rad, WFS wavelength].
        rng : numpy.random.Generator, optional
            Draws the photon and read noise; none without it.
        amplitude : (n_dir, n_sub, p q, p q) ndarray, optional
            Pupil amplitude on the fine samples (see :meth:`psfs`); default 1.

        Notes
        -----
        Each PSF is computed over ``psf_pixels`` and normalised to unit sum there: a tilt
        that moves its core beyond ``max_shift + 1`` pixels, outside the sensor's search
        range, is not imaged faithfully.
        """
        phase = self._check_phase(phase)
        if amplitude is not None:
            fine = self.n_pupil * self.pupil_oversampling
            amplitude = np.asarray(amplitude, dtype=np.float64)
            if amplitude.shape != phase.shape[:2] + (fine, fine):
                raise ValueError(f"`amplitude` must have shape {phase.shape[:2] + (fine, fine)}"
                                 f"; got {amplitude.shape}.")
        img = self._form(phase, amplitude)
        gain, offset = self.detector_maps(img.shape[0])
        if gain is not None:
            img = img * gain
        if rng is not None:
            img = np.clip(img, 0.0, None)
            if self.electrons_per_pixel >= _GAUSSIAN_ABOVE:
                # photon and read noise as one Gaussian of variance mean + RON^2 (3x faster
                # than Poisson draws; the Poisson's skewness is < 3 % at these levels and
                # the shift noise depends on the variance only)
                img = img + np.sqrt(img + self.budget.read_noise ** 2) * rng.standard_normal(
                    img.shape)
            else:
                img = rng.poisson(img).astype(np.float64)
                if self.budget.read_noise > 0:
                    img += self.budget.read_noise * rng.standard_normal(img.shape)
        if offset is not None:
            img = img + offset
        return img

    def detector_maps(self, n_sub: int):
        """Return the fixed gain and offset maps ``(n_sub, N, N)`` (None if not configured).

        Each subaperture's image falls on its own pixels, so each has its own map; the
        maps are drawn from ``detector_seed`` (gains first, then offsets) and are the
        same at every frame.
        """
        if n_sub not in self._maps:
            det = np.random.default_rng(self.detector_seed)
            shape = (n_sub, self.field_pixels, self.field_pixels)
            gain = 1.0 + self.gain_rms * det.standard_normal(shape) if self.gain_rms > 0 else None
            offset = self.offset_rms * det.standard_normal(shape) if self.offset_rms > 0 else None
            self._maps[n_sub] = (gain, offset)
        return self._maps[n_sub]

    def displaced_references(self, shifts) -> np.ndarray:
        """Noise-free images ``(n, N, N)`` [e-] of a flat wavefront displaced by ``shifts``.

        ``shifts`` ``(n, 2)`` [detector pixels, ``(x, y)``]: the flat wavefront's OTF times
        the shift theorem's ramp ``exp(-2 i pi (kx sx + ky sy))``, i.e. the image of a
        Z-tilt of that many pixels without forming its PSF (used to tabulate the shift
        noise over sub-pixel shifts). ``shifts`` (0, 0) gives :attr:`reference`.
        """
        sh = np.atleast_2d(np.asarray(shifts, dtype=np.float64))
        if sh.ndim != 2 or sh.shape[1] != 2 or not np.all(np.isfinite(sh)) \
                or np.abs(sh).max(initial=0.0) > self.max_shift:
            raise ValueError(f"`shifts` must be finite (n, 2) pixels within +-{self.max_shift}"
                             f"; got shape {sh.shape}.")
        m, n, g = self.support, self.field_pixels, self.margin
        flat = np.zeros((self.n_patches ** 2, 1, self.n_pupil, self.n_pupil))
        otf = self._dft_y @ self.psfs(flat) @ self._dft_x.T           # (n_dir, 1, m, m//2+1)
        ky = np.fft.fftfreq(m)[None, :, None]
        kx = np.fft.rfftfreq(m)[None, None, :]
        ramp = np.exp(-2j * math.pi * (kx * sh[:, 0, None, None] + ky * sh[:, 1, None, None]))
        conv = np.fft.irfft2(otf * ramp[None] * self._patch_ft, s=(m, m))[..., g:g + n, g:g + n]
        img = np.einsum("dyx,dsyx->syx", self.weights, conv)
        img *= self.electrons_per_pixel
        return img

    def _form(self, phase: np.ndarray, amplitude: np.ndarray | None = None) -> np.ndarray:
        """Noise-free, error-free images [e-] of checked phases ``(n_dir, n_sub, p, p)``."""
        m, n, g = self.support, self.field_pixels, self.margin
        psf = self.psfs(phase, amplitude)                       # (n_dir, n_sub, mpk, mpk)
        # the OTF at the convolution's real-FFT frequencies, the PSF's centre at x = 0
        otf = self._dft_y @ psf @ self._dft_x.T                  # (n_dir, n_sub, m, m//2+1)
        conv = np.fft.irfft2(otf * self._patch_ft, s=(m, m))[..., g:g + n, g:g + n]
        img = np.einsum("dyx,dsyx->syx", self.weights, conv)
        img *= self.electrons_per_pixel
        return img

    def direction_weights(self) -> np.ndarray:
        """Weight of each sub-direction's tilt in the measured slope, to first order.

        Linearising the SDF of ``I = sum_d w_d r(x - s_d)`` about the reference ``r``
        gives ``s = sum_d c_d s_d / sum_d c_d`` with ``c_d = sum_window w_d (D r)^2``
        (``D`` the central difference along the slope's axis): the field's tilts
        averaged with the scene's local contrast as weights. A geometric sensor that
        averages its field samples with these weights reproduces this sensor's slopes
        to first order.

        Returns
        -------
        (n_dir, 2) ndarray
            Weights for the x and y slopes (each column sums to 1).
        """
        ref = self.reference
        n = self.field_pixels
        lag = self.max_shift + 1
        win = n - 2 * lag if self.window is None else self.window
        a = (n - win) // 2
        sl = slice(a, a + win)
        dx = (ref[sl, a + 1:a + win + 1] - ref[sl, a - 1:a + win - 1]) / 2.0
        dy = (ref[a + 1:a + win + 1, sl] - ref[a - 1:a + win - 1, sl]) / 2.0
        w = self.weights[:, sl, sl]
        c = np.column_stack([(w * dx ** 2).sum(axis=(1, 2)), (w * dy ** 2).sum(axis=(1, 2))])
        return c / c.sum(axis=0, keepdims=True)

    # ------------------------------------------------------------------ measurement
    def measure(self, phase, rng: np.random.Generator | None = None,
                reference: int | np.ndarray | None = None) -> CorrelatingMeasurement:
        """Form the images and measure their shifts and slopes.

        Parameters
        ----------
        phase : (n_dir, n_sub, p, p) array_like
            [rad] at the WFS wavelength.
        rng : numpy.random.Generator, optional
            Noise draws (noise-free without).
        reference : None, int or (N, N) ndarray
            None: the stored noise-free image of a flat wavefront; an int ``k``: the image of
            subaperture ``k`` of this frame (slopes relative to it); an array: that image.

        Returns
        -------
        CorrelatingMeasurement
        """
        imgs = self.images(phase, rng)
        if reference is None:
            ref = self.reference
        elif isinstance(reference, (int, np.integer)) and not isinstance(reference, bool):
            if not 0 <= reference < imgs.shape[0]:
                raise ValueError(f"`reference` must be a subaperture index in "
                                 f"[0, {imgs.shape[0] - 1}]; got {reference}.")
            ref = imgs[reference]
        else:
            ref = np.asarray(reference, dtype=np.float64)
            if ref.shape != imgs.shape[1:]:
                raise ValueError(f"`reference` must be an image of shape {imgs.shape[1:]}; "
                                 f"got {ref.shape}.")
        res = measure_shifts(ref, imgs, method=self.method, interpolation=self.interpolation,
                             max_shift=self.max_shift, window=self.window,
                             normalize=self.normalize)
        slopes = 2.0 * math.pi * res.shifts * self.pixel_scale_arcsec * _ARCSEC / self.wavelength
        return CorrelatingMeasurement(images=imgs, shifts=res.shifts, slopes=slopes,
                                      at_edge=res.at_edge, mismatch=res.mismatch)
