"""Science path: residual phase variance over the pupil for every field direction, Strehl.

The residual seen in direction ``theta`` is ``sum_p r_p(x + h_p theta)`` over the pupil,
``r_p`` the residual map (turbulence minus DMs) of plane ``p``. Its piston-removed
variance is computed for all directions at once by a numba kernel (the sub-pixel part
of a plane's shift is shared by the whole pupil because all planes have the pupil's
pitch, so one set of read weights serves a (direction, plane) pair; a plane whose shift
is the same in every direction, the ground plane, is read once for all directions, and
directions on one row of the field grid share the row sums of each plane they read at
the same rows: :func:`closedloop.optics._kernels.direction_moments_grouped`). The
Strehl ratio is the extended Marechal approximation ``exp(-sigma**2)`` at the science
wavelength (Ross 2009, Appl. Opt. 48, 1812); :func:`fft_strehl` computes the PSF peak by
FFT to check it.

Reading a plane between its pixels (:func:`read_weights`). A bilinear read at a
fraction ``t`` of a pixel multiplies the power at angular frequency ``w`` (rad per
pixel) by ``1 - 2 t (1 - t) (1 - cos w)`` per axis: it smooths the phase, and by an
amount that depends on ``t``, so anisoplanatism came out 4.6 % low at 2.5 pixels and
exact at whole pixels (issue 17). The read used here is that bilinear read of the plane
sharpened by ``1 + c (1 - cos w)``, ``c = K t (1 - t)``, a separable 4-tap filter per
axis (offsets -1..2). ``K = 1`` is Keys' cubic convolution (``a = -1/2``): its power
gain is 1 to second order in ``w`` at every ``t``, but it still loses 1-2 % of the
anisoplanatism of Kolmogorov phase (its power near the Nyquist frequency). ``K = 1.3``
over-sharpens the low frequencies slightly to balance that loss: computed from the
aliased Kolmogorov spectrum, the variance of a 2-3 pixel shift difference is then kept
within -0.9 / +0.6 % at every fraction in x and y (Keys: -1.8 / 0 %, bilinear: -5.4 /
0 %), tested against the exact piston-removed expectation in
``tests/closedloop/test_offaxis_reads.py``. The read is exact at whole pixels, keeps
the mean and reproduces linear phase (tilt) exactly. The WFS operators keep bilinear
reads: they average over subapertures and over their field.

When: :func:`closedloop.simulate` samples once per frame, at the frame's last internal
step, so a frame's Strehl is the instantaneous one at the frame's end, not an exposure
average over the frame's ``loop.oversampling`` internal steps. An exposure-averaged
Strehl (a camera adds intensities, so the mean of ``exp(-sigma_s**2)`` over the steps,
which by Jensen's inequality is at least the Marechal value of the frame-averaged
variance ``exp(-<sigma_s**2>)``) would cost one science pass per internal step. On
table1 (two steps per frame, the last one right after a command update) the end-of-frame
sampling reads the freshest correction: SR peak 0.3995 against 0.3968 for the mean of
``exp(-sigma_s**2)`` and 0.3964 for ``exp(-<sigma_s**2>)``, field mean 0.1823 against
0.1812 and 0.1811 (seed 1, 0.3 s, after closure;
measured with the bilinear read and the former SH window): +0.7 % and +0.6 %, relative.
"""

from __future__ import annotations

import numpy as np

from closedloop.optics import _kernels
from closedloop.optics.geometry import Geometry
from modalinfo.common.validation import as_float_array, check_int

__all__ = ["ScienceCamera", "fft_strehl", "marechal_strehl", "read_weights"]

#: ``K`` of :func:`read_weights` (1 would be Keys' cubic convolution)
READ_SHARPENING = 1.3

#: pixel-directions above which the science kernel runs on threads: table1's 81 x 3228
#: (0.26 M) take ~0.35 ms serially, and two threads were slower than one even idle
#: (0.40 ms), much slower on a loaded machine (a thread wake-up costs up to milliseconds)
_PARALLEL_WORK = 4_000_000


def read_weights(frac, sharpening: float = READ_SHARPENING) -> np.ndarray:
    """Weights of the sub-pixel read at offsets -1, 0, 1, 2 from ``floor(position)``.

    Parameters
    ----------
    frac : float or ndarray
        Fractional part ``t`` of the read position, in ``[0, 1)`` [pixels].
    sharpening : float
        ``K``: the bilinear weights ``(1 - t, t)`` convolved with ``(-c/2, 1 + c, -c/2)``,
        ``c = K t (1 - t)`` (see the module docstring).

    Returns
    -------
    ndarray
        ``frac.shape + (4,)``; they sum to 1, their first moment is ``t`` (linear phase
        read exactly), and at ``t = 0`` they are ``(0, 1, 0, 0)`` (a copy).
    """
    t = np.asarray(frac, dtype=np.float64)
    c = sharpening * t * (1.0 - t)
    a, b = 1.0 - t, t
    return np.stack([-0.5 * c * a, a * (1.0 + c) - 0.5 * c * b,
                     b * (1.0 + c) - 0.5 * c * a, -0.5 * c * b], axis=-1)


def marechal_strehl(variance) -> np.ndarray:
    """``exp(-variance)`` (variance in rad^2 at the science wavelength, ``>= 0``).

    The image's Strehl ratio only above ~0.3 (``closedloop.result.MARECHAL_MIN_SR``). A
    negative variance (an SR above 1) or NaN is refused.
    """
    # text is not a variance: '0.1' was parsed, 'abc' failed naming nothing (round 41 a)
    v = as_float_array(variance, "variance", finite=False)
    if not np.all(v >= 0.0):  # also NaN: exp(+1) = 2.7 was returned as a Strehl ratio
        raise ValueError(f"`variance` must be >= 0 rad^2 (a variance); got min "
                         f"{float(np.min(v)) if v.size else v!r}.")
    return np.exp(-v)


def fft_strehl(phase: np.ndarray, mask: np.ndarray, *, padding: int = 4) -> float:
    """Strehl ratio from the FFT PSF: peak of |FT(P e^{i phi})|^2 over the diffraction-limited peak.

    Parameters
    ----------
    phase : (N, N) ndarray
        Residual phase [rad at the science wavelength] (values outside ``mask`` ignored).
    mask : (N, N) bool
        Pupil.
    padding : int
        Zero padding factor of the FFT (the PSF sampled at lambda / (padding D)), >= 1.

    Returns
    -------
    float
        Maximum of the PSF (wherever it is: residual tilt moves it) over the peak of the
        unaberrated PSF, ``(sum P)**2``. The FFT samples the PSF at ``lambda / (padding
        D)``; the largest local maxima of the samples are refined off the grid (the PSF's
        Fourier sum at fractional frequencies, :func:`_refined_peak`), so a peak between
        samples is read at its top: a pure tilt half a sample off read 0.962 at
        ``padding=4`` and 0.520 at ``padding=1`` from the samples alone (adversarial
        round 44 PART a, S18, S47), 1 now.
    """
    padding = check_int(padding, "padding", minimum=1)
    phase = np.asarray(phase, dtype=np.float64)
    mask = np.asarray(mask)
    if phase.ndim != 2 or phase.shape[0] != phase.shape[1] or mask.shape != phase.shape:
        raise ValueError(f"`phase` and `mask` must be square (N, N) arrays of one shape; got "
                         f"{phase.shape} and {mask.shape}.")
    mask = mask.astype(bool)
    if not mask.any():  # 0 / 0: NaN was returned as a Strehl ratio
        raise ValueError("`mask` must hold at least one pupil pixel; got none.")
    if not np.all(np.isfinite(phase[mask])):
        raise ValueError("`phase` must be finite inside `mask`; it holds NaN or inf there.")
    n = phase.shape[0] * padding
    field = np.zeros((n, n), dtype=np.complex128)
    inside = np.exp(1j * np.where(mask, phase, 0.0))
    field[: phase.shape[0], : phase.shape[1]] = np.where(mask, inside, 0.0)
    psf = np.abs(np.fft.fft2(field)) ** 2
    peak = _refined_peak(np.where(mask, inside, 0.0), psf)
    return float(peak / mask.sum() ** 2)


#: local maxima of the sampled PSF refined off the grid by :func:`fft_strehl`
_PEAK_CANDIDATES = 4


def _refined_peak(pupil_field: np.ndarray, psf: np.ndarray) -> float:
    """Largest value of ``|sum E exp(-2 pi i (u x + v y))|**2`` near the sampled PSF's maxima.

    ``pupil_field`` ``(N, N)``: the complex pupil field ``E`` (0 outside the pupil);
    ``psf`` ``(n, n)``: its zero-padded FFT's squared modulus (samples at ``u, v = k /
    n`` cycles per pupil pixel). The :data:`_PEAK_CANDIDATES` largest local maxima of the
    samples (periodic 8-neighbourhood) are each refined within one sample by a bounded
    Nelder-Mead maximisation of the Fourier sum evaluated at fractional frequencies
    (separable: two length-N exponentials per evaluation); never below the samples'
    maximum.
    """
    from scipy import optimize

    n = psf.shape[0]
    k = np.arange(pupil_field.shape[0])
    neighbours = [np.roll(np.roll(psf, dy, 0), dx, 1)
                  for dy in (-1, 0, 1) for dx in (-1, 0, 1) if dy or dx]
    local = np.all([psf >= nb for nb in neighbours], axis=0)
    cand = np.flatnonzero(local.ravel())
    cand = cand[np.argsort(psf.ravel()[cand])[::-1][:_PEAK_CANDIDATES]]
    best = float(psf.max())

    def minus_psf(f: np.ndarray) -> float:
        eu = np.exp(-2j * np.pi * f[0] * k)  # along x (columns)
        ev = np.exp(-2j * np.pi * f[1] * k)  # along y (rows)
        return -float(np.abs(ev @ pupil_field @ eu) ** 2)

    for c in cand:
        ky, kx = divmod(int(c), n)
        start = np.array([kx / n, ky / n])
        res = optimize.minimize(minus_psf, start, method="Nelder-Mead",
                                bounds=[(start[0] - 1 / n, start[0] + 1 / n),
                                        (start[1] - 1 / n, start[1] + 1 / n)],
                                options={"xatol": 1e-5 / n, "fatol": 1e-10 * best,
                                         "initial_simplex": [start, start + [0.4 / n, 0],
                                                             start + [0, 0.4 / n]]})
        best = max(best, -float(res.fun))
    return best


def _row_spans(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Columns ``[lo, hi)`` of each row of a mask whose rows are single spans (int64)."""
    has = mask.any(axis=1)
    lo = np.where(has, np.argmax(mask, axis=1), 0)
    hi = np.where(has, mask.shape[1] - np.argmax(mask[:, ::-1], axis=1), 0)
    return lo.astype(np.int64), hi.astype(np.int64)


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
        # the kernel sums over one span of columns per row (a convex pupil). An obscured
        # pupil is the full disc minus the hole, both convex: the annulus's moments are
        # the disc's minus the hole's (:meth:`forward`), so its Strehl is that of the
        # annular pupil, as the FFT PSF of that pupil gives (test_obscured_pupil.py)
        disc, hole = geometry.disc_and_hole()
        self._span_lo, self._span_hi = _row_spans(disc)
        self._hole = None
        if hole.any():
            self._hole = _row_spans(hole)
            self._counts = (int(disc.sum()), int(hole.sum()))
        self._shifts = np.ascontiguousarray(geometry.pupil_shifts(self.directions))
        # read weights per (direction, plane, axis): (n_dir, P, 2, 4)
        self._taps = np.ascontiguousarray(read_weights(self._shifts - np.floor(self._shifts)))
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
        self._groups = None if self._parallel else self._row_groups(mask.shape[1])
        self.mean = np.zeros(len(self.directions))
        self.variance = np.zeros(len(self.directions))
        self._ones = np.ones(sizes.size)

    def _row_groups(self, n_cols: int):
        """Return the serial kernel's groups: (direction, plane) reads sharing a row sum.

        Directions that read a plane at the same whole row and with the same row weights
        (one row of the field grid) share the 4-row sum of every pupil row
        (:func:`closedloop.optics._kernels.direction_moments_grouped`; the same bits as
        the kernel without groups). Returns the kernel's group arrays, or None when no
        two directions share a group, or when one plane only depends on the direction:
        the kernel without groups fuses that plane's read with the moments, faster there
        (table1: 0.60 against 0.97 ms; ``est-mcao``'s six planes: 14.9 against 9.5 ms).
        """
        shifts, taps, common = self._shifts, self._taps, self._common
        n_dir, n_planes = shifts.shape[:2]
        if int(np.sum(~common)) < 2:
            return None
        group = -np.ones((n_dir, n_planes), dtype=np.int64)
        keys: dict = {}
        cols: list[list[int]] = []
        for p in range(n_planes):
            if common[p]:
                continue
            for d in range(n_dir):
                fc, fr = shifts[d, p]
                if fc == np.floor(fc) and fr == np.floor(fr):
                    continue  # a whole-pixel shift is read directly
                key = (p, int(np.floor(fr)), taps[d, p, 1].tobytes())
                g = keys.setdefault(key, len(keys))
                if g == len(cols):
                    cols.append([])
                cols[g].append(int(np.floor(fc)))
                group[d, p] = g
        if not any(len(c) > 1 for c in cols):
            return None
        spread = np.array([max(c) - min(c) for c in cols], dtype=np.int64)
        plane = np.array([k[0] for k in keys], dtype=np.int64)
        row = np.array([k[1] for k in keys], dtype=np.int64)
        first = [int(np.argmax(group[:, p] == g)) for g, p in enumerate(plane)]
        return (group, plane, row, np.array([min(c) for c in cols], dtype=np.int64), spread,
                np.ascontiguousarray([taps[d, p, 1] for d, p in zip(first, plane, strict=True)]),
                np.empty((len(cols), n_cols + 3 + int(spread.max()))))

    def _moments(self, span_lo, span_hi, w, mean, variance) -> None:
        """Run the moments kernel over the pupil spans ``[span_lo, span_hi)`` of each row."""
        args = (self._flat, self._offsets, self._sizes, span_lo, span_hi, self._shifts,
                self._taps, w, self._common, self._base)
        if self._parallel:
            _kernels.direction_moments(*args, mean, variance)
        elif self._groups is not None:
            _kernels.direction_moments_grouped(*args, *self._groups, mean, variance)
        else:
            _kernels.direction_moments_serial(*args, mean, variance)

    def plane_views(self) -> list[np.ndarray]:
        """Writable ``(n_p, n_p)`` views of the residual maps, one per plane, in one buffer."""
        return [self._flat[o:o + n * n].reshape(n, n)
                for o, n in zip(self._offsets, self._sizes, strict=True)]

    def reset(self) -> None:
        """Zero the plane maps and the last variances."""
        self._flat[:] = 0.0
        self.mean[:] = 0.0
        self.variance[:] = 0.0

    def looking_at(self, directions: np.ndarray) -> ScienceCamera:
        """Return a camera for other ``directions`` [arcsec] that reads this camera's maps.

        What the loop writes into :meth:`plane_views` is seen by both (the snapshots of
        :func:`closedloop.simulate` use this).
        """
        other = ScienceCamera(self.geometry, directions)
        other._flat = self._flat
        return other

    def forward(self, weights: np.ndarray | None = None) -> np.ndarray:
        """Piston-removed variance [rad^2 at the phase wavelength] per direction, ``(n_dir,)``.

        Reads the maps written into :meth:`plane_views`; ``weights`` (per plane) scales
        each plane (default all 1).
        """
        w = self._ones if weights is None else np.asarray(weights, float)
        self._moments(self._span_lo, self._span_hi, w, self.mean, self.variance)
        if self._hole is not None:
            # annulus = disc - hole: combine the moments about the disc's mean (stable
            # for any piston), the hole's from a second pass over its spans
            hole_mean, hole_var = np.empty_like(self.mean), np.empty_like(self.variance)
            self._moments(self._hole[0], self._hole[1], w, hole_mean, hole_var)
            n_disc, n_hole = self._counts
            n_ring = n_disc - n_hole
            d = hole_mean - self.mean
            m = -n_hole * d / n_ring
            var = (n_disc * self.variance - n_hole * (hole_var + d * d)) / n_ring - m * m
            self.mean += m
            self.variance[:] = np.maximum(var, 0.0)
        return self.variance

    def residual_phase(self, k: int) -> np.ndarray:
        """Return the residual phase over the pupil grid seen in direction ``k`` (NaN outside).

        A plain-numpy evaluation (the same reads of every plane), used for checks.
        """
        g = self.geometry
        n = g.n_pixels
        out = np.zeros((n, n))
        jj, ii = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
        for p, view in enumerate(self.plane_views()):
            fc, fr = self._shifts[k, p]
            ic, ir = int(np.floor(fc)), int(np.floor(fr))
            if fc == ic and fr == ir:
                out += view[ir + ii, ic + jj]
                continue
            wx, wy = self._taps[k, p]
            for a in range(4):
                for b in range(4):
                    out += wy[a] * wx[b] * view[ir + ii + a - 1, ic + jj + b - 1]
        return np.where(g.pupil_mask, out, np.nan)
