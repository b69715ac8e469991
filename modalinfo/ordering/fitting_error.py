"""Fitting-error curves of an ordered modal basis (the paper's Section 2, eq. 4).

With the reference wavefront ``Phi_ref = sum_{k=1..M} a_k Z_k`` (the full
reconstruction) and ``Phi_n`` the reconstruction with the first ``n`` modes of an
ordering, the fitting error is

    dPhi(n) = mean over the pupil of |Phi_n - Phi_ref|^2 = mean_p |sum_{k > n} a_k Z_k(p)|^2,

per frame and averaged over frames, in rad^2 or waves^2 (1 wave = 2 pi rad, so
waves^2 = rad^2 / (2 pi)^2 whatever the wavelength).

Three computations give the same numbers:

- ``"parseval"``: ``sum_{k > n} a_k^2`` -- exact when the basis is orthonormal on the
  pupil pixels (``gram() == I``);
- ``"gram"``: the quadratic form ``r^T G r`` of the dropped coefficients ``r`` with the
  Gram matrix ``G = Z^T Z / n_valid`` -- algebraically identical to the pixel sum for
  any basis, O(T M^2);
- ``"pixels"``: the residual wavefront summed on every pupil pixel (numba kernel),
  O(T M n_valid); the reference the other two are tested against.

``"auto"`` uses Parseval when ``gram()`` equals the identity to 1e-8 and the Gram
form otherwise.

At scale (issue 30: 3,000 modes x 10^5 frames is 2.4 GB of curves) the ``(T, M)``
per-frame curves are kept only up to ``2^25`` values (256 MB) unless asked for
(``per_frame=True``), and without them the percentile bands come from an evenly spaced
subsample of 20,000 frames (``band_frames``): a band at level ``p`` is then the
``p``-quantile of those frames, whose rank is off by ``sqrt(p (1 - p) / n)`` (standard
deviation for independent frames: 0.15 percentile points at 5 % and 95 %, 0.35 at the
median, for n = 20,000; time-correlated frames count as fewer). The frame-mean curve and
the totals always use every frame. At the paper's size (7,000 x 27) everything is kept
and exact, as before.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from modalinfo.common.chunked import matmul
from modalinfo.common.quiet import warn
from modalinfo.common.records import array_fields_eq
from modalinfo.common.validation import (
    SQUARE_FLOOR,
    as_float_array,
    check_choice,
    check_int,
    check_real,
    unmasked,
)
from modalinfo.ordering import _kernels as kern
from modalinfo.ordering._coefficients import (
    as_basis,
    check_represented,
    check_values,
    coefficients_in_basis,
)
from modalinfo.telemetry.units import unit_scale

__all__ = ["FittingErrorResult", "PupilSamplingWarning", "fitting_error", "check_order"]

_UNITS = ("rad2", "waves2")
_METHODS = ("auto", "parseval", "gram", "pixels")
_ORTHO_ATOL = 1e-8
_PERCENTILES = (5.0, 25.0, 50.0, 75.0, 95.0)
#: ``per_frame=None`` keeps the (T, M) per-frame curves up to this many values (256 MB)
_KEEP_ELEMENTS = 1 << 25
#: frames of the percentile bands when the per-frame curves are not kept (module notes)
_BAND_FRAMES = 20_000
#: Gram error (max |gram - I|) and relative curve difference (pixels vs Parseval) above
#: which a fitting error of continuous modes warns that it is the sampled pupil's
_SAMPLING_TOL = 1e-2
#: Exponent of the Gram error's fall with the grid size N: max |gram - I| of Noll Zernikes
#: 2..28 and 2..66 times N^1.5 stays within 13-34 from 32 to 384 pixels (fix33-a), so the
#: grid that brings it below ``_SAMPLING_TOL`` is about N (error / tol)^(1 / 1.5)
_GRAM_FALL = 1.5


class PupilSamplingWarning(UserWarning):
    """The fitting error of continuous modes is that of their samples on a coarse pupil.

    Issued by :func:`fitting_error` when the coefficients are of Zernike or K-L modes
    (continuous functions, a log's or a ``ZernikeBasis`` / ``KLBasis``'s), the
    basis sampled on the pupil pixels is not orthonormal (``max |gram - I| > 1e-2``) and the
    pixel answer differs from the sum of squares of the coefficients (Parseval, the
    continuous modes' answer) by more than 1 % somewhere on the curve.

    Attributes
    ----------
    n_pixels : int
        Pupil grid size across [pixels].
    gram_deviation : float
        ``max |gram - I|`` of the sampled basis.
    difference : float
        Largest relative difference pixels vs Parseval over the curve, signed.
    n_at : int
        The number of modes n where it is reached.
    suggested_pixels : int
        Grid size at which the Gram error is expected below 1e-2; 0 when the modes are
        not orthonormal on the continuous pupil itself (an obscured pupil), where no
        grid helps.
    pupil_deviation : float
        ``max |gram - I|`` of the continuous modes on the pupil's annulus (0 on a clear
        pupil). Above 1e-2 the difference is the pupil's, not the sampling's: the pixel
        curve is this pupil's fitting error and Parseval is not.
    """

    def __init__(self, message: str, *, n_pixels: int = 0, gram_deviation: float = 0.0,
                 difference: float = 0.0, n_at: int = 0, suggested_pixels: int = 0,
                 pupil_deviation: float = 0.0) -> None:
        super().__init__(message)
        self.pupil_deviation = pupil_deviation
        self.n_pixels = n_pixels
        self.gram_deviation = gram_deviation
        self.difference = difference
        self.n_at = n_at
        self.suggested_pixels = suggested_pixels


def check_order(order: Any, n_modes: int, name: str = "order",
                labels: Any = None, basis: Any = None) -> np.ndarray:
    """Validate a permutation of ``range(n_modes)``; return it as an int array.

    Parameters
    ----------
    order : array_like of int or None
        Indices into the basis (None: the standard order ``0..M-1``).
    n_modes : int
        Number of modes M.
    name : str
        Argument name for messages.
    labels : sequence of str, optional
        The basis's mode labels: an :class:`OrderingResult` is then matched by label
        (refused if the basis lacks its modes) instead of by index.
    basis : object, optional
        The basis itself: an :class:`OrderingResult` of another K-L basis (same labels,
        other variances) is refused.

    Returns
    -------
    numpy.ndarray, shape (M,), int64
    """
    if order is None:
        return np.arange(n_modes, dtype=np.int64)
    if hasattr(order, "order") and not isinstance(order, np.ndarray):  # an OrderingResult
        if basis is not None:
            from modalinfo.ordering.result import check_basis_key

            check_basis_key(order, basis, "basis")
        order = _result_order(order, labels, name)
    arr = np.asarray(unmasked(order, name))
    if arr.ndim != 1 or not (arr.dtype.kind in "iu" or arr.size == 0):  # not timedelta64
        raise TypeError(f"`{name}` must be a 1-D sequence of ints; got {arr!r}.")
    if arr.size != n_modes or not np.array_equal(np.sort(arr), np.arange(n_modes)):
        raise ValueError(
            f"`{name}` must be a permutation of 0..{n_modes - 1} (one index per basis mode); "
            f"got {arr.tolist()}."
        )
    return arr.astype(np.int64)


def _result_order(result: Any, labels: Any, name: str) -> np.ndarray:
    """Return the indices into a basis of labels ``labels`` of an OrderingResult's modes.

    The result's indices point into the basis it was computed on: applied to a basis
    holding the same modes in another order they named other modes (a curve of the wrong
    modes without a word: adversarial round 9, row fb-ordres-other-basis). Its modes are
    found by label; a basis without all of them is refused.
    """
    idx = np.asarray(result.order)
    own = tuple(getattr(result, "basis_labels", ()) or ())
    if labels is None or not own:
        return idx
    labels = tuple(str(s) for s in labels)
    if own == labels or labels == tuple(f"mode{k + 1}" for k in range(len(labels))):
        return idx  # the same basis, or a bare matrix (no labels to match): indices
    where = {s: k for k, s in enumerate(labels)}
    picked = [own[int(i)] for i in idx] if idx.size and idx.max() < len(own) else []
    missing = [s for s in picked if s not in where]
    if missing or len(own) != len(labels) or not picked:
        raise ValueError(
            f"`{name}` orders the {len(own)} modes of another basis ({list(own)[:5]}...); "
            f"this basis has {len(labels)} ({list(labels)[:5]}...)"
            + (f", without {missing[:3]}" if missing else "")
            + ": order the modes of this basis.")
    return np.array([where[s] for s in picked], dtype=np.int64)


@array_fields_eq
@dataclass(frozen=True)
class FittingErrorResult:
    """Fitting error dPhi(n), n = 1..M, of an ordered basis.

    Attributes
    ----------
    per_frame : numpy.ndarray, shape (T, M), or None
        ``per_frame[t, n - 1]`` = dPhi(n) of frame t [``units``]; None when not kept
        (see :func:`fitting_error`'s ``per_frame``).
    mean : numpy.ndarray, shape (M,)
        dPhi(n) averaged over frames [``units``].
    total : numpy.ndarray, shape (T,)
        dPhi(0) = mean over the pupil of Phi_ref^2 per frame (the total variance).
    percentiles : tuple of float
        Percentile levels of ``bands`` (per cent).
    bands : numpy.ndarray, shape (len(percentiles), M)
        Percentiles over frames of dPhi(n) (over ``band_frames`` evenly spaced frames).
    order : numpy.ndarray, shape (M,)
        Indices into the basis, in the order the modes were added.
    labels : tuple of str
        Labels of the modes in that order.
    units : str
        ``"rad2"`` or ``"waves2"``.
    method : str
        Computation used: ``"parseval"``, ``"gram"`` or ``"pixels"``.
    band_frames : int or None
        Number of frames the bands were computed from (None: every frame).
    gram_deviation : float
        ``max |gram - I|`` of the (ordered) basis on the pupil pixels (0: orthonormal).
    parseval_difference : float
        Largest relative difference ``(dPhi(n) - P(n)) / P(n)`` over n = 0..M-1 between
        the curve returned and the Parseval curve ``P(n)`` (the sum of the dropped
        coefficients' squares, the answer for continuous orthonormal modes), signed; 0
        when the method is ``"parseval"``.
    """

    per_frame: np.ndarray | None
    mean: np.ndarray
    total: np.ndarray
    percentiles: tuple[float, ...]
    bands: np.ndarray
    order: np.ndarray
    labels: tuple[str, ...]
    units: str
    method: str
    band_frames: int | None = None
    gram_deviation: float = 0.0
    parseval_difference: float = 0.0

    @property
    def n_frames(self) -> int:
        """Number of frames T."""
        return self.total.shape[0]

    @property
    def n_modes(self) -> np.ndarray:
        """The numbers of modes ``1..M`` the curve is given at."""
        return np.arange(1, self.mean.shape[0] + 1)

    @property
    def mean_total(self) -> float:
        """dPhi(0) averaged over frames (the mean total variance) [``units``]."""
        return float(self.total.mean())

    def curve(self, frame: int | None = None, *, include_zero: bool = False) -> np.ndarray:
        """dPhi(n) for n = 1..M (or 0..M), averaged or of one frame.

        Parameters
        ----------
        frame : int, optional
            Frame index (negative counts from the end); None for the frame average.
        include_zero : bool
            Prepend dPhi(0), the total variance.

        Returns
        -------
        numpy.ndarray, shape (M,) or (M + 1,)
        """
        if frame is None:
            values, zero = self.mean, self.mean_total
        else:
            t = self._frame(frame)
            if self.per_frame is None:
                raise ValueError(
                    f"`frame`: the per-frame curves of these {self.n_frames} frames were not "
                    "kept; call fitting_error(..., per_frame=True) to keep them."
                )
            values, zero = self.per_frame[t], float(self.total[t])
        return np.concatenate([[zero], values]) if include_zero else values.copy()

    def _frame(self, frame: int) -> int:
        t = check_int(frame, "frame", minimum=-self.n_frames, maximum=self.n_frames - 1)
        return t % self.n_frames

    def modes_to_reach(self, error: float, frame: int | None = None) -> int:
        """Smallest number of modes n (0..M) with dPhi(n) <= ``error``.

        Parameters
        ----------
        error : float
            Target fitting error [``units``], >= 0.
        frame : int, optional
            Use one frame's curve instead of the frame average.

        Returns
        -------
        int
            n in 0..M (0 when the total variance is already below the target; dPhi(M)
            is 0, so the target is always reached by n = M).

        Notes
        -----
        dPhi(n) is within its float error of the target counts as reaching it: the
        curve is a sum of up to M squares, exact to ~M eps dPhi(0), and two orders that
        drop the same modes give the same dPhi(n) only to that error, summed in another
        order (or on another CPU). A bare ``<=`` read "the error the standard order
        reaches with 20 modes" as reached by the a_k^2 order with the same 20 modes at
        20 or 21 depending on the CPU (round 39 CI, AMD EPYC against the golden run).
        """
        error = check_real(error, "error", minimum=0.0)
        values = self.curve(frame, include_zero=True)
        slack = values.size * np.finfo(np.float64).eps * abs(float(values[0]))
        hits = np.flatnonzero(values <= error + slack)
        return int(hits[0]) if hits.size else int(values.size - 1)

    def modes_to_reach_fraction(self, fraction: float, frame: int | None = None) -> int:
        """Smallest n with dPhi(n) <= ``fraction`` x dPhi(0) (a fraction of the total variance).

        Parameters
        ----------
        fraction : float
            Fraction of the total variance, in [0, 1].
        frame : int, optional
            Use one frame's curve instead of the frame average.

        Returns
        -------
        int
            n in 0..M.
        """
        fraction = check_real(fraction, "fraction", minimum=0.0, maximum=1.0)
        values = self.curve(frame, include_zero=True)
        return self.modes_to_reach(fraction * float(values[0]), frame)


# Frames per block of the chunked loops: ~8 MB of float64 at 1,000 modes, so the squares
# and their cumulative sums stay in cache-sized temporaries whatever T is.
_CHUNK_ELEMENTS = 1 << 20


def _parseval(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """dPhi(n) = sum of the squares of the dropped coefficients (orthonormal basis).

    The whole-array form (three ``(T, M)`` temporaries); :func:`_parseval_chunked` gives the
    same bits in bounded memory and is what :func:`fitting_error` uses.
    """
    sq = a * a
    rc = np.cumsum(sq[:, ::-1], axis=1)[:, ::-1]  # rc[t, j] = sum_{k >= j}
    out = np.zeros_like(a)
    out[:, :-1] = rc[:, 1:]
    return out, rc[:, 0].copy()


def _parseval_pass(a: np.ndarray, keep: bool, rows: np.ndarray
                   ) -> tuple[np.ndarray | None, np.ndarray, np.ndarray, np.ndarray]:
    """Parseval by the one-pass kernel: (per-frame curves or None, sums, totals, picked rows).

    The per-frame curves equal :func:`_parseval`'s bit for bit (the same sequential tail
    sums) and ``sums`` is ``per_frame.sum(axis=0)`` summed frame by frame; without
    ``keep`` only ``O(M)`` memory beyond the ``(len(rows), M)`` picked curves is used.
    """
    n_frames, n_modes = a.shape
    out = np.empty_like(a) if keep else np.empty((1, 1))
    sums = np.empty(n_modes)
    total = np.empty(n_frames)
    picked = np.empty((rows.size, n_modes))
    kern.parseval_pass(a, keep, out, sums, total, rows, picked)
    return (out if keep else None), sums, total, picked


def _bands(per_frame: np.ndarray, levels: tuple[float, ...]) -> np.ndarray:
    """``np.percentile(per_frame, levels, axis=0)`` by blocks of modes, frames contiguous.

    Percentiles are order statistics and a linear interpolation between two of them per
    column, so computing them column block by column block gives the same bits; each block
    is copied frames-contiguous first so the partial sorts run on contiguous lanes (1.3-1.4x
    less CPU than along the strided frame axis at 3,000 modes x 2e4 frames) and the
    partition's copy is one block, not the whole ``(T, M)`` array.
    """
    n_frames, n_modes = per_frame.shape
    if not levels:
        return np.empty((0, n_modes))
    out = np.empty((len(levels), n_modes))
    step = max(1, _CHUNK_ELEMENTS // max(n_frames, 1))
    for c0 in range(0, n_modes, step):
        lanes = np.ascontiguousarray(per_frame[:, c0:c0 + step].T)
        out[:, c0:c0 + step] = np.percentile(lanes, levels, axis=1)
    return out


def _gram(a: np.ndarray, gram: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """dPhi(n) = r^T G r for the dropped coefficients r, built from the back.

    With D(j) = sum_{i, k >= j} a_i a_k G_ik, D(j) = D(j + 1) + a_j^2 G_jj
    + 2 a_j sum_{k > j} G_jk a_k.
    """
    upper = np.triu(gram, 1)
    u = matmul(a, upper.T)  # u[t, j] = sum_{k > j} G_jk a_k; in chunks (Ctrl-C between)
    inc = a * a * np.diag(gram) + 2.0 * a * u
    rc = np.cumsum(inc[:, ::-1], axis=1)[:, ::-1]
    out = np.zeros_like(a)
    out[:, :-1] = rc[:, 1:]
    np.maximum(out, 0.0, out=out)  # rounding of a positive semi-definite form
    return out, np.maximum(rc[:, 0], 0.0)


def _pixels(a: np.ndarray, matrix: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Residual wavefront on every pupil pixel (numba kernel)."""
    out = np.empty_like(a)
    total = np.empty(a.shape[0])
    kern.pixel_fitting_error(a, np.ascontiguousarray(matrix.T), out, total)
    return out, total


def _band_rows(n_frames: int, band_frames: int | None, keep: bool) -> np.ndarray | None:
    """Frames of the bands: None for every frame, else ``n`` evenly spaced ones."""
    if band_frames is None:
        band_frames = n_frames if keep else _BAND_FRAMES
    else:
        band_frames = check_int(band_frames, "band_frames", minimum=1)
    if band_frames >= n_frames:
        return None
    return (np.arange(band_frames, dtype=np.int64) * n_frames) // band_frames


def _check_square_floor(a: np.ndarray, total: np.ndarray) -> None:
    """Refuse coefficients so small that every square underflows (dPhi would read 0).

    Only looked at when the total is tiny (one extra pass over ``a`` on such logs only):
    coefficients all below ``SQUARE_FLOOR`` in magnitude, not all zero, are refused. A
    zeroed log (all 0) keeps its exact fitting error of 0. Before round 26 PART b a log
    at 1e-300 rad printed "total variance dPhi(0) = 0 waves2" and a table of zeros.
    """
    if a.size == 0 or float(np.max(total)) >= SQUARE_FLOOR**2:
        return
    peak = float(np.max(np.abs(a)))
    if 0.0 < peak < SQUARE_FLOOR:
        raise ValueError(
            f"`coeffs_or_log`: its largest coefficient is {peak:.3g} rad, below "
            f"{SQUARE_FLOOR:.3g}, where the squares behind the fitting error underflow "
            "float64 (it would come out as 0); rescale the data (multiply it by a "
            "large factor) before this analysis."
        )


def _continuous_zernikes(obj: Any) -> np.ndarray | None:
    """Noll indices of the Zernikes behind the modes, when they are continuous; else None.

    A log's Zernike columns, a (not orthonormalised) ``ZernikeBasis`` and a K-L
    basis describe continuous modes; a bare matrix or another ``ModalBasis`` holds
    its own samples, whose pixel answer is the exact one.
    """
    if obj is None or getattr(obj, "orthonormalized", False):
        return None
    modes = getattr(obj, "zernike_modes", None)
    if modes is None:
        modes = getattr(obj, "modes", None)
    if modes is None or getattr(obj, "pupil", None) is None:
        return None
    return np.asarray(modes, dtype=np.int64)


def _finer_grid(obj: Any, pupil: Any, zmodes: np.ndarray, dev: float) -> tuple[int, bool]:
    """Pupil grid size across on which the basis's Gram error falls below ``_SAMPLING_TOL``.

    Above ``check_zernike_sampling``'s rule (Nyquist: 2 pixels per cycle of the highest
    radial order) and the current grid, from the N^-1.5 extrapolation up in 10 % steps,
    the same modes (the K-L's Zernike combination) are sampled on each grid and their
    Gram error measured (it is not monotone in N: the extrapolation alone named 216
    pixels for the K-L of Zernikes 2..28, where it is 0.0116). Returns (size, True) when
    found within 32 steps and a 64 MB matrix, else (the last size tried, False).
    """
    from modalinfo.bases.indexing import noll_to_zernike
    from modalinfo.bases.pupil import Pupil
    from modalinfo.bases.zernike import PIXELS_PER_CYCLE, zernike_matrix

    n_pix = int(pupil.n_pixels)
    order = int(np.max(noll_to_zernike(zmodes)[0]))
    size = max(PIXELS_PER_CYCLE * order, n_pix + 1,
               int(np.ceil(n_pix * (dev / _SAMPLING_TOL) ** (1.0 / _GRAM_FALL))))
    change = getattr(obj, "zernike_from_kl", None)
    for _ in range(32):
        if 0.8 * size * size * zmodes.size > 1 << 23:  # (n_valid, n_z) float64 > 64 MB
            return size, False
        grid = Pupil(size, diameter=pupil.diameter, obscuration=pupil.obscuration)
        z = zernike_matrix(zmodes, grid.rho_valid, grid.theta_valid)
        gram = z.T @ z / z.shape[0]
        if change is not None:
            c = np.asarray(change)
            gram = c.T @ gram @ c
        if float(np.max(np.abs(gram - np.eye(gram.shape[0])))) <= _SAMPLING_TOL:
            return size, True
        size = int(np.ceil(size * 1.1))
    return size, False


def _pupil_gram_error(obj: Any, pupil: Any, zmodes: np.ndarray) -> float:
    """``max |gram - I|`` of the continuous modes on the pupil's annulus (no sampling).

    The mean over the annulus ``obscuration <= rho <= 1`` of ``Z_i Z_j``, by quadrature
    exact for these polynomials: Gauss-Legendre in ``rho`` (weight ``rho``) with
    ``order + 2`` nodes and ``2 order + 2`` equally spaced azimuths. 0 on a clear pupil
    (Noll's Zernikes are orthonormal on the disc); 0.26 for Zernikes 2..28 at
    obscuration 0.3, which no grid removes (round 37 PART a, S1-S8).
    """
    from modalinfo.bases.indexing import noll_to_zernike
    from modalinfo.bases.zernike import zernike_matrix

    eps = float(pupil.obscuration)
    if eps <= 0.0:
        return 0.0
    order = int(np.max(noll_to_zernike(zmodes)[0]))
    x, w = np.polynomial.legendre.leggauss(order + 2)
    r = 0.5 * (1.0 - eps) * x + 0.5 * (1.0 + eps)
    wr = 0.5 * (1.0 - eps) * w * r
    n_t = 2 * order + 2
    t = 2.0 * np.pi * np.arange(n_t) / n_t
    rho, theta = np.repeat(r, n_t), np.tile(t, r.size)
    weight = np.repeat(wr, n_t) * (2.0 / (n_t * (1.0 - eps * eps)))
    z = zernike_matrix(zmodes, rho, theta)
    gram = z.T @ (z * weight[:, None])
    change = getattr(obj, "zernike_from_kl", None)
    if change is not None:
        c = np.asarray(change)
        gram = c.T @ gram @ c
    return float(np.max(np.abs(gram - np.eye(gram.shape[0]))))


def _sampling_check(curve: np.ndarray, zero: float, mean_square: np.ndarray,
                    dev: float, zmodes: np.ndarray | None, obj: Any,
                    method: str) -> float:
    """Relative difference pixels vs Parseval of the mean curve; warn when it matters.

    ``curve`` (M,) and ``zero`` are dPhi(1..M) and dPhi(0) as returned; ``mean_square``
    (M,) the frame-mean squares of the ordered coefficients in the same units.
    """
    par = np.cumsum(mean_square[::-1])[::-1]  # P(n) for n = 0..M-1
    got = np.concatenate([[zero], curve[:-1]])
    live = par > 0
    if not np.any(live):
        return 0.0
    pupil = getattr(obj, "pupil", None)
    rel = (got[live] - par[live]) / par[live]
    k = int(np.argmax(np.abs(rel)))
    worst = float(rel[k])
    if zmodes is None or dev <= _SAMPLING_TOL or abs(worst) <= _SAMPLING_TOL:
        return worst
    n_pix = int(pupil.n_pixels)
    n_at = int(np.flatnonzero(live)[k])
    first = float((got[0] - par[0]) / par[0]) if par[0] > 0 else 0.0
    own = _pupil_gram_error(obj, pupil, zmodes)
    if own > _SAMPLING_TOL:
        # the annulus's own share: converged, no grid removes it (round 37 PART a, S1-S8)
        warn(PupilSamplingWarning(
            f"fitting_error: the modes are not orthonormal on this pupil (obscuration "
            f"{float(pupil.obscuration):g}: max |gram - I| = {own:.2g} on the continuous "
            f"annulus, {dev:.2g} on its {n_pix} pixels), so method '{method}' gives this "
            f"pupil's fitting error, {100 * first:+.1f} % at dPhi(0) and {100 * worst:+.1f} % "
            f"at dPhi({n_at}) from the sum of the dropped coefficients' squares, which is "
            "not the fitting error on an obscured pupil; a finer grid does not change this "
            "(result.parseval_difference holds the difference).",
            n_pixels=n_pix, gram_deviation=dev, difference=worst, n_at=n_at,
            suggested_pixels=0, pupil_deviation=own), stacklevel=3)
        return worst
    need, found = _finer_grid(obj, pupil, zmodes, dev)
    warn(PupilSamplingWarning(
        f"fitting_error: the basis sampled on the {n_pix}-pixel pupil is not orthonormal "
        f"(max |gram - I| = {dev:.2g}), so method '{method}' gives the sampled pupil's "
        f"fitting error of these continuous modes: {100 * first:+.1f} % at dPhi(0) and "
        f"{100 * worst:+.1f} % at dPhi({n_at}) from the sum of the dropped coefficients' "
        f"squares (Parseval); the Gram error is below {_SAMPLING_TOL:g} "
        + (f"on {need} pixels" if found else f"above about {need} pixels (extrapolated)")
        + " (result.parseval_difference holds the difference).",
        n_pixels=n_pix, gram_deviation=dev, difference=worst, n_at=n_at,
        suggested_pixels=need, pupil_deviation=own), stacklevel=3)
    return worst


def fitting_error(
    coeffs_or_log: Any,
    basis: Any,
    order: Any = None,
    *,
    units: str = "rad2",
    wavelength: float | None = None,
    method: str = "auto",
    percentiles: tuple[float, ...] = _PERCENTILES,
    per_frame: bool | None = None,
    band_frames: int | None = None,
) -> FittingErrorResult:
    """Fitting error dPhi(n) of a basis truncated to the first n modes of an ordering.

    Parameters
    ----------
    coeffs_or_log : ModalLog or array_like, shape (T, M) or (M,)
        A log (converted to radians; matched to the basis by Noll index; changed to
        K-L coefficients for a K-L basis; a ``convention="labels"`` log matched to
        the basis's labels by name, a label the basis lacks refused) or coefficients
        of the basis's modes [rad].
    basis : ModalBasis or array_like, shape (n_valid, M)
        The basis (or its mode matrix on the valid pupil pixels).
    order : array_like of int, OrderingResult or None
        Permutation of the basis modes (None: the basis's column order 0..M-1, e.g.
        of a basis reordered by :meth:`OrderingResult.apply`; not re-sorted by Noll
        index: ``order_modes(..., "standard")`` gives that order). An
        :class:`OrderingResult` is matched to the basis by mode label.
    units : {"rad2", "waves2"}
        Units of the result (waves^2 = rad^2 / (2 pi)^2).
    wavelength : float, optional
        Wavelength [m] to convert a log in nm or um that carries none.
    method : {"auto", "parseval", "gram", "pixels"}
        How dPhi is computed (see the module docstring).
    percentiles : tuple of float
        Percentile levels (per cent) of the bands over frames.
    per_frame : bool, optional
        Keep the ``(T, M)`` per-frame curves in the result (needed for one frame's
        curve, ``curve(frame=...)``). Default: kept when ``T x M <= 2^25`` (256 MB).
        With Parseval, not keeping them also saves their memory while computing.
    band_frames : int, optional
        Compute the bands from this many evenly spaced frames (frame ``floor(i T / n)``,
        i = 0..n-1; all frames when ``n >= T``). Default: every frame when the
        per-frame curves are kept, 20,000 frames otherwise (the sampling error is in
        the module notes). The mean curve and the totals always use every frame.

    Returns
    -------
    FittingErrorResult

    Raises
    ------
    ValueError
        On a shape mismatch, an order that is not a permutation, unknown units or
        method, ``method="parseval"`` on a basis that is not orthonormal, non-finite
        coefficients or sums of squares that overflow, coefficients (not all zero) so
        small that every square underflows; or a log with (non-zero) modes
        the basis does not represent, or a K-L basis keeping fewer modes than the
        Zernikes it combines (their variance would be missing from every dPhi(n)).
    """
    check_choice(units, "units", _UNITS)
    check_choice(method, "method", _METHODS)
    if per_frame is not None and not isinstance(per_frame, bool | np.bool_):
        raise TypeError(f"`per_frame` must be True, False or None; got {per_frame!r}.")
    view = as_basis(basis)
    # an array's finiteness and overflow checks are two passes over it: deferred to the
    # sums formed below (finite sums <=> finite values without overflow)
    a = coefficients_in_basis(coeffs_or_log, view, wavelength=wavelength, name="coeffs_or_log",
                              defer_value_checks=True)
    check_represented(coeffs_or_log, view)
    idx = check_order(order, view.n_modes, labels=view.labels, basis=view.obj)
    levels = tuple(float(p) for p in np.atleast_1d(as_float_array(percentiles, "percentiles")))
    if any(p < 0 or p > 100 for p in levels):
        raise ValueError(f"`percentiles` must lie in [0, 100]; got {levels}.")
    keep = bool(a.size <= _KEEP_ELEMENTS) if per_frame is None else bool(per_frame)
    rows = _band_rows(a.shape[0], band_frames, keep)
    identity = bool(np.array_equal(idx, np.arange(idx.size)))
    # the standard order needs no (T, M) reordered copy (a is C-contiguous already)
    a = np.ascontiguousarray(a) if identity else np.ascontiguousarray(a[:, idx])
    gram = view.gram()
    if not identity:
        gram = gram[np.ix_(idx, idx)]
    orthonormal = bool(np.max(np.abs(gram - np.eye(gram.shape[0]))) <= _ORTHO_ATOL)
    if method == "auto":
        method = "parseval" if orthonormal else "gram"
    scale = unit_scale("rad", "waves") ** 2 if units == "waves2" else None
    mean = picked = None
    if method == "parseval":
        if not orthonormal:
            dev = float(np.max(np.abs(gram - np.eye(gram.shape[0]))))
            raise ValueError(
                "`method`='parseval' needs a basis orthonormal on the pupil (max |gram - I| "
                f"<= {_ORTHO_ATOL:g}); got max |gram - I| = {dev:.3g}. Use 'gram' or 'pixels'."
            )
        full = keep or rows is None
        curves, sums, total, picked = _parseval_pass(
            a, full, np.empty(0, np.int64) if rows is None else rows)
        if not full:
            mean = sums / a.shape[0]
            if scale is not None:
                mean *= scale
                picked *= scale
                total *= scale
    elif method == "gram":
        curves, total = _gram(a, gram)
    else:
        curves, total = _pixels(a, view.matrix[:, idx])
    if curves is not None:
        if scale is not None:
            curves *= scale  # in place: curves and total are this call's own arrays
            total *= scale
        mean = curves.mean(axis=0)
        picked = curves if rows is None else curves[rows]
    if not (np.all(np.isfinite(total)) and np.all(np.isfinite(mean))):
        check_values(a, "coeffs_or_log")  # names a non-finite or too large column
        raise ValueError("`coeffs_or_log`: the sums of squares overflow float64; rescale the "
                         "data (e.g. convert it to smaller units) before this analysis.")
    _check_square_floor(a, total)
    bands = _bands(picked, levels)
    dev = float(np.max(np.abs(gram - np.eye(gram.shape[0])))) if gram.size else 0.0
    difference = 0.0
    if method != "parseval":
        # no (T, M) temporary: the logs of issue 30 are GBs
        mean_square = np.einsum("tm,tm->m", a, a) / max(a.shape[0], 1)
        if scale is not None:
            mean_square *= scale
        difference = _sampling_check(
            mean, float(total.mean()), mean_square, dev,
            _continuous_zernikes(view.obj), view.obj,
            method)
    return FittingErrorResult(
        per_frame=curves if keep else None,
        mean=mean,
        total=total,
        percentiles=levels,
        bands=np.atleast_2d(bands),
        order=idx,
        labels=tuple(view.labels[i] for i in idx),
        units=units,
        method=method,
        band_frames=None if rows is None else int(rows.size),
        gram_deviation=dev,
        parseval_difference=difference,
    )
