"""Small statistics shared by subpackages that must not import each other."""

from __future__ import annotations

import numpy as np

from modalinfo.common.validation import as_float_array, check_int

__all__ = ["lag1_autocorrelation", "sample_autocovariance"]


def sample_autocovariance(x: np.ndarray, n_lags: int) -> np.ndarray:
    """Biased sample autocovariance ``gamma(k) = 1/n sum (x_t - m)(x_{t+k} - m)``, by FFT.

    Parameters
    ----------
    x : array_like, shape (T,)
        Finite real series, T >= 1.
    n_lags : int
        Largest lag ``K``.

    Returns
    -------
    numpy.ndarray, shape (K + 1,)
        ``gamma(0..K)`` (Brockwell & Davis eq. 1.4.4; the biased estimator is positive
        semi-definite, which Yule-Walker and the block-length rule rely on).

    Raises
    ------
    TypeError, ValueError
        If ``x`` is not a finite real 1-D series with a sample, or ``n_lags`` is not an
        int >= 0 (a list raised AttributeError, a (T, M) array was read as one series).
    """
    x = as_float_array(x, "x", ndim=1, min_length=1)
    n_lags = check_int(n_lags, "n_lags", minimum=0)
    xc = x - x.mean()
    n = xc.size
    # zero-padding to >= 2n makes the circular correlation of the FFT a linear one
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(xc, nfft)
    return np.fft.irfft(f * np.conj(f), nfft)[: n_lags + 1] / n


def lag1_autocorrelation(a: np.ndarray) -> float:
    """Lag-1 sample autocorrelation of a 1-D series (mean removed); 0 for a constant.

    ``sum (a_t - m)(a_(t+1) - m) / sum (a_t - m)^2`` (the biased estimator of
    Brockwell & Davis eq. 1.4.4, in [-1, 1]), computed on ``a / max |a|`` so that
    values near 1e300 do not overflow (the ratio is scale invariant).

    Parameters
    ----------
    a : numpy.ndarray, shape (n,)
        Finite real series in time order.

    Returns
    -------
    float
        The lag-1 autocorrelation.
    """
    scale = float(np.max(np.abs(a))) if a.size else 0.0
    if scale == 0.0:
        return 0.0
    d = a / scale
    d = d - d.mean()
    power = float(d @ d)
    return 0.0 if power <= 0.0 else float(d[1:] @ d[:-1]) / power
