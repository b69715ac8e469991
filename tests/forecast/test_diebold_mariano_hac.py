"""Diebold-Mariano statistic of ``evaluate``: the EWC formula of the literature.

Reference: the equal-weighted cosine (EWC) test of Lazarus, Lewis, Stock & Watson
(2018, J. Bus. Econ. Stat. 36, 541, eq. 4 and their rule ``B = 0.4 N^(2/3)``), written
out here with an explicit cosine matrix: on the loss differential d_t recomputed from
the stored forecasts and the observed frames (summed squared error of the predictor
minus that of the best trivial baseline), ``Lambda_j = sqrt(2 / N) sum_t cos(pi j
(t - 1/2) / N) d_t``, ``Omega = mean_(j=1..B) Lambda_j^2``, ``DM = sqrt(N) mean(d) /
sqrt(Omega)``, p-value ``scipy.stats.t.cdf(DM, B)``. The differential here is short-memory
(lag-1 autocorrelation ~0.1), so the documented AR(1) plug-in keeps LLSW's B.
"""

import numpy as np
import pytest
from scipy import stats
from scipy.signal import lfilter

from modalinfo.forecast import ARMAPredictor, evaluate


def ewc(d: np.ndarray, b: int) -> float:
    n = d.size
    t = np.arange(1, n + 1)
    cos = np.cos(np.pi * np.arange(1, b + 1)[:, None] * (t[None, :] - 0.5) / n)
    lam = np.sqrt(2.0 / n) * cos @ d
    return float(np.sqrt(n) * d.mean() / np.sqrt(np.mean(lam**2)))


def test_dm_statistic_equals_the_ewc_formula():
    rng = np.random.default_rng(31)
    # two modes, AR(1)-like with MA(1) errors: the loss differential is autocorrelated
    x = lfilter([1.0, 0.6], [1.0, -0.5], rng.standard_normal((3000, 2)), axis=0)
    ev = evaluate({"arma": ARMAPredictor(order=(1, 1))}, x, train=1500, horizons=[1],
                  keep_series=5000)
    n = ev.origins.size
    assert ev.one_step.shape[1] == n  # every origin kept: the losses can be recomputed
    target = ev.truth[1 : n + 1]
    loss = {name: np.sum((target - ev.one_step[ev.index(name)]) ** 2, axis=1)
            for name in ev.names}
    d = loss["arma"] - loss[ev.baseline[0]]
    b = int(np.floor(0.4 * n ** (2.0 / 3.0)))
    i = ev.index("arma")
    assert ev.dm_statistic[i, 0] == pytest.approx(ewc(d, b), rel=1e-9)
    assert ev.pvalue[i, 0] == pytest.approx(stats.t.cdf(ewc(d, b), b), rel=1e-9)
    # the number of terms matters: one fewer is another statistic on this series
    assert abs(ewc(d, b - 1) - ewc(d, b)) > 1e-6 * abs(ewc(d, b))
