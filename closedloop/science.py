"""Science path: residual phase variance over the pupil for every field direction, Strehl.

The residual seen in direction ``theta`` is ``sum_p r_p(x + h_p theta)`` over the pupil,
``r_p`` the residual map (turbulence minus DMs) of plane ``p``. Its piston-removed
variance is computed for all directions at once by a numba kernel (four bilinear reads
per plane and pixel; the four weights are shared by the whole pupil because all planes
have the pupil's pitch; a plane whose shift is the same in every direction, the ground
plane, is read once for all directions). The Strehl ratio is the extended
Marechal approximation ``exp(-sigma**2)`` at the science wavelength (Ross 2009, Appl.
Opt. 48, 1812); :func:`fft_strehl` computes the PSF peak by FFT to check it.

When: :func:`closedloop.simulate` measures once per frame, at the frame's last internal
step, so a frame's Strehl is the instantaneous one at the frame's end, not an exposure
average over the frame's ``loop.oversampling`` internal steps. An exposure-averaged
Strehl (a camera adds intensities, so the mean of ``exp(-sigma_s**2)`` over the steps,
which by Jensen's inequality is at least the Marechal value of the frame-averaged
variance ``exp(-<sigma_s**2>)``) would cost one science pass per internal step. On
table1 (two steps per frame, the last one right after a command update) the end-of-frame
sampling reads the freshest correction: SR peak 0.3995 against 0.3968 for the mean of
``exp(-sigma_s**2)`` and 0.3964 for ``exp(-<sigma_s**2>)``, field mean 0.1823 against
0.1812 and 0.1811 (seed 1, 0.3 s, after closure): +0.7 % and +0.6 %, relative.
"""

from __future__ import annotations

import numpy as np

from closedloop import _kernels
from closedloop.geometry import Geometry

__all__ = ["ScienceCamera", "fft_strehl", "marechal_strehl"]

#: pixel-directions above which the science kernel runs on threads: table1's 81 x 3228
#: (0.26 M) take ~0.35 ms serially, and two threads were slower than one even idle
#: (0.40 ms), much slower on a loaded machine (a thread wake-up costs up to milliseconds)
_PARALLEL_WORK = 4_000_000


def marechal_strehl(variance) -> np.ndarray:
    """``exp(-variance)`` (variance in rad^2 at the science wavelength)."""
    return np.exp(-np.asarray(variance, dtype=np.float64))


def fft_strehl(phase: np.ndarray, mask: np.ndarray, *, padding: int = 4) -> float:
    """Strehl ratio from the FFT PSF: peak of |FT(P e^{i phi})|^2 over the diffraction-limited peak.

    Parameters
    ----------
    phase : (N, N) ndarray
        Residual phase [rad at the science wavelength] (values outside ``mask`` ignored).
    mask : (N, N) bool
        Pupil.
    padding : int
        Zero padding factor of the FFT (the PSF sampled at lambda / (padding D)).

    Returns
    -------
    float
        Maximum of the PSF (wherever it is: residual tilt moves it) over the peak of the
        unaberrated PSF, ``(sum P)**2``.
    """
    n = phase.shape[0] * padding
    field = np.zeros((n, n), dtype=np.complex128)
    inside = np.exp(1j * np.where(mask, phase, 0.0))
    field[: phase.shape[0], : phase.shape[1]] = np.where(mask, inside, 0.0)
    psf = np.abs(np.fft.fft2(field)) ** 2
    return float(psf.max() / mask.sum() ** 2)


class ScienceCamera:
    """Piston-removed residual variance in a set of directions.

    Parameters
    ----------
    geometry : Geometry
    directions : (n_dir, 2) ndarray
        Directions [arcsec].
    """

    def __init__(self, geometry: Geometry, directions: np.ndarray):
        self.geometry = geometry
        self.directions = np.ascontiguousarray(directions, dtype=np.float64).reshape(-1, 2)
        mask = geometry.pupil_mask
        if geometry.config.telescope.obscuration > 0:
            raise NotImplementedError("an obscured pupil's rows are not single spans")
        has = mask.any(axis=1)
        lo = np.where(has, np.argmax(mask, axis=1), 0)
        hi = np.where(has, mask.shape[1] - np.argmax(mask[:, ::-1], axis=1), 0)
        self._span_lo = lo.astype(np.int64)
        self._span_hi = hi.astype(np.int64)
        self._shifts = np.ascontiguousarray(geometry.pupil_shifts(self.directions))
        sizes = np.array([p.n for p in geometry.planes], dtype=np.int64)
        self._sizes = sizes
        self._offsets = np.concatenate([[0], np.cumsum(sizes ** 2)[:-1]]).astype(np.int64)
        self._flat = np.zeros(int((sizes ** 2).sum()))
        # planes seen at the same place from every direction (the ground): read once
        self._common = np.array([bool(np.all(self._shifts[:, p] == self._shifts[0, p]))
                                 for p in range(sizes.size)], dtype=np.bool_)
        self._base = np.zeros(mask.shape)
        # threads only for very many pixel-directions (see _PARALLEL_WORK)
        self._parallel = len(self.directions) * int(mask.sum()) >= _PARALLEL_WORK
        self.mean = np.zeros(len(self.directions))
        self.variance = np.zeros(len(self.directions))
        self._ones = np.ones(sizes.size)

    def plane_views(self) -> list[np.ndarray]:
        """Writable ``(n_p, n_p)`` views of the residual maps, one per plane, in one buffer."""
        return [self._flat[o:o + n * n].reshape(n, n)
                for o, n in zip(self._offsets, self._sizes, strict=True)]

    def measure(self, weights: np.ndarray | None = None) -> np.ndarray:
        """Piston-removed variance [rad^2 at the phase wavelength] per direction, ``(n_dir,)``.

        Reads the maps written into :meth:`plane_views`; ``weights`` (per plane) scales
        each plane (default all 1).
        """
        w = self._ones if weights is None else np.asarray(weights, float)
        kernel = (_kernels.direction_moments if self._parallel
                  else _kernels.direction_moments_serial)
        kernel(self._flat, self._offsets, self._sizes, self._span_lo, self._span_hi,
               self._shifts, w, self._common, self._base, self.mean, self.variance)
        return self.variance

    def residual_phase(self, k: int) -> np.ndarray:
        """Return the residual phase over the pupil grid seen in direction ``k`` (NaN outside).

        A plain-numpy evaluation (bilinear reads of every plane), used for checks.
        """
        g = self.geometry
        n = g.n_pixels
        out = np.zeros((n, n))
        jj, ii = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
        for p, view in enumerate(self.plane_views()):
            fc = self._shifts[k, p, 0] + jj
            fr = self._shifts[k, p, 1] + ii
            ic = np.floor(fc).astype(int)
            ir = np.floor(fr).astype(int)
            tc, tr = fc - ic, fr - ir
            out += ((1 - tr) * (1 - tc) * view[ir, ic] + (1 - tr) * tc * view[ir, ic + 1]
                    + tr * (1 - tc) * view[ir + 1, ic] + tr * tc * view[ir + 1, ic + 1])
        return np.where(g.pupil_mask, out, np.nan)
