"""Analytic references of the loop's error terms (Kolmogorov / von Karman turbulence).

The difference of a frozen-flow layer with itself shifted by ``s`` (a pure delay ``s = v
tau``, or anisoplanatism ``s = h theta``) has the mean-square value ``D(s)``, the
structure function, ``6.8839 (s / r0)**(5/3)`` for Kolmogorov turbulence (Fried 1966;
solar-mcao-notes). The simulator removes the piston over the pupil, which takes away the
variance of the difference's mean: for ``s << D`` that share falls only as
``(s / D)**(1/3)`` (the mean of ``s . grad phi`` is a tilt term), about 30 % at
``s = D / 32``. :func:`shifted_difference_variance` gives the exact expectation of the
piston-removed variance over a sampled pupil,

    E[var_P(phi(x) - phi(x - s))]
        = D(s) - (1/N^2) sum_{x,y in P} [(D(r + s) + D(r - s)) / 2 - D(r)],

``r = x - y``, computed with the pupil's autocorrelation (FFT), so tests and the error
budget compare the simulator with the law it must obey, not with its small-shift limit.
"""

from __future__ import annotations

import numpy as np

# the constant and the law live once, in modalinfo (the DM K-L modes use them too)
from modalinfo.bases.dm_kl import KOLMOGOROV_D_CONSTANT, von_karman_structure_function
from modalinfo.bases.turbulence import KOLMOGOROV_PSD_CONSTANT  # noqa: F401  (documentation)
from modalinfo.common.validation import as_float_array, check_real

__all__ = ["KOLMOGOROV_D_CONSTANT", "structure_function", "shifted_difference_variance"]


def structure_function(r, r0: float) -> np.ndarray:
    """Kolmogorov phase structure function ``6.8839 (r / r0)**(5/3)`` [rad^2].

    :func:`modalinfo.bases.von_karman_structure_function` at ``L0 = inf`` (``r`` [m],
    any sign; ``r0`` [m], ``> 0``), with its constant ``KOLMOGOROV_D_CONSTANT`` (of
    ``modalinfo.bases.dm_kl``, re-exported here).
    """
    return von_karman_structure_function(r, r0)


def shifted_difference_variance(mask: np.ndarray, dx: float, shift, r0: float) -> float:
    """Return the expected piston-removed variance over ``mask`` of ``phi(x) - phi(x - shift)``.

    Parameters
    ----------
    mask : (N, N) bool
        Pupil on a grid of pitch ``dx`` [m] (x along columns, y along rows); square, with
        at least one pixel.
    dx : float
        Grid pitch [m], ``> 0``.
    shift : (2,) array_like
        Shift ``(s_x, s_y)`` [m], finite.
    r0 : float
        Fried parameter [m] (Kolmogorov turbulence, phase at r0's wavelength).

    Returns
    -------
    float
        [rad^2].
    """
    mask = as_float_array(mask, "mask", ndim=2)
    if mask.shape[0] != mask.shape[1] or not mask.any():
        # a wider-than-tall mask wrapped around the 2N padding: a wrong number, no error
        raise ValueError(f"`mask` must be a square (N, N) pupil with at least one pixel; got "
                         f"shape {mask.shape} with {int(np.count_nonzero(mask))} pixels.")
    dx = check_real(dx, "dx", minimum=0.0, strict_min=True)
    shift = as_float_array(shift, "shift", shape=(2,))
    n = mask.shape[0]
    pad = 2 * n
    f = np.fft.rfft2(mask, s=(pad, pad))
    auto = np.fft.irfft2(f * np.conj(f), s=(pad, pad))
    auto = np.fft.fftshift(auto)  # lag 0 at (n, n)
    lags = (np.arange(pad) - n) * dx
    ly, lx = np.meshgrid(lags, lags, indexing="ij")
    sx, sy = float(shift[0]), float(shift[1])

    def d(x, y):
        return structure_function(np.hypot(x, y), r0)

    kernel = 0.5 * (d(lx + sx, ly + sy) + d(lx - sx, ly - sy)) - d(lx, ly)
    n_pix = mask.sum()
    piston = float(np.sum(auto * kernel)) / n_pix ** 2
    return float(d(sx, sy)) - piston
