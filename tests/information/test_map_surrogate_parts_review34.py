"""The transfer-entropy map's surrogates are built on the documented parts (review34).

``flow._estimator_map`` (fix51-a) rotates, for each cell, the source's residual on the
target's history and keeps its fit: the linear least-squares fit plus, at each row, a
least-squares line through its residual over the row's 20 nearest other rows of the
history (fix51-d; neighbours in the maximum norm, on normal scores for a rank-based
estimator, on unit-s.d. values otherwise; the line on unit-s.d. values, fix52-c).
References, outside the package: numpy's ``lstsq`` fit,
brute-force maximum-norm neighbours on
``scipy.special.ndtri(scipy.stats.rankdata / (n + 1))`` scores or on values over their
s.d., ``numpy.roll``; the "estimator" is the test's own bilinear statistic ``x . y / n``
(the map's code calls it on the surrogate, so its value is the surrogate's). A 3-series
AR(1) of 300 frames, history 2 (two z columns), seeded: deterministic.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ndtri
from scipy.stats import rankdata

from modalinfo.information.flow import _estimator_map


def _stat(x, y, z):
    return float(x[:, 0] @ y[:, 0]) / x.shape[0]


def _near(z, rank_based, k=20):
    n = z.shape[0]
    s = (np.column_stack([ndtri(rankdata(c) / (n + 1.0)) for c in z.T]) if rank_based
         else z / z.std(axis=0))
    d = np.abs(s[:, None, :] - s[None, :, :]).max(axis=2)
    np.fill_diagonal(d, np.inf)
    return np.argsort(d, axis=1, kind="stable")[:, :k]


def _local_line(resid, z, near):
    """Each row's least-squares line (a constant and z's columns scaled to unit s.d.,
    centred on the row: on the values whatever the neighbours' metric since fix52-c)
    through the residual over its neighbours: its value at the row (fix51-d), by numpy's
    ``lstsq`` one row at a time."""
    n = z.shape[0]
    s = z / z.std(axis=0)
    out = np.empty_like(resid)
    for i in range(n):
        u = np.column_stack([np.ones(near.shape[1]), s[near[i]] - s[i]])
        out[i] = np.linalg.lstsq(u, resid[near[i]], rcond=None)[0][0]
    return out


@pytest.mark.parametrize("rank_based", [True, False])
def test_every_surrogate_is_the_fit_plus_the_rotated_local_residual(rank_based):
    rng = np.random.default_rng(34)
    T, S = 300, 3
    series = np.zeros((T, S))
    e = rng.standard_normal((T, S)) * np.array([1.0, 3.0, 0.3])
    for t in range(1, T):
        series[t] = 0.7 * series[t - 1] + e[t]
    series[:, 1] = np.sinh(series[:, 1])  # a heavy-tailed series: scores differ from values
    lags, history, t0 = np.array([1, 2]), 2, 2
    shifts = np.array([37, 101])
    te, null = _estimator_map(series, lags, history, t0, shifts, _stat, rank_based=rank_based)
    for i in range(S):
        x = series[t0:, i : i + 1]
        z = np.column_stack([series[t0 - h : T - h, i] for h in range(1, history + 1)])
        near = _near(z, rank_based)
        a = np.column_stack([np.ones(z.shape[0]), z])
        for j in range(S):
            if j == i:
                continue
            for g, lag in enumerate(lags):
                y = series[t0 - lag : T - lag, j : j + 1]
                lin = a @ np.linalg.lstsq(a, y, rcond=None)[0]
                local = _local_line(y - lin, z, near)
                fit, resid = lin + local, y - lin - local
                assert te[j, i, g] == pytest.approx(_stat(x, y, z), abs=1e-12)
                for s_i, s in enumerate(shifts):
                    want = _stat(x, fit + np.roll(resid, int(s), axis=0), z)
                    # the local lines are solved two ways (normal equations, lstsq): a
                    # row whose neighbours nearly share a line in z squares its
                    # condition number (4e-10 relative measured)
                    assert null[s_i, j, i, g] == pytest.approx(want, rel=1e-8, abs=1e-9)
