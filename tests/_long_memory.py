"""Fractional Gaussian noise drawn exactly: one copy for the long-memory tests.

For tests/forecast/test_level_shift_long_memory_fix54a.py and
tests/information/test_ci_long_memory_round52.py. Reference: the Davies & Harte (1987)
circulant embedding of fGn's exact autocovariance ``0.5 (|k + 1|^2H - 2 |k|^2H +
|k - 1|^2H)`` (numpy FFT): stationary by construction, of Hurst exponent H.
"""

from __future__ import annotations

import numpy as np


def fgn(n: int, hurst: float, rng: np.random.Generator, m: int = 1) -> np.ndarray:
    """``m`` independent unit-variance fGn series of Hurst exponent ``hurst``, shape (n, m)."""
    k = np.arange(n, dtype=float)
    g = 0.5 * (np.abs(k + 1) ** (2 * hurst) - 2 * k ** (2 * hurst)
               + np.abs(k - 1) ** (2 * hurst))
    lam = np.clip(np.fft.fft(np.concatenate([g, g[-2:0:-1]])).real, 0.0, None)
    z = rng.standard_normal((lam.size, m)) + 1j * rng.standard_normal((lam.size, m))
    return np.fft.fft(np.sqrt(lam / lam.size)[:, None] * z, axis=0).real[:n]
