"""GCV's row-block QR holds the ``n x n`` triangle and a 2 MiB block, not a ``2n x n`` one.

fix49-b's ``_lag_qr`` stacked the triangle on ``max(n, 2^18 / n)`` rows and factorised the
whole block, copying each block's lags through the constant-mode mask: beyond ``n = 512``
columns the block was ``2n x n`` (64 MB for Figure 6's 400-mode VAR(4) latency fit, whose
``_gcv_ridge`` peaked at 131 MB in tracemalloc; 88 MB now, 38 MB of it ``_lag_qr``'s).
``_lag_qr`` now folds blocks of at most ``2^18`` elements into the triangle with
LAPACK's ``tpqrt`` (stop 56's left item, fix50-b).

References: stop 55's SVD path (one SVD of the scaled lags, kept verbatim in
tests/forecast/test_gcv_qr_fix49b.py; pinned against ``numpy.linalg.lstsq``'s GCV by
tests/forecast/test_multivariate_gcv_fixes48.py) for GCV's choice and weights, with a
constant mode among 200 (the mask path) and ``n = 1000`` columns; and the footprint
written out here, ``8 (n^2 + 2 x 2^18 + 64 n)`` bytes (the triangle, the block and the
mask's copy of it, ``tpqrt``'s ``T``), with a 2x margin, for tracemalloc's peak of
``_lag_qr`` (at this size 12.6 MB, the footprint's 12.6; fix49-b's 32.7 MB, above the
bound's 25.2).
"""

import tracemalloc

import numpy as np

from modalinfo.forecast.multivariate import _gcv_ridge, _lag_qr, _lagged

from .test_gcv_qr_fix49b import _gcv_ridge_svd

M, ORDER, T = 200, 4, 2500


def _lags():
    rng = np.random.default_rng(50)
    x = rng.standard_normal((T + ORDER, M)) + 0.05 * np.cumsum(
        rng.standard_normal((T + ORDER, M)), axis=0)
    x[:, 7] = 3.0  # a constant mode: its lags and target are left out by the masks
    Z, Y = _lagged(x - x.mean(axis=0), ORDER)
    keep, targets = np.ptp(Z, axis=0) > 0, np.ptp(Y, axis=0) > 0
    return Z, Y, keep, targets, np.linalg.norm(Z[:, keep], axis=0)


def test_gcv_chooses_and_weighs_as_the_svd_path():
    Z, Y, keep, targets, scale = _lags()
    assert keep.sum() + targets.sum() == 995  # n > 512: the regime of the 2n x n block
    alpha, B = _gcv_ridge(Z, Y, scale, keep, targets)
    alpha_ref, B_ref = _gcv_ridge_svd(Z[:, keep] / scale, Y[:, targets])
    assert alpha == alpha_ref
    assert np.abs(B - B_ref).max() <= 1e-12 * np.abs(B_ref).max()


def test_the_qr_holds_the_triangle_and_one_block():
    Z, Y, keep, targets, scale = _lags()
    n = int(keep.sum() + targets.sum())
    tracemalloc.start()
    try:
        R = _lag_qr(Z, Y, scale, keep, targets)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert R.shape == (n, n)
    footprint = 8 * (n * n + 2 * 2 ** 18 + 64 * n)
    assert peak <= 2 * footprint, (peak, footprint)
