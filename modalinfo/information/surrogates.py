"""The rotated-source Gaussian null of the maximum-statistic tests.

Shared by the two maximum-statistic tests of issue 21: the transfer-entropy map
(:mod:`modalinfo.information.flow`) and the greedy input search
(:mod:`modalinfo.information.selection`). In both, under a surrogate every candidate
series is rotated by s rows against the target and against the conditioning set
(the target's history, or the inputs chosen so far), and is residualised against the
conditioning set like the original, so each series keeps its autocorrelation and
only the alignment of candidate and target is broken. The shifts s are drawn by
:func:`modalinfo.information.resampling.surrogate_shifts` (multiples of a spacing b
with the original at 0, so the original is exchangeable with the surrogates); this
module computes the Gaussian statistics of the rotated candidates from circular
cross-correlations. Why both halves matter (the rotated *target residual* and shifts
drawn at random from ``[m, n - m]`` were liberal) is measured in
``benchmarks/bench_flow_fwer.py`` and told in :mod:`modalinfo.information.flow`.
"""

from __future__ import annotations

import numpy as np
from scipy import fft as sfft

from modalinfo.common.chunked import blocks

__all__ = ["candidate_spectra", "circular_cross", "rotated_rho2"]

#: Values per column block of the FFT null's temporaries (the padded columns, their
#: spectra, the inverse transforms): 1 Mi values, 8 MiB of float64, whatever the
#: candidates' count; whole (columns, 2 T) arrays were 5 copies of the candidates
#: (fix54-d: select on 3,000 modes x 10 lags peaked at 4.5 GB for a 48 MB log).
BLOCK_VALUES = 1 << 20


def candidate_spectra(C: np.ndarray, L: int) -> np.ndarray:
    """Return ``rfft(C.T, L, axis=1)`` (shape (m, L // 2 + 1)), column block by column block.

    Parameters
    ----------
    C : numpy.ndarray, shape (n, m)
        Candidate columns.
    L : int
        Transform length (>= 2 n for :func:`circular_cross`).

    Returns
    -------
    numpy.ndarray of complex, shape (m, L // 2 + 1)
        The spectra: each row transformed alone, so the same values as one call.
    """
    n, m = C.shape
    out = np.empty((m, L // 2 + 1), dtype=complex)
    for cols in blocks(m, L, BLOCK_VALUES):
        out[cols] = sfft.rfft(np.ascontiguousarray(C[:, cols].T), L, axis=1)
    return out


def circular_cross(v: np.ndarray, C: np.ndarray, shifts: np.ndarray,
                   spectra: tuple[np.ndarray, int] | None = None) -> np.ndarray:
    """``(N, m)``: ``sum_t v[(t + s) mod n] C[t, j]`` for every shift s and column j.

    The dot product of ``v`` with column j of C rotated by s rows
    (``C_s[t] = C[(t - s) mod n]``). Directly, one gather and one matrix product
    (~ N n m); or, given ``spectra = (rfft(C.T, L), L)`` with L >= 2 n, from the linear
    cross-correlation ``lin[k] = sum_t C[t + k] v[t]`` by one inverse FFT
    (~ m L log L): the circular value at s is ``lin[-s] + lin[n - s]`` (``lin[-s]`` at
    index L - s).

    Parameters
    ----------
    v : numpy.ndarray, shape (n,)
    C : numpy.ndarray, shape (n, m)
    shifts : numpy.ndarray of int, shape (N,)
        Shifts in 1 .. n - 1 [rows].
    spectra : (numpy.ndarray, int), optional
        ``rfft(C.T, L, axis=1)`` (shape (m, L // 2 + 1)) and L.

    Returns
    -------
    numpy.ndarray, shape (N, m)
    """
    n = v.shape[0]
    if spectra is None:
        return v[(np.arange(n)[None, :] + shifts[:, None]) % n] @ C
    F, L = spectra
    vf = np.conj(sfft.rfft(v, L))[None, :]
    out = np.empty((shifts.shape[0], F.shape[0]))
    for cols in blocks(F.shape[0], L, BLOCK_VALUES):  # rows of F: the product and inverse
        lin = sfft.irfft(F[cols] * vf, L, axis=1)  # transform of all m were 3 copies
        out[:, cols] = (lin[:, L - shifts] + lin[:, n - shifts]).T
    return out


def rotated_rho2(xr: np.ndarray, xq: list[np.ndarray], c2: np.ndarray, r2: float
                 ) -> np.ndarray:
    """Squared partial correlation of a residual with rotated, residualised columns.

    With ``r`` orthogonal to the constant and to an orthonormal, centred basis
    ``q_1 .. q_k`` of the conditioning set, and ``C_s`` centred columns rotated by s,
    the residual of ``C_s`` against the basis is ``P C_s`` and
    ``r . P C_s = r . C_s``, ``|P C_s|^2 = |C|^2 - sum_a (q_a . C_s)^2``; so the
    squared correlation of ``r`` with ``P C_s`` needs only the cross-products of
    :func:`circular_cross`.

    Parameters
    ----------
    xr : numpy.ndarray, shape (N, m)
        ``r . C_s`` per shift and column.
    xq : list of numpy.ndarray, each shape (N, m)
        ``q_a . C_s`` per basis vector.
    c2 : numpy.ndarray, shape (m,)
        ``|C|^2`` per column.
    r2 : float
        ``|r|^2``.

    Returns
    -------
    numpy.ndarray, shape (N, m)
        ``rho^2`` in [0, 1] up to rounding.
    """
    den = np.broadcast_to(c2, xr.shape).copy()
    for x in xq:
        den -= x ** 2
    return xr * xr / (np.maximum(den, 1e-300) * r2)
