"""``_lag_qr``'s row blocks when the history is longer than one block (review32, round 32).

Planted-bug review of fix49-b: every fix49-b log (400-3,000 rows of at most 6 x 4 lag
columns) fits in one row block (``2^18 / n`` rows), so a triangle not carried into the
next block (R32-B1: ``block[:R.shape[0]] = 0``) passed every test. Here the block size
is shrunk (``_QR_ELEMENTS``, read at each call) so a 600-row history is many blocks.
Reference: ``numpy.linalg.qr`` of the whole ``[Z / scale, Y]`` (its R, up to the sign of
each row), and the ridge weights by ``numpy.linalg.solve`` of the normal equations
``(Zs^T Zs + alpha I) Bs = Zs^T Y`` at the chosen alpha, which is also the argmin of the
GCV score computed here with ``numpy.linalg.svd`` of the whole ``Zs``.
"""

import numpy as np
import pytest

from modalinfo.forecast import multivariate as mv


def _history(T=600, M=3, seed=2):
    rng = np.random.default_rng(seed)
    x = np.zeros((T, M))
    for t in range(1, T):
        x[t] = 0.7 * x[t - 1] + rng.standard_normal(M)
    return x - x.mean(axis=0)


@pytest.mark.parametrize("elements", [64, 1000, 2 ** 18])
def test_r_of_many_blocks_is_numpys(monkeypatch, elements):
    monkeypatch.setattr(mv, "_QR_ELEMENTS", elements)
    Z, Y = mv._lagged(_history(), 3)
    scale = np.sqrt(np.sum(Z ** 2, axis=0))
    R = mv._lag_qr(Z, Y, scale)
    ref = np.linalg.qr(np.column_stack([Z / scale, Y]), mode="r")
    assert np.allclose(np.abs(R), np.abs(ref), rtol=1e-9, atol=1e-12 * np.abs(ref).max())


@pytest.mark.parametrize("elements", [64, 2 ** 18])
def test_gcv_choice_and_weights_of_many_blocks(monkeypatch, elements):
    monkeypatch.setattr(mv, "_QR_ELEMENTS", elements)
    Z, Y = mv._lagged(_history(), 3)
    scale = np.sqrt(np.sum(Z ** 2, axis=0))
    alpha, Bs = mv._gcv_ridge(Z, Y, scale)
    Zs = Z / scale
    n, k = Zs.shape
    s = np.linalg.svd(Zs, compute_uv=False)
    scores = {}
    for a in mv.GCV_GRID:
        H = Zs @ np.linalg.solve(Zs.T @ Zs + a * np.eye(k), Zs.T)
        rss = np.sum((Y - H @ Y) ** 2)
        dof = n - np.sum(s * s / (s * s + a)) if a > 0 else n - k
        scores[a] = n * rss / dof ** 2
    assert alpha == min(scores, key=scores.get)
    expected = np.linalg.solve(Zs.T @ Zs + alpha * np.eye(k), Zs.T @ Y)
    assert np.allclose(Bs, expected, rtol=1e-8, atol=1e-10 * np.abs(expected).max())


@pytest.mark.parametrize("order, n_modes", [(2, 10), (4, 27), (8, 27)])
def test_gcv_memory_beyond_fixed_alpha_does_not_grow_with_the_history(order, n_modes):
    # R32-B7 (fit_bytes' block rows min(T, ...) -> max(T, ...)): fit_bytes' docstring,
    # "a block of min(T, max(n, 2^18 / n)) + n rows of n = (order + 1) M columns ... and
    # two n x n triangles, whatever T: 2-4 MiB up to n = 512"
    gcv = mv.MultivariatePredictor(order=order, alpha="gcv")
    fixed = mv.MultivariatePredictor(order=order, alpha=1e-3)
    extra = [gcv.fit_bytes(T, n_modes) - fixed.fit_bytes(T, n_modes)
             for T in (40_000, 400_000)]
    assert extra[0] == extra[1]
    assert 2 * 2 ** 20 <= extra[0] <= 4 * 2 ** 20
