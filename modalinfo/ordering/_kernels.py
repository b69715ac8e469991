"""numba kernels of the ordering subpackage (no validation, no random numbers)."""

from __future__ import annotations

import numpy as np

from modalinfo.common.jit import jit


@jit
def pixel_fitting_error(coeffs, modes, out, total):
    """Fitting error on the pupil pixels for truncations of an ordered expansion.

    Parameters
    ----------
    coeffs : float64 (T, M), C-contiguous
        Coefficients, columns already in the chosen order.  # IN
    modes : float64 (M, n_valid), C-contiguous
        Mode values on the valid pixels, rows in the same order.  # IN
    out : float64 (T, M)
        ``out[t, j]`` = mean over pixels of ``|sum_{k > j} coeffs[t, k] modes[k]|^2``,
        i.e. the fitting error dPhi(j + 1) with the first j + 1 modes.  # OUT
    total : float64 (T,)
        dPhi(0) = mean over pixels of the full reconstruction squared.  # OUT
    """
    n_frames, n_modes = coeffs.shape
    n_pix = modes.shape[1]
    resid = np.empty(n_pix)
    for t in range(n_frames):
        for p in range(n_pix):
            resid[p] = 0.0
        for j in range(n_modes - 1, -1, -1):
            acc = 0.0
            for p in range(n_pix):
                acc += resid[p] * resid[p]
            out[t, j] = acc / n_pix
            a = coeffs[t, j]
            for p in range(n_pix):
                resid[p] += a * modes[j, p]
        acc = 0.0
        for p in range(n_pix):
            acc += resid[p] * resid[p]
        total[t] = acc / n_pix


@jit
def row_variances(values, out):
    """Write the population variance of every row (two passes: mean, then deviations).

    Parameters
    ----------
    values : float64 (M, B), C-contiguous  # IN
    out : float64 (M,)
        ``out[k]`` = mean over the row of ``(values[k] - mean(values[k]))**2``.  # OUT
    """
    n_rows, n_cols = values.shape
    for k in range(n_rows):
        acc = 0.0
        for i in range(n_cols):
            acc += values[k, i]
        mean = acc / n_cols
        acc = 0.0
        for i in range(n_cols):
            d = values[k, i] - mean
            acc += d * d
        out[k] = acc / n_cols


@jit
def gather_contributions(coeffs, matrix, frames, pixels, out):
    """Per-mode contributions ``a_k Z_k`` at sampled pairs, one row per mode.

    Written mode-major, so the ``(M, B)`` array the searches read row by row is built
    without a ``(B, M)`` temporary and its transposed copy (2 x 3.2 GB at 2,000 modes
    and 2e5 samples).

    Parameters
    ----------
    coeffs : float64 (T, M)  # IN
    matrix : float64 (n_valid, M)  # IN
    frames, pixels : int64 (B,)
        Frame and pixel index of each sample.  # IN
    out : float64 (M, B)
        ``out[k, i] = coeffs[frames[i], k] * matrix[pixels[i], k]``.  # OUT
    """
    n_samples = frames.shape[0]
    n_modes = coeffs.shape[1]
    block = 64  # modes per pass: reads rows of coeffs and matrix in cache-sized strips
    for k0 in range(0, n_modes, block):
        k1 = min(n_modes, k0 + block)
        for i in range(n_samples):
            t = frames[i]
            p = pixels[i]
            for k in range(k0, k1):
                out[k, i] = coeffs[t, k] * matrix[p, k]


@jit
def parseval_pass(coeffs, keep, out, sums, total, rows, picked):
    """Parseval fitting error of every frame, in one pass, optionally not kept.

    For each frame ``t`` the tail sums ``r_j = sum_{k > j} a_k^2`` are built from the
    last mode down (``r_{M-1} = 0``, ``r_{j-1} = r_j + a_j^2``: the sequential order of
    ``np.cumsum`` over the reversed row, so the same bits). They are written to
    ``out[t]`` when ``keep``, added to ``sums`` (frame by frame, in frame order: the
    order of ``out.sum(axis=0)``) and copied to ``picked`` for the frames listed in
    ``rows``.

    Parameters
    ----------
    coeffs : float64 (T, M), C-contiguous
        Coefficients, columns in the chosen order.  # IN
    keep : bool
        Write the per-frame curves to ``out``.
    out : float64 (T, M) when ``keep`` (any 2-D array otherwise)
        ``out[t, j]`` = dPhi(j + 1) of frame t.  # OUT
    sums : float64 (M,)
        ``sum_t`` dPhi(j + 1) of frame t, zeroed here.  # OUT
    total : float64 (T,)
        dPhi(0) per frame.  # OUT
    rows : int64 (R,), increasing
        Frames whose curves go to ``picked``.  # IN
    picked : float64 (R, M)
        Their curves.  # OUT
    """
    n_frames, n_modes = coeffs.shape
    for j in range(n_modes):
        sums[j] = 0.0
    i = 0
    for t in range(n_frames):
        take = i < rows.shape[0] and rows[i] == t
        s = 0.0
        for j in range(n_modes - 1, -1, -1):
            if keep:
                out[t, j] = s
            if take:
                picked[i, j] = s
            sums[j] += s
            a = coeffs[t, j]
            s += a * a
        total[t] = s
        if take:
            i += 1
