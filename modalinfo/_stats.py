"""Small statistics shared by subpackages that must not import each other."""

from __future__ import annotations

import numpy as np

__all__ = ["sample_autocovariance"]


def sample_autocovariance(x: np.ndarray, n_lags: int) -> np.ndarray:
    """Biased sample autocovariance ``gamma(k) = 1/n sum (x_t - m)(x_{t+k} - m)``, by FFT.

    Parameters
    ----------
    x : numpy.ndarray, shape (T,)
        Series (validated by the caller).
    n_lags : int
        Largest lag ``K``.

    Returns
    -------
    numpy.ndarray, shape (K + 1,)
        ``gamma(0..K)`` (Brockwell & Davis eq. 1.4.4; the biased estimator is positive
        semi-definite, which Yule-Walker and the block-length rule rely on).
    """
    xc = x - x.mean()
    n = xc.size
    # zero-padding to >= 2n makes the circular correlation of the FFT a linear one
    nfft = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(xc, nfft)
    return np.fft.irfft(f * np.conj(f), nfft)[: n_lags + 1] / n
