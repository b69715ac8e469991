"""Transfer-entropy map with a target history longer than the largest source lag.

Reference: the Gaussian TE from source j at lag l to target i with history k is the
partial correlation's ``-1/2 ln(1 - rho^2)`` (Barnett, Barrett & Seth 2009, Phys. Rev.
Lett. 103, 238701: Granger causality = 2 TE for Gaussian variables), computed here with
``numpy.linalg.lstsq``: ``x_i[t]`` and ``x_j[t - l]`` regressed on ``(1, x_i[t - 1], ...,
x_i[t - k])`` over the module's common rows ``t = t0 .. T - 1`` with ``t0 = max(max(lags),
k)``, and their residuals correlated. The other flow tests use ``history <= max(lags)``,
where ``t0 = max(lags)`` alone is the same; here ``k = 3 > 2``.
"""

import numpy as np
import pytest

from modalinfo.information import transfer_entropy_map

LAGS = [1, 2]
HISTORY = 3


def _gaussian_te(x: np.ndarray, j: int, i: int, lag: int, k: int, t0: int) -> float:
    n = x.shape[0]
    rows = np.arange(t0, n)
    past = np.column_stack([np.ones(rows.size)] + [x[rows - d, i] for d in range(1, k + 1)])

    def residual(v):
        return v - past @ np.linalg.lstsq(past, v, rcond=None)[0]

    a, b = residual(x[rows, i]), residual(x[rows - lag, j])
    rho = a @ b / np.sqrt((a @ a) * (b @ b))
    return -0.5 * np.log(1.0 - rho * rho)


def test_long_history_map_is_the_partial_correlation_te():
    rng = np.random.default_rng(4)
    e = rng.standard_normal((800, 3))
    x = np.zeros_like(e)
    for t in range(3, 800):
        x[t, 0] = 0.5 * x[t - 1, 0] + e[t, 0]
        x[t, 1] = 0.4 * x[t - 3, 1] + 0.6 * x[t - 2, 0] + e[t, 1]   # 0 -> 1 at lag 2
        x[t, 2] = 0.3 * x[t - 1, 2] + e[t, 2]
    flow = transfer_entropy_map(x, lags=LAGS, history=HISTORY, n_surrogates=19, seed=0)
    t0 = max(max(LAGS), HISTORY)
    for j, i in [(0, 1), (1, 0), (2, 1)]:
        for a, lag in enumerate(LAGS):
            want = _gaussian_te(x, j, i, lag, HISTORY, t0)
            assert flow.te[j, i, a] == pytest.approx(want, rel=1e-8, abs=1e-12), (j, i, lag)
    assert flow.te[0, 1, 1] > 0.1  # the planted link
