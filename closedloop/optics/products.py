"""The loop's large dense matrix-vector products, in float32 above a size.

Two dense products grow with a 4-m system every frame: the reconstructor (modes x
measurements, 1,500 x 2,900 for a DKIST-like 43 x 43 Shack-Hartmann) and an actuator
mirror's modal-to-command matrix ``m2c`` (1,584 x 1,500). Both stream their matrix from
memory each frame (35 MB and 19 MB in float64, far beyond the caches), so their cost is
memory traffic: measured 3.0 and 0.92 ms of CPU in float64, 0.95 and 0.42 ms in float32
(``benchmarks/RESULTS.md``, "4-m loop").

**Float32 changes nothing the loop reports.** A float32 product of an ``n``-term row
has a relative error of order ``sqrt(n) 2^-24`` (3e-6 at n = 2,900) of ``|A| |x|``; in
the loop it is an error in the measured modal residual (and in the strokes), which the
integrator filters like measurement noise. At the 4-m size it moves the residual phase
variance by less than 1e-5 of itself (the benchmark's same-seed comparison), while the
WFS noise, aliasing and the frame-to-frame spread of the residual are 1e-2 to 1 of it.
Only loops with a mirror whose kind asks for it
(``DeformableMirror.large_products``: the actuator DM) switch; every other loop keeps
its float64 products and SVDs whatever their size, so the earlier presets keep their
bits (the error-budget probe's ideal-sensor model of table1 has an 11.9 MB reconstructor,
above the threshold: it moved fig7's budget terms by 2e-6 before this rule).

The reconstructors themselves are truncated pseudo-inverses; above :data:`GRAM_MIN_BYTES`
:func:`gram_pinv` takes them through the eigen-decomposition of the Gram matrix
``A^T A`` (a symmetric rank-k update and an ``n x n`` ``eigh``) instead of the SVD of
``A``: 1.1 against 3.3 s of CPU for a 2,882 x 1,500 interaction matrix. Squaring the
matrix squares its condition number, but the reconstructors keep only singular values
above 1e-3 of the largest, so the kept eigenvalues are >= 1e-6 of the largest and
their rounding (``eps`` of the largest) is <= 2.2e-10 of each: measured 2.4e-11 of
the largest entry against ``numpy.linalg.pinv`` (``tests/closedloop/test_dense_products.py``).
"""

from __future__ import annotations

import numpy as np

__all__ = ["DenseProduct", "FLOAT32_MIN_BYTES", "GRAM_MIN_BYTES", "gram_pinv", "svd_pinv"]

#: float64 size [bytes] from which a product runs in float32 (8 MB: beyond a core's L2
#: and this machine's share of L3, where the product is bound by memory traffic)
FLOAT32_MIN_BYTES = 8_000_000
#: float64 size [bytes] of a matrix from which its truncated pseudo-inverse is taken
#: through its Gram matrix (in loops with ``large_products`` mirrors only)
GRAM_MIN_BYTES = 8_000_000


def gram_pinv(a: np.ndarray, cut, *, return_sv: bool = False) -> tuple:
    """Return the truncated pseudo-inverse, through the eigen-decomposition of A^T A.

    Parameters
    ----------
    a : (m, n) ndarray
        The matrix (float64).
    cut : callable
        ``cut(sv_max) -> threshold``: singular values ``> threshold`` are kept (e.g.
        ``lambda s0: 1e-3 * s0``, ``numpy.linalg.pinv``'s ``rcond`` rule).

    Returns
    -------
    pinv : (n, m) ndarray
        ``V_k S_k^-1 U_k^T`` over the kept singular values.
    n_kept : int
    sv : ndarray
        With ``return_sv``: the singular values, descending (from the eigenvalues).
    """
    if a.shape[0] < a.shape[1]:  # the smaller Gram matrix: pinv(A) = pinv(A^T)^T
        p, k, sv = gram_pinv(a.T, cut, return_sv=True)
        p = np.ascontiguousarray(p.T)
        return (p, k, sv) if return_sv else (p, k)
    w, v = np.linalg.eigh(a.T @ a)  # ascending
    w, v = w[::-1], v[:, ::-1]
    sv = np.sqrt(np.clip(w, 0.0, None))
    keep = sv > cut(sv[0])
    vk = v[:, keep]
    p = (vk / w[keep]) @ (vk.T @ a.T)
    return (p, int(keep.sum()), sv) if return_sv else (p, int(keep.sum()))


def svd_pinv(a: np.ndarray, rcond: float) -> tuple[np.ndarray, int]:
    """Return ``numpy.linalg.pinv(a, rcond)`` and how many singular values it kept.

    The same steps as numpy's (its SVD, its cut ``s > rcond * s_max``, its product), so
    the same matrix to the last bit; the count is what ``pinv`` does not return.

    Returns
    -------
    pinv : (n, m) ndarray
    n_kept : int
    """
    if a.size == 0:
        return np.linalg.pinv(a, rcond=rcond), 0
    u, s, vt = np.linalg.svd(a, full_matrices=False)
    large = s > rcond * np.amax(s)
    s_inv = np.divide(1.0, s, where=large, out=np.zeros_like(s))
    return np.matmul(vt.T, np.multiply(s_inv[:, None], u.T)), int(large.sum())


class DenseProduct:
    """``y = A x`` with ``A`` held in float32 when its float64 form is large.

    Parameters
    ----------
    matrix : (m, n) array_like
        ``A`` (kept as given when small, as a float32 copy when its float64 size is at
        least ``min_bytes``).
    min_bytes : float or None
        The size threshold [bytes]; None: :data:`FLOAT32_MIN_BYTES` as it is when the
        product is made (``inf``: always float64).

    Attributes
    ----------
    single : bool
        Whether the product runs in float32.
    """

    def __init__(self, matrix, min_bytes: float | None = None):
        if min_bytes is None:
            min_bytes = FLOAT32_MIN_BYTES
        a = np.asarray(matrix, dtype=np.float64)
        self.single = a.ndim == 2 and 8.0 * a.size >= min_bytes
        self.matrix = np.ascontiguousarray(a, dtype=np.float32) if self.single else a

    def __call__(self, x: np.ndarray) -> np.ndarray:
        """Return ``A x`` as float64 ``(m,)``."""
        if self.single:
            return (self.matrix @ np.asarray(x, dtype=np.float32)).astype(np.float64)
        return self.matrix @ x
