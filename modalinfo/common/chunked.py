"""Long array work in chunks, so that Ctrl-C is honoured between them.

Python runs a signal handler (``KeyboardInterrupt`` for SIGINT) only between bytecodes:
one numba kernel or BLAS product of several seconds defers Ctrl-C until it returns.
``fitting-error --plot`` on a 3,000-mode log stopped 12.6 s after SIGINT (adversarial
round 53 PART b, W39): the Zernike matrix of 3,000 modes on a 160-pixel pupil (one numba
call, 8 s under load) and its Gram matrix ``A^T A`` (one BLAS call, 6.5 s). Cut into
chunks (:data:`PRODUCT_TERMS`, :data:`KERNEL_VALUES`), a pending SIGINT is raised after the
chunk in progress (a fraction of a second). :func:`blocks` cuts a kernel's pixels and
:func:`matmul`'s rows: whole entries per call, the same values. :func:`gram` sums the
products of row blocks: equal to rounding (the terms added in another order), and one
call, the same values, where the product is within one chunk.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

#: Multiply-adds per product chunk: about 0.1-0.5 s of one core's BLAS.
PRODUCT_TERMS = 1 << 31

#: Values per chunk of a numba kernel of ~100 ns a value (the Zernike matrix): ~0.1 s.
KERNEL_VALUES = 1 << 20


def blocks(n_rows: int, cost_per_row: int, budget: int = PRODUCT_TERMS) -> Iterator[slice]:
    """Yield consecutive slices of ``n_rows`` rows (or columns), each about ``budget`` work.

    Parameters
    ----------
    n_rows : int
        Rows to cover (>= 0).
    cost_per_row : int
        Work of one row, in the unit of ``budget`` (multiply-adds, values).
    budget : int
        Work per chunk: :data:`PRODUCT_TERMS` or :data:`KERNEL_VALUES`.

    Yields
    ------
    slice
        ``slice(start, stop)``, together covering ``0 .. n_rows`` once, in order.
    """
    step = max(1, int(budget) // max(int(cost_per_row), 1))
    for start in range(0, n_rows, step):
        yield slice(start, min(start + step, n_rows))


def matmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return ``a @ b`` for 2-D float arrays, in row blocks of ``a`` (Ctrl-C between them).

    Parameters
    ----------
    a : numpy.ndarray, shape (n, k)
    b : numpy.ndarray, shape (k, m)

    Returns
    -------
    numpy.ndarray, shape (n, m)
        The product; each entry summed over all k terms in one BLAS call, as unchunked.
    """
    n, k = a.shape
    m = b.shape[1]
    out = np.empty((n, m), dtype=np.result_type(a, b))
    for rows in blocks(n, k * m):
        np.matmul(a[rows], b, out=out[rows])
    return out


def gram(a: np.ndarray) -> np.ndarray:
    """Return ``a.T @ a`` for a 2-D float array, summed over row blocks of ``a``.

    Parameters
    ----------
    a : numpy.ndarray, shape (P, M)

    Returns
    -------
    numpy.ndarray, shape (M, M)
        The cross-products ``G[i, j] = sum_p a[p, i] a[p, j]``: one BLAS call when P M^2
        is within :data:`PRODUCT_TERMS` (the same values as ``a.T @ a``), else the sum of
        the blocks' products (equal to rounding: the terms are added in another order).
    """
    p, m = a.shape
    chunks = list(blocks(p, m * m))
    if len(chunks) <= 1:
        return a.T @ a
    out = np.zeros((m, m), dtype=a.dtype)
    part = np.empty_like(out)
    for rows in chunks:
        block = a[rows]
        np.matmul(block.T, block, out=part)
        out += part
    return out
