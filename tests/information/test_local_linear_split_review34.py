"""``neighbour_rows`` and ``local_linear_split`` against brute force (review34, round 34).

fix51-a's surrogate parts (``information.resampling``): each row's ``k`` nearest other
rows in z under the maximum norm (on normal scores ``Phi^-1(rank / (n + 1))`` for a rank-
based estimator, on values scaled to unit s.d. otherwise), and y's least-squares fit on z
and a constant plus, at each row, a least-squares line (fix51-d; a constant and z's
columns scaled to unit s.d., centred on the row: on the values since fix52-c, in the
neighbours' metric before) through that fit's residual over
those rows, the local mean where z has more than 4 columns. References, outside the
package: the pairwise maximum-norm distances by numpy broadcasting, the scores by
``scipy.stats.rankdata`` and ``scipy.special.ndtri``, the fits by ``numpy.linalg.lstsq``
one row at a time.
Continuous random data: the neighbours' distances are the k smallest (the scores' grid can
tie two distances, so distances are compared, not row numbers); two z columns of very
different scales, where the maximum and the Euclidean norm, or scaled and unscaled
columns, pick different neighbours.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtri
from scipy.stats import rankdata

from modalinfo.information.resampling import (
    LOCAL_FIT_NEIGHBOURS,
    local_linear_split,
    neighbour_rows,
)


def _z(n: int = 150, seed: int = 34) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.column_stack([rng.normal(size=n), 100.0 * rng.standard_t(3, size=n)])


def _distances(z: np.ndarray, rank_based: bool) -> np.ndarray:
    n = z.shape[0]
    if rank_based:
        s = np.column_stack([ndtri(rankdata(c) / (n + 1.0)) for c in z.T])
    else:
        s = z / z.std(axis=0)
    d = np.abs(s[:, None, :] - s[None, :, :]).max(axis=2)
    np.fill_diagonal(d, np.inf)
    return d


def _brute(z: np.ndarray, rank_based: bool, k: int) -> np.ndarray:
    return np.argsort(_distances(z, rank_based), axis=1, kind="stable")[:, :k]


@pytest.mark.parametrize("rank_based", [True, False])
@pytest.mark.parametrize("k", [LOCAL_FIT_NEIGHBOURS, 5])
def test_neighbour_rows_are_the_maximum_norm_nearest_others(rank_based, k):
    z = _z()
    got = neighbour_rows(z, rank_based, k)
    assert got.shape == (z.shape[0], k)
    d = _distances(z, rank_based)
    # the k smallest distances (scores lie on a grid, so two distances may tie: the
    # distances, not the row numbers, are unique)
    np.testing.assert_allclose(np.sort(np.take_along_axis(d, got, axis=1), axis=1),
                               np.sort(d, axis=1)[:, :k], rtol=0, atol=1e-12)
    assert not (got == np.arange(z.shape[0])[:, None]).any()


def test_k_is_cut_to_the_other_rows():
    z = _z(n=4)
    got = neighbour_rows(z, False, 20)
    assert got.shape == (4, 3)
    for i in range(4):
        assert sorted(got[i]) == [j for j in range(4) if j != i]


def test_tied_rows_keep_the_others_and_drop_the_row_itself():
    # 30 rows at one point: every row's 20 neighbours are 20 of the other 29, never itself
    z = np.zeros((30, 1))
    z[25:, 0] = np.arange(1.0, 6.0)
    got = neighbour_rows(z[:25], False, 20)
    assert got.shape == (25, 20)
    assert not (got == np.arange(25)[:, None]).any()


def _space(z: np.ndarray, rank_based: bool) -> np.ndarray:
    n = z.shape[0]
    if rank_based:
        return np.column_stack([ndtri(rankdata(c) / (n + 1.0)) for c in z.T])
    return z / z.std(axis=0)


@pytest.mark.parametrize("rank_based", [True, False])
def test_local_linear_split_is_the_linear_fit_plus_the_neighbours_line(rank_based):
    z = _z()
    rng = np.random.default_rng(3)
    y = (np.sin(0.9 * z[:, :1]) + 0.01 * z[:, 1:] + 0.3 * rng.normal(size=(z.shape[0], 1)))
    a = np.column_stack([np.ones(z.shape[0]), z])
    lin = a @ np.linalg.lstsq(a, y, rcond=None)[0]  # on the values, even rank-based
    resid = y - lin
    near = _brute(z, rank_based, LOCAL_FIT_NEIGHBOURS)
    s = _space(z, False)  # the line's coordinates: values of unit s.d. (fix52-c)
    local = np.empty_like(resid)
    for i in range(z.shape[0]):
        u = np.column_stack([np.ones(near.shape[1]), s[near[i]] - s[i]])
        local[i] = np.linalg.lstsq(u, resid[near[i]], rcond=None)[0][0]
    fit, rest = local_linear_split(y, z, rank_based)
    np.testing.assert_allclose(fit, lin + local, rtol=0, atol=1e-8)
    np.testing.assert_allclose(rest, resid - local, rtol=0, atol=1e-8)
    np.testing.assert_allclose(fit + rest, y, rtol=0, atol=1e-10)


def test_many_columns_take_the_neighbours_mean():
    # 5 columns: 20 neighbours are too few for a line with 6 coefficients (fix51-d)
    rng = np.random.default_rng(5)
    z = rng.normal(size=(120, 5))
    y = np.sin(z[:, :1]) + 0.3 * rng.normal(size=(120, 1))
    a = np.column_stack([np.ones(120), z])
    resid = y - a @ np.linalg.lstsq(a, y, rcond=None)[0]
    local = resid[_brute(z, False, LOCAL_FIT_NEIGHBOURS)].mean(axis=1)
    fit, rest = local_linear_split(y, z, False)
    np.testing.assert_allclose(rest, resid - local, rtol=0, atol=1e-10)


def test_a_tied_y_is_moved_whole():
    z = _z()
    y = np.repeat(np.arange(3.0), 50)[:, None]  # three levels: a residual breaks them
    fit, rest = local_linear_split(y, z, True)
    assert not fit.any()
    assert np.array_equal(rest, y)
