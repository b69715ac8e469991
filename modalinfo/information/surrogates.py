"""Time-shift surrogates on a lattice and the rotated-source Gaussian null.

Shared by the two maximum-statistic tests of issue 21: the transfer-entropy map
(:mod:`modalinfo.information.flow`) and the greedy input search
(:mod:`modalinfo.information.selection`). In both, under a surrogate every candidate
series is rotated by s rows against the target and against the conditioning set
(the target's history, or the inputs chosen so far), and is residualised against the
conditioning set like the original, so each series keeps its autocorrelation and
only the alignment of candidate and target is broken. The shifts are multiples of a
spacing b with the original at 0 (:func:`surrogate_shifts`): the original is then
exchangeable with the surrogates. Why both halves matter (the rotated *target
residual* and shifts drawn at random from ``[m, n - m]`` were liberal) is measured in
``benchmarks/bench_flow_fwer.py`` and told in :mod:`modalinfo.information.flow`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from scipy import fft as sfft

from modalinfo.common.validation import check_rng

__all__ = ["circular_cross", "rotated_rho2", "surrogate_shifts"]


def _lattice(n: int, spacing: int, max_lag: int) -> np.ndarray:
    """Admissible multiples of ``spacing`` (see :func:`surrogate_shifts`)."""
    k = np.arange(1, (n - spacing) // spacing + 1) * spacing
    d = (2 * k) % n
    return k[np.minimum(d, n - d) >= 2 * (spacing + max_lag)]


def surrogate_shifts(n: int, n_surrogates: int, max_lag: int, spacing: int | None = None,
                     seed: Any = None) -> tuple[np.ndarray, int]:
    """Circular shifts of a map's surrogates: points of a lattice with the original at 0.

    The shifts are ``n_surrogates`` distinct multiples ``k b`` of a spacing b (drawn
    at random from the admissible ones), so the original (shift 0) and every
    surrogate are at least b apart from each other on the circle of n rows: the
    original is then exchangeable with the surrogates (a randomisation test over the
    subgroup of rotations by multiples of b), and the p-value
    ``(1 + #{surrogate >= original}) / (1 + n_surrogates)`` is exact for circularly
    stationary series when b divides n and no multiple is left out (approximately
    otherwise: the measured rates are in the module notes of
    :mod:`modalinfo.information.flow`). Shifts drawn from ``[m, n - m]`` at random are
    not: they may lie close to each other but never close to the original, which
    removes from the comparison exactly the values most correlated with the original,
    and the test is liberal by an amount that grows with ``m / n`` and with the number
    of candidates. A spacing below the span of the lags plus the series' correlation
    time costs power (a surrogate can re-align a true link at another lag), not
    validity.

    Multiples k b with ``2 k b`` within ``2 (b + max_lag)`` of a multiple of n are left
    out: there the cells ``j -> i`` and ``i -> j`` of a pair read the same part of the
    two series' cross-correlation (offsets ``k b + l`` and ``-(k b + l')`` equal modulo
    n), become copies, and the surrogate maximum falls below the null's.

    Parameters
    ----------
    n : int
        Rows of the map.
    n_surrogates : int
        Number of shifts >= 0.
    max_lag : int
        Largest source lag [samples].
    spacing : int, optional
        Lattice spacing b >= 1 [samples]; default the largest with ``n_surrogates``
        admissible multiples (about ``n / (n_surrogates + 1)``).
    seed : None, int or numpy.random.Generator
        Randomness of the choice among the admissible multiples.

    Returns
    -------
    shifts : numpy.ndarray of int, shape (n_surrogates,)
        Ascending shifts [samples].
    spacing : int
        The spacing b used (0 when ``n_surrogates`` is 0).

    Raises
    ------
    ValueError
        If fewer than ``n_surrogates`` admissible multiples exist.
    """
    if n_surrogates == 0:
        return np.empty(0, dtype=np.int64), 0
    rng = check_rng(seed)
    if spacing is None:
        b = max(n // (n_surrogates + 1), 1)
        while b > 1 and _lattice(n, b, max_lag).size < n_surrogates:
            b -= 1
    else:
        b = spacing
    allowed = _lattice(n, b, max_lag)
    if allowed.size < n_surrogates:
        raise ValueError(
            f"`n_surrogates`={n_surrogates} circular shifts spaced "
            f"{'`min_shift`=' if spacing is not None else ''}{b} apart do not fit in "
            f"{n} rows ({allowed.size} do, lags up to {max_lag}); use fewer surrogates"
            f"{' or a smaller `min_shift`' if spacing is not None else ''}, or more frames.")
    pick = np.sort(rng.choice(allowed.size, size=n_surrogates, replace=False))
    return allowed[pick].astype(np.int64), int(b)


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
    lin = sfft.irfft(F * np.conj(sfft.rfft(v, L))[None, :], L, axis=1)
    return (lin[:, L - shifts] + lin[:, n - shifts]).T


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
