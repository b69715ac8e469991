"""Exact rescaling of samples whose magnitude float64 cannot square.

The estimators form sums of squares (variances, autocovariances): they overflow above
~1e154 and vanish below ~1e-154 (audit 9: 1e200 gave inf, 1e-300 gave 0, 1e100 NaN in
the block length). Mutual information, conditional MI and block lengths are unchanged by
a variable's scale, and an entropy shifts by exactly ``ln c`` (Cover & Thomas 2006,
Theorem 8.6.4), so such a sample is divided by a power of two first: ``ldexp`` changes
only the exponent of every value, so the scaled sample holds the same digits and the
answer is that of the sample as given. Samples within the bounds are returned as they
are (the same object), so every result inside them is unchanged bit for bit.
"""

from __future__ import annotations

import numpy as np

__all__ = ["SAFE_MAGNITUDE", "rescale_power_of_two"]

#: Magnitudes [any unit] outside which :func:`rescale_power_of_two` rescales by default:
#: a factor 1e54 from each end of float64's squares (~1e-154 .. 1e154).
SAFE_MAGNITUDE = (1e-100, 1e100)


def rescale_power_of_two(
    x: np.ndarray,
    size: float | np.ndarray,
    *,
    peak: float | np.ndarray | None = None,
    bounds: tuple[float, float] = SAFE_MAGNITUDE,
) -> tuple[np.ndarray, int | np.ndarray]:
    """Divide ``x`` (or each of its columns) by ``2**e`` where its magnitude is out of bounds.

    Parameters
    ----------
    x : numpy.ndarray, shape (n,) or (n, d)
        Float sample, not modified.
    size : float or numpy.ndarray, shape (d,)
        The magnitude that sets the exponent (a spread, a largest ``|x|``), one per column
        for a 2-D ``x``; a size of 0 (a constant column) is never rescaled.
    peak : float or numpy.ndarray, shape (d,), optional
        A second magnitude that must stay at or below ``bounds[1]`` (the largest ``|x|``
        of a sample whose ``size`` is its spread); default ``size``.
    bounds : tuple of float
        ``(low, high)``: a column is rescaled when ``0 < size < low`` or ``size > high``
        or ``peak > high``.

    Returns
    -------
    scaled : numpy.ndarray
        ``x`` itself when no column is out of bounds, else a copy with each such column
        multiplied by ``2**-e`` (exact), so that its ``size`` is in ``[0.5, 1)``.
    e : int or numpy.ndarray of int, shape (d,)
        The exponent of each column (0 where untouched); an int for a scalar ``size``.
    """
    size_a = np.asarray(size, dtype=float)
    peak_a = size_a if peak is None else np.asarray(peak, dtype=float)
    low, high = bounds
    bad = ((size_a > 0) & (size_a < low)) | (size_a > high) | (peak_a > high)
    e = np.where(bad & (size_a > 0), np.frexp(size_a)[1], 0)
    if size_a.ndim == 0:
        e = int(e)
        return (x, 0) if e == 0 else (np.ldexp(x, -e), e)
    if not e.any():
        return x, e
    return np.ldexp(x, -e), e
