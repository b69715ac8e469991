"""Image-shift measurement for a correlating (solar) Shack-Hartmann.

The methods Loefdahl (2010, A&A 524, A90, "Evaluation of image-shift measurement
algorithms for solar Shack-Hartmann wavefront sensors") evaluates, on a "live" image
against a reference image of the same scene:

``method``
    ``"sdf"``
        square difference function ``C(d) = sum_x (i(x) - r(x - d))**2`` over a window
        of the live image; minimum at the shift.
    ``"adf2"``
        absolute difference function, squared: ``C(d) = (sum_x |i(x) - r(x - d)|)**2``
        (squaring makes the surface near its minimum closer to a paraboloid).
    ``"cfi"``
        covariance function computed with FFTs (``-`` the cyclic cross-covariance of
        the mean-subtracted windows), whose maximum is the shift. The cyclic covariance
        of windows that are not periodic (any real granulation image) wraps each window's
        far edge onto its near one, which pulls the peak towards zero shift: shifts of
        0.3 / 1.0 / 1.3 / 2.0 pixels of a smoothed random scene in a 40-pixel window read
        0.17 / 0.83 / 1.12 / 1.89 (SDF and ADF^2: within 0.01; audit 9). Loefdahl (2010)
        finds CFI the least accurate of the three for the same reason. ``measure_shifts``
        warns (``UserWarning``) whenever it is chosen; it is kept for timing comparisons
        (``closedloop.studies.solar.correlation_compute_time``).

``interpolation``
    Sub-pixel position of the extremum from the 3x3 values around the integer one
    (Loefdahl 2010, Sect. 3.2):

    ``"2d-quadratic"``
        (2QI) the paraboloid ``a1 + a2 x + a3 x^2 + a4 y + a5 y^2 + a6 x y`` through the
        centre and its 4 neighbours with the cross term from the corners (Yi &
        Molowny-Horas 1992); Loefdahl's recommended choice with SDF and ADF^2.
    ``"1d-quadratic"``
        (1QI) a parabola along each axis through 3 points.
    ``"2d-least-squares"``
        (2LS) the same paraboloid fitted to all 9 points.

The difference functions are computed by a numba kernel over the whole batch
(:func:`closedloop.optics._shift_kernels.difference_surfaces`), the covariance by numpy's
real FFT. Shifts are in pixels, ``(x, y)`` = (columns, rows), positive when the live
image is displaced towards larger indices relative to the reference.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from closedloop.optics import _shift_kernels
from modalinfo.common.quiet import warn

__all__ = ["ShiftResult", "measure_shifts", "sdf_noise_rms", "sdf_noise_at_shifts", "METHODS",
           "INTERPOLATIONS"]

METHODS = ("sdf", "adf2", "cfi")
INTERPOLATIONS = ("2d-quadratic", "1d-quadratic", "2d-least-squares")


@dataclass(frozen=True)
class ShiftResult:
    """Measured image shifts.

    Attributes
    ----------
    shifts : (n_images, 2) ndarray
        Shift ``(x, y)`` of each image relative to its reference [pixels].
    integer : (n_images, 2) ndarray of int
        The integer lag ``(x, y)`` of the extremum before interpolation.
    at_edge : (n_images,) ndarray of bool
        True where the extremum sits on the edge of the search range (``|lag| ==
        max_shift``): the true shift may lie beyond it.
    mismatch : (n_images,) ndarray of float
        How poorly the best lag matches: the smallest value of the difference surface
        over the searched lags divided by its median over them (``sdf`` and ``adf2``;
        NaN for ``cfi``). Near 0 for a true match, near 1 when no lag matches: a dark
        frame with read noise, an inverted image, a strong aberration (3 rad of defocus
        over the subaperture: 0.64), or a shift well beyond
        ``max_shift``, whose minimum falls on a look-alike of the scene inside the range
        with ``at_edge`` False (granulation repeats every ~1.3", a few pixels). Measured
        on granulation (pixels 0.2-0.5", windows 24-48 pixels, 100 e- per pixel to
        noise-free; adversarial round 29): 0.03-0.50 for shifts within ``max_shift`` = 3,
        0.60-0.84 for shifts of 5-17 pixels (read as 0-3 pixels). Not a threshold: the
        noise floor raises it at low signal.
    """

    shifts: np.ndarray
    integer: np.ndarray
    at_edge: np.ndarray
    mismatch: np.ndarray | None = None


# ----------------------------------------------------------------------- surfaces
def _surfaces_difference(refs, images, r0, c0, win, lag, squared):
    """SDF / ADF^2 surfaces by the numba kernel; preconditions as the kernel's."""
    out = np.empty((images.shape[0], 2 * lag + 1, 2 * lag + 1))
    _shift_kernels.difference_surfaces(refs, images, r0, c0, win, lag, squared, out)
    return out


def _surfaces_numpy(refs, images, r0, c0, win, lag, squared):
    """Compute the same surfaces with numpy slicing (one pass per lag); for benchmarks."""
    n = images.shape[0]
    out = np.empty((n, 2 * lag + 1, 2 * lag + 1))
    live = images[:, r0:r0 + win, c0:c0 + win]
    for iy, dy in enumerate(range(-lag, lag + 1)):
        for ix, dx in enumerate(range(-lag, lag + 1)):
            d = live - refs[:, r0 - dy:r0 - dy + win, c0 - dx:c0 - dx + win]
            out[:, iy, ix] = ((d * d).sum(axis=(1, 2)) if squared
                              else np.abs(d).sum(axis=(1, 2)) ** 2)
    return out


def _surfaces_cfi(refs, images, r0, c0, win, lag):
    """Minus the cyclic cross-covariance of the mean-subtracted windows (Loefdahl's CFI)."""
    live = images[:, r0:r0 + win, c0:c0 + win]
    ref = refs[:, r0:r0 + win, c0:c0 + win]
    live = live - live.mean(axis=(1, 2), keepdims=True)
    ref = ref - ref.mean(axis=(1, 2), keepdims=True)
    # c(d) = sum_x i(x) r(x - d): FT(c) = FT(i) conj(FT(r))
    cov = np.fft.irfft2(np.fft.rfft2(live) * np.conj(np.fft.rfft2(ref)), s=(win, win))
    idx = np.arange(-lag, lag + 1) % win
    return -cov[:, idx[:, None], idx[None, :]]


# ----------------------------------------------------------------------- interpolation
def _paraboloid_vertex(a2, a3, a4, a5, a6):
    """Stationary point of ``a2 x + a3 x^2 + a4 y + a5 y^2 + a6 x y``; 0 where degenerate."""
    det = a6 * a6 - 4.0 * a3 * a5
    ok = det != 0.0
    safe = np.where(ok, det, 1.0)
    x = np.where(ok, (2.0 * a2 * a5 - a4 * a6) / safe, 0.0)
    y = np.where(ok, (2.0 * a3 * a4 - a2 * a6) / safe, 0.0)
    return x, y


def _interp_2qi(c):
    """2QI: Yi & Molowny-Horas (1992) as Loefdahl (2010) Sect. 3.2 writes it; ``c[:, y, x]``."""
    a2 = (c[:, 1, 2] - c[:, 1, 0]) / 2.0
    a3 = (c[:, 1, 2] - 2.0 * c[:, 1, 1] + c[:, 1, 0]) / 2.0
    a4 = (c[:, 2, 1] - c[:, 0, 1]) / 2.0
    a5 = (c[:, 2, 1] - 2.0 * c[:, 1, 1] + c[:, 0, 1]) / 2.0
    a6 = (c[:, 2, 2] - c[:, 2, 0] - c[:, 0, 2] + c[:, 0, 0]) / 4.0
    return _paraboloid_vertex(a2, a3, a4, a5, a6)


def _interp_1qi(c):
    """1QI: a parabola through 3 points per axis, ``x = (c_- - c_+) / 2 (c_- - 2 c_0 + c_+)``."""
    def one(m, z, p):
        den = m - 2.0 * z + p
        ok = den != 0.0
        return np.where(ok, (m - p) / (2.0 * np.where(ok, den, 1.0)), 0.0)
    return one(c[:, 1, 0], c[:, 1, 1], c[:, 1, 2]), one(c[:, 0, 1], c[:, 1, 1], c[:, 2, 1])


_YY, _XX = np.mgrid[-1:2, -1:2]
#: 2LS: least-squares paraboloid on the 3x3 points (columns a1..a6)
_LS_PINV = np.linalg.pinv(np.column_stack([np.ones(9), _XX.ravel(), _XX.ravel() ** 2,
                                           _YY.ravel(), _YY.ravel() ** 2,
                                           (_XX * _YY).ravel()]).astype(np.float64))


def _interp_2ls(c):
    """2LS: the paraboloid of :func:`_interp_2qi` fitted by least squares to all 9 points."""
    a = c.reshape(c.shape[0], 9) @ _LS_PINV.T
    return _paraboloid_vertex(a[:, 1], a[:, 2], a[:, 3], a[:, 4], a[:, 5])


_INTERP = {"2d-quadratic": _interp_2qi, "1d-quadratic": _interp_1qi,
           "2d-least-squares": _interp_2ls}


# ----------------------------------------------------------------------- wrapper
def _as_stack(name: str, a) -> np.ndarray:
    arr = np.asarray(a)
    if arr.dtype.kind not in "fiu":
        raise TypeError(f"`{name}` must be a real numeric array; got dtype {arr.dtype}.")
    if arr.ndim == 2:
        arr = arr[None]
    if arr.ndim != 3:
        raise ValueError(f"`{name}` must be (H, W) or (n, H, W); got shape {arr.shape}.")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"`{name}` must be finite; it holds NaN or inf.")
    return np.ascontiguousarray(arr, dtype=np.float64)


def _search_window(h: int, w: int, max_shift, window, method: str = "sdf"):
    """Return ``(lag, window)`` of the difference surface for ``h x w`` images.

    One copy of the rule for the measurement and both noise laws: the window must leave
    room for every lag of ``max_shift + 1`` on both sides (``'cfi'``: the lags are taken
    inside the window instead).
    """
    lag = int(max_shift) + 1
    side = min(h, w)
    if method == "cfi":
        low, high = 2 * lag + 1, side
    else:
        low, high = 3, side - 2 * lag
    if high < low:
        # no window fits: name the search range, not a window the user never gave
        raise ValueError(f"`max_shift` = {max_shift} is too large for images of {h}x{w} "
                         f"with method {method!r}: it must be <= "
                         f"{(side - 3) // 2 if method == 'cfi' else (side - 5) // 2}.")
    if window is None:
        window = high
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)) \
            or not low <= window <= high:
        raise ValueError(f"`window` must be an int in [{low}, {high}] for images of "
                         f"{h}x{w} with `max_shift` = {max_shift} and method {method!r}; "
                         f"got {window!r}.")
    return lag, int(window)


def measure_shifts(reference, images, *, method: str = "sdf",
                   interpolation: str = "2d-quadratic", max_shift: int = 3,
                   window: int | None = None, normalize: bool = False) -> ShiftResult:
    """Measure the shift of each image against its reference.

    Parameters
    ----------
    reference : (H, W) or (n_images, H, W) array_like
        One reference for all images, or one per image [any intensity unit].
    images : (H, W) or (n_images, H, W) array_like
        Live images, same ``(H, W)``.
    method : {"sdf", "adf2", "cfi"}
        Matching function (module docstring).
    interpolation : {"2d-quadratic", "1d-quadratic", "2d-least-squares"}
        Sub-pixel interpolation of the extremum.
    max_shift : int
        Largest integer lag searched [pixels], >= 1; the difference functions are
        evaluated one pixel further so that an extremum at ``max_shift`` can be
        interpolated.
    window : int, optional
        Side of the centred square of the live image that is compared [pixels]. For
        ``sdf``/``adf2`` it must leave ``max_shift + 1`` pixels of the reference on
        every side (``window + 2 (max_shift + 1) <= min(H, W)``; default the largest
        such). For ``cfi`` it is the FFT size (``2 max_shift + 3 <= window <=
        min(H, W)``; default ``min(H, W)``).
    normalize : bool
        Divide every image and reference by its mean first, so that a difference of
        intensity between subapertures (vignetting, gain errors: Loefdahl's "bias
        mismatch") does not bias SDF/ADF^2 (CFI subtracts the means anyway).

    Returns
    -------
    ShiftResult
        ``shifts`` ``(n_images, 2)`` [pixels], ``(x, y)``.
    """
    if method not in METHODS:
        raise ValueError(f"`method` must be one of {METHODS}; got {method!r}.")
    if interpolation not in _INTERP:
        raise ValueError(f"`interpolation` must be one of {INTERPOLATIONS}; "
                         f"got {interpolation!r}.")
    if isinstance(max_shift, bool) or not isinstance(max_shift, (int, np.integer)) \
            or max_shift < 1:
        raise ValueError(f"`max_shift` must be an int >= 1; got {max_shift!r}.")
    refs = _as_stack("reference", reference)
    imgs = _as_stack("images", images)
    if imgs.shape[1:] != refs.shape[1:]:
        raise ValueError(f"`reference` and `images` must have the same (H, W); got "
                         f"{refs.shape[1:]} and {imgs.shape[1:]}.")
    if refs.shape[0] not in (1, imgs.shape[0]):
        raise ValueError(f"`reference` must hold 1 image or one per image "
                         f"({imgs.shape[0]}); got {refs.shape[0]}.")
    if not isinstance(normalize, (bool, np.bool_)):
        raise TypeError(f"`normalize` must be a bool; got {normalize!r}.")
    if normalize:
        for name, a in (("reference", refs), ("images", imgs)):
            mean = a.mean(axis=(1, 2), keepdims=True)
            if np.any(mean <= 0):
                raise ValueError(f"`{name}` must have a positive mean to be normalised.")
        refs = refs / refs.mean(axis=(1, 2), keepdims=True)
        imgs = imgs / imgs.mean(axis=(1, 2), keepdims=True)
    h, w = imgs.shape[1:]
    lag, window = _search_window(h, w, max_shift, window, method)
    flat = np.flatnonzero(np.ptp(refs, axis=(1, 2)) == 0)
    if flat.size:  # a flat surface: its "minimum" was lag (-max_shift, -max_shift) (audit 9)
        raise ValueError(f"`reference` image {int(flat[0])} is constant: it has no structure "
                         "to measure a shift against.")
    flat = np.flatnonzero(np.ptp(imgs, axis=(1, 2)) == 0)
    if flat.size:  # a dark or saturated frame: every lag matched equally badly (round 29)
        raise ValueError(f"`images` image {int(flat[0])} is constant (a dark or saturated "
                         "frame): it has no structure to measure a shift from.")
    win = int(window)
    r0 = (h - win) // 2
    c0 = (w - win) // 2
    if method == "cfi":
        warn("method 'cfi' of measure_shifts (a cyclic cross-covariance) underestimates "
             "shifts of non-periodic images, by up to ~0.4 pixel at 1-2 pixels "
             "(module docstring); use 'sdf' or 'adf2' for measurements",
             UserWarning, stacklevel=2)
        surf = _surfaces_cfi(refs, imgs, r0, c0, win, lag)
    else:
        surf = _surfaces_difference(refs, imgs, r0, c0, win, lag, method == "sdf")
    n = imgs.shape[0]
    # the extremum among the lags |d| <= max_shift; its 3x3 neighbourhood always exists
    inner = surf[:, 1:-1, 1:-1].reshape(n, -1)
    flat = np.argmin(inner, axis=1)
    m = 2 * lag - 1
    iy = flat // m + 1
    ix = flat % m + 1
    k = np.arange(n)
    rows = iy[:, None, None] + np.arange(-1, 2)[None, :, None]
    cols = ix[:, None, None] + np.arange(-1, 2)[None, None, :]
    nb = surf[k[:, None, None], rows, cols]
    fx, fy = _INTERP[interpolation](nb)
    # an interpolated vertex outside the 3x3 cell is an extrapolation: keep it inside
    fx = np.clip(fx, -1.0, 1.0)
    fy = np.clip(fy, -1.0, 1.0)
    integer = np.column_stack([ix - lag, iy - lag]).astype(np.int64)
    shifts = integer + np.column_stack([fx, fy])
    at_edge = np.abs(integer).max(axis=1) == max_shift
    return ShiftResult(shifts=shifts, integer=integer, at_edge=at_edge,
                       mismatch=_mismatch(surf, method))


def _mismatch(surf: np.ndarray, method: str) -> np.ndarray:
    """``ShiftResult.mismatch``: min / median of the searched lags' surface (NaN for cfi)."""
    n = surf.shape[0]
    if method == "cfi":
        return np.full(n, np.nan)
    # a shift beyond the range lands on a look-alike inside it with at_edge False, and a
    # noisy dark or an inverted image still has a minimum: say how good it is
    # (adversarial round 29, rows sh-beyond, sh-dark, sh-neg)
    searched = surf[:, 1:-1, 1:-1].reshape(n, -1)
    median = np.median(searched, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(median > 0, searched.min(axis=1) / median, 1.0)


def sdf_noise_rms(reference, noise_variance, *, max_shift: int = 3,
                  window: int | None = None) -> np.ndarray:
    """Predicted rms of SDF + quadratic-interpolation shifts from white noise in the live image.

    The linearised least-squares law (Michau et al. 1992's ``sigma^2 / sum (dr/dx)^2``)
    written with the finite differences the 3-point interpolation uses: along x,

        var = 4 sum_W s2 (D r)^2 / (sum_W (r - r(x + 1))^2 + (r - r(x - 1))^2)^2,

    ``D r = (r(x + 1) - r(x - 1)) / 2``, sums over the live window ``W``, ``s2`` the noise
    variance of each live pixel (a noise-free reference, the stored-reference case; a
    reference as noisy as the live image doubles the variance). It ignores the 2QI cross
    term, which the tests show is negligible on granulation. Use it to give a fast
    (geometric) sensor the noise of a correlating one.

    It is the law at a whole-pixel shift (the live image aligned with the reference to
    an integer lag). At a sub-pixel shift the interpolation's error is no longer linear
    in the noise: measured on granulation (0.25"/pixel, 48-pixel images, 1000 e- per
    pixel, 1000 Poisson draws; adversarial round 29) the variance is 1.0x the law at
    (0, 0), 1.2x along x at (0.2, 0), 1.5-2.2x at (0.4, 0.2) and (1.4, -0.3) pixels,
    and 70-110x at (0.5, 0.5), where the noise flips the integer lag between the two
    nearest and each side's interpolation bias (~0.03 pixel) differs. Averaged over the
    sub-pixel shifts a closed loop leaves, the law is a lower bound: over Gaussian
    shifts of rms 0.05 / 0.1 / 0.2 / 0.3 / 0.5 pixel the variance is 1.03-1.04x /
    1.04-1.08x / 1.2-1.3x / 1.5x / 1.6-1.7x the law (30 shifts x 100 draws each).

    Parameters
    ----------
    reference : (H, W) array_like
        Noise-free image [e-].
    noise_variance : float or (H, W) array_like
        Per-pixel noise variance of the live image [e-^2] (photon + read: ``r + RON^2``).
    max_shift, window
        As in :func:`measure_shifts` (``sdf``).

    Returns
    -------
    (2,) ndarray
        rms shift error ``(x, y)`` [pixels].
    """
    ref = _as_stack("reference", reference)
    if ref.shape[0] != 1:
        raise ValueError(f"`reference` must be one (H, W) image; got shape {ref.shape}.")
    ref = ref[0]
    var = np.broadcast_to(np.asarray(noise_variance, dtype=np.float64), ref.shape)
    if not np.all(np.isfinite(var)) or var.min() < 0:
        raise ValueError("`noise_variance` must be finite and >= 0.")
    h, w = ref.shape
    lag, window = _search_window(h, w, max_shift, window)
    r0, c0 = (h - window) // 2, (w - window) // 2
    out = np.empty(2)
    for axis in (0, 1):  # 0: x (columns), 1: y (rows)
        img = ref if axis == 0 else ref.T
        v = var if axis == 0 else var.T
        a, b = (r0, c0) if axis == 0 else (c0, r0)
        c = img[a:a + window, b:b + window]
        plus = img[a:a + window, b + 1:b + window + 1]
        minus = img[a:a + window, b - 1:b + window - 1]
        d = (plus - minus) / 2.0
        curv = ((c - plus) ** 2 + (c - minus) ** 2).sum()
        out[axis] = np.sqrt(4.0 * (v[a:a + window, b:b + window] * d ** 2).sum() / curv ** 2)
    return out


def sdf_noise_at_shifts(reference, live, noise_variance, *, max_shift: int = 3,
                        window: int | None = None, draws: int = 4000,
                        seed: int = 0) -> np.ndarray:
    """Predict the rms of SDF + 2QI shifts of noise-free live images plus white Gaussian noise.

    :func:`sdf_noise_rms` is the law at a whole-pixel shift. At any shift, the square
    difference ``C(d) = sum_W (i + n - r(x - d))**2`` of a live image ``i`` with noise
    ``n`` is ``C0(d) + 2 sum_W n (i - r(x - d)) + sum_W n**2``: the last sum is the same
    at every lag (the window is on the live image), so it moves neither the minimum nor
    the 2QI vertex, and the rest is linear in ``n``. The 5x5 lags around the noise-free
    minimum are therefore Gaussian with mean ``C0`` and covariance ``4 sum_W s2 (i -
    r_d)(i - r_d')``; ``draws`` surfaces are drawn from it and measured as
    :func:`measure_shifts` measures (the integer minimum over the central 3x3, then 2QI),
    so that the lag flip near half a pixel and the two sides' different interpolation
    biases are included. Cheap: no image is formed per draw. The same draws (``seed``)
    serve every live image, so ratios between shifts have little Monte Carlo noise.

    Parameters
    ----------
    reference : (H, W) array_like
        Noise-free reference image [e-].
    live : (H, W) or (n, H, W) array_like
        Noise-free live images [e-], displaced from the reference by less than
        ``max_shift - 1`` pixels.
    noise_variance : float or array_like broadcastable to (n, H, W)
        Per-pixel noise variance of the live images [e-^2] (photon + read: ``i + RON^2``).
    max_shift, window
        As in :func:`measure_shifts` (``sdf``, ``2d-quadratic``).
    draws : int
        Gaussian surfaces per image (the variance's relative standard error is
        ``sqrt(2 / draws)``).
    seed : int
        Seed of the draws.

    Returns
    -------
    (n, 2) ndarray
        rms shift error ``(x, y)`` of each live image [pixels].
    """
    ref = _as_stack("reference", reference)
    if ref.shape[0] != 1:
        raise ValueError(f"`reference` must be one (H, W) image; got shape {ref.shape}.")
    imgs = _as_stack("live", live)
    if imgs.shape[1:] != ref.shape[1:]:
        raise ValueError(f"`reference` and `live` must have the same (H, W); got "
                         f"{ref.shape[1:]} and {imgs.shape[1:]}.")
    var = np.broadcast_to(np.asarray(noise_variance, dtype=np.float64), imgs.shape)
    if not np.all(np.isfinite(var)) or var.min() < 0:
        raise ValueError("`noise_variance` must be finite and >= 0.")
    if isinstance(draws, bool) or not isinstance(draws, (int, np.integer)) or draws < 2:
        raise ValueError(f"`draws` must be an int >= 2; got {draws!r}.")
    h, w = ref.shape[1:]
    if isinstance(max_shift, bool) or not isinstance(max_shift, (int, np.integer)) \
            or max_shift < 1:
        raise ValueError(f"`max_shift` must be an int >= 1; got {max_shift!r}.")
    lag, win = _search_window(h, w, max_shift, window)
    r0, c0 = (h - win) // 2, (w - win) // 2
    surf = _surfaces_difference(ref, imgs, r0, c0, win, lag, True)
    n = imgs.shape[0]
    z = np.random.default_rng(seed).standard_normal((int(draws), 25))
    off = np.arange(-2, 3)
    out = np.empty((n, 2))
    for k in range(n):
        iy, ix = np.unravel_index(np.argmin(surf[k, 1:-1, 1:-1]), surf[k, 1:-1, 1:-1].shape)
        dy0, dx0 = int(iy) + 1 - lag, int(ix) + 1 - lag
        if max(abs(dy0), abs(dx0)) > lag - 2:
            raise ValueError(f"`live` image {k} is displaced by ({dx0}, {dy0}) pixels; "
                             f"it must be within {lag - 2} of the reference.")
        i = imgs[k, r0:r0 + win, c0:c0 + win].ravel()
        a = np.stack([i - ref[0, r0 - dy:r0 - dy + win, c0 - dx:c0 - dx + win].ravel()
                      for dy in dy0 + off for dx in dx0 + off])          # (25, win^2)
        c0_ = (a * a).sum(axis=1)
        m = 2.0 * a * np.sqrt(var[k, r0:r0 + win, c0:c0 + win].ravel())[None, :]
        ev, vec = np.linalg.eigh(m @ m.T)
        root = vec * np.sqrt(np.clip(ev, 0.0, None))[None, :]
        c = (c0_[None, :] + z @ root.T).reshape(-1, 5, 5)
        flat = np.argmin(c[:, 1:4, 1:4].reshape(-1, 9), axis=1)
        jy, jx = flat // 3 + 1, flat % 3 + 1
        rows = jy[:, None, None] + np.arange(-1, 2)[None, :, None]
        cols = jx[:, None, None] + np.arange(-1, 2)[None, None, :]
        nb = c[np.arange(c.shape[0])[:, None, None], rows, cols]
        fx, fy = _interp_2qi(nb)
        sx = jx - 2 + np.clip(fx, -1.0, 1.0)
        sy = jy - 2 + np.clip(fy, -1.0, 1.0)
        out[k] = [sx.std(ddof=1), sy.std(ddof=1)]
    return out
