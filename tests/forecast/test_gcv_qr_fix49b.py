"""GCV's ridge from the QR factor of ``[Z_s, Y]``, without the ``T x p M`` SVD (fix49-b, issue 27).

Stop 55's ``multivariate`` preset (``alpha="gcv"``) took one economy SVD of the scaled lags
``Z_s`` and kept its ``T x p M`` ``U``: Figure 6's peak RSS went from 0.82 to 1.87 GB.
``_gcv_ridge`` now factorises ``[Z_s, Y]`` by row blocks (tall-skinny QR) and takes the SVD
of the ``p M x p M`` triangle.

References: the stop-55 SVD path, kept here verbatim as ``_gcv_ridge_svd`` (its choice
and weights were pinned against ``numpy.linalg.lstsq`` GCV by
tests/forecast/test_multivariate_gcv_fixes48.py), and ``numpy.linalg.lstsq`` for the
ordinary least squares weights where GCV takes ``alpha = 0``. Logs: a noisy VAR, round
47's smooth open-loop log (condition 8e5), the same with a mode repeated (condition
3e16) and nearly repeated (8e13). Memory: :mod:`tracemalloc`'s peak of ``_gcv_ridge`` on
20,000 x 200 lags against half the size of one ``T x p M`` array (the SVD path's ``U``
alone is one).
"""

import tracemalloc

import numpy as np
import pytest

from modalinfo.forecast import MultivariatePredictor
from modalinfo.forecast.multivariate import _OLS_RCOND, GCV_GRID, _gcv_ridge, _lagged

from .conftest import noisy_var, smooth_log


def _gcv_ridge_svd(Zs, Y):
    """Stop 55's ``_gcv_ridge`` (one SVD of ``Zs``, ``U`` kept): the reference."""
    U, s, Vt = np.linalg.svd(Zs, full_matrices=False)
    uty = U.T @ Y
    rss_out = float(np.sum((Y - U @ uty) ** 2))
    n = Y.shape[0]
    s2 = s * s
    well_conditioned = s.size and s[-1] >= _OLS_RCOND * s[0]
    best = (np.inf, None)
    for alpha in GCV_GRID:
        if alpha == 0.0 and not well_conditioned:
            continue
        f = s2 / (s2 + alpha) if alpha > 0 else np.ones_like(s)
        rss = rss_out + float(np.sum(((1.0 - f)[:, None] * uty) ** 2))
        dof = n - float(np.sum(f))
        score = n * rss / (dof * dof)
        if score < best[0]:
            best = (score, alpha)
    alpha = best[1]
    weight = s / (s2 + alpha)
    return alpha, Vt.T @ (weight[:, None] * uty)


def _logs():
    smooth = smooth_log()
    rng = np.random.default_rng(7)
    near = smooth[:, 0] * (1 + 1e-9) + 1e-12 * rng.standard_normal(len(smooth))
    return {
        "noisy": (noisy_var(400, 1), 4),
        "smooth": (smooth, 4),
        "repeated": (np.column_stack([smooth, smooth[:, 0]]), 4),
        "near-repeated": (np.column_stack([smooth, near]), 4),
    }


LOGS = _logs()


def _scaled(x, order):
    Z, Y = _lagged(x - x.mean(axis=0), order)
    return Z, Y, np.sqrt(np.sum(Z ** 2, axis=0))


@pytest.mark.parametrize("name, alpha", [("noisy", 10 ** -0.5), ("smooth", 0.0),
                                         ("repeated", 1e-10), ("near-repeated", 1e-10)])
def test_qr_path_chooses_and_weighs_as_the_svd_path(name, alpha):
    """Measured: the same alpha on all four; weights within 1.1e-12 of the largest."""
    x, order = LOGS[name]
    Z, Y, norm = _scaled(x, order)
    ref_alpha, ref = _gcv_ridge_svd(Z / norm, Y)
    got_alpha, got = _gcv_ridge(Z, Y, norm)
    assert got_alpha == ref_alpha == alpha
    # the weights of an ill-conditioned ridge are known to cond x eps of their size
    # (condition of Zs^T Zs + alpha I: <= 1e11 here), fits far better
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-10 * np.abs(ref).max())
    np.testing.assert_allclose((Z / norm) @ got, (Z / norm) @ ref, rtol=0,
                               atol=1e-12 * np.abs(Y).max())


def test_alpha_zero_is_ordinary_least_squares():
    """The smooth log (GCV 0): the weights are numpy lstsq's on the scaled lags."""
    x, order = LOGS["smooth"]
    Z, Y, norm = _scaled(x, order)
    alpha, got = _gcv_ridge(Z, Y, norm)
    assert alpha == 0.0
    ref = np.linalg.lstsq(Z / norm, Y, rcond=None)[0]
    np.testing.assert_allclose(got, ref, rtol=0, atol=1e-9 * np.abs(ref).max())


def test_constant_mode_columns_are_left_out_by_mask():
    """A dead mode: the regression on the other columns, as if the mode were absent (the
    column masks ``_gcv_ridge`` now takes row block by row block; passed before too)."""
    x, order = LOGS["smooth"]
    dead = np.column_stack([x[:, :3], np.full(len(x), 2.5), x[:, 3:]])
    with_dead = MultivariatePredictor(order=order, alpha="gcv").fit(dead)
    without = MultivariatePredictor(order=order, alpha="gcv").fit(x)
    assert with_dead.alpha_ == without.alpha_
    live = [0, 1, 2, 4, 5, 6]
    coef = with_dead.coef_[:, live][:, :, live]
    np.testing.assert_allclose(coef, without.coef_, rtol=0,
                               atol=1e-9 * np.abs(without.coef_).max())
    assert not np.any(with_dead.coef_[:, 3]) and not np.any(with_dead.coef_[:, :, 3])


@pytest.mark.parametrize("mask", [False, True])
def test_no_allocation_of_the_lags_size(mask):
    """tracemalloc peak of ``_gcv_ridge`` on 20,000 x 200 lags (50 modes, order 4) below half
    of one 20,000 x 200 float64 array (32 MB): the SVD path's ``U`` is one such array
    (its peak, measured: 48.4 MB); the QR path holds ~2 MiB row blocks (3.7 MB)."""
    rng = np.random.default_rng(3)
    n_rows, n_modes, order = 20_000, 50, 4
    Z = rng.standard_normal((n_rows, order * n_modes))
    Y = rng.standard_normal((n_rows, n_modes))
    norm = np.sqrt(np.sum(Z ** 2, axis=0))
    columns = np.ones(Z.shape[1], bool)
    targets = np.ones(n_modes, bool)
    if mask:
        columns[::n_modes] = False  # mode 0 dead: its lags and target left out
        targets[0] = False
    bound = Z.nbytes // 2
    tracemalloc.start()
    try:
        _gcv_ridge(Z, Y, norm[columns], columns, targets)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < bound, (peak, bound)
