"""AR(1) modes of Kolmogorov Noll covariance and their glitched copies: one copy.

For the glitched-log tests of round 53 PART a (test_outlier_links_round53) and fix54-b
(test_glitch_links_fix54b). Reference: the exact model, AR(1) ``y_t = a y_(t-1) + e_t``
of coefficient ``a`` whose innovations share the Kolmogorov Noll covariance of Zernike
modes 2 ... (``modalinfo.bases.zernike_covariance`` at D/r0 20), started from that
covariance (the stationary law): given a mode's own past no other series adds
information, so the exact input set of ``select_inputs`` is the target's lag 1 and every
transfer entropy given the target's own past is 0. The glitches are +-20 sd at 4
frames in 3 modes (mode 0 and 2 others), placed by the seed (numpy).
"""

from __future__ import annotations

import numpy as np

from modalinfo.bases import zernike_covariance

A = 0.9


def noll_ar1(n_frames: int, n_modes: int, seed: int) -> np.ndarray:
    """``n_modes`` AR(1) modes of coefficient :data:`A`, shape (n_frames, n_modes) [rad]."""
    cov = zernike_covariance(list(range(2, 2 + n_modes))) * 20.0 ** (5 / 3)
    chol = np.linalg.cholesky(cov)
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n_frames, n_modes)) @ chol.T * np.sqrt(1 - A * A)
    y = np.empty((n_frames, n_modes))
    y[0] = rng.standard_normal(n_modes) @ chol.T
    for t in range(1, n_frames):
        y[t] = A * y[t - 1] + e[t]
    return y


def glitched(y: np.ndarray, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A copy of ``y`` with +-20 sd at 4 frames of 3 modes, the frames and the modes."""
    rng = np.random.default_rng(seed + 999)
    out, sd = y.copy(), y.std(axis=0)
    frames = rng.choice(np.arange(10, len(y) - 10), 4, replace=False)
    cols = np.r_[0, rng.choice(np.arange(1, y.shape[1]), 2, replace=False)]
    for f in frames:
        for c in cols:
            out[f, c] += 20 * sd[c] * rng.choice([-1, 1])
    return out, frames, cols
