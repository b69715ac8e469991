"""Diebold-Mariano statistic at a horizon whose h - 1 exceeds the Newey-West rule's lag.

Reference: ``statsmodels`` OLS on a constant with ``cov_type="HAC"`` (Newey-West,
Bartlett kernel, no small-sample correction) and ``maxlags = h - 1``, the lag an
h-step forecast error's MA(h - 1) structure needs (Diebold & Mariano 1995, J. Bus.
Econ. Stat. 13, 253, Sect. 1.1), and with ``kernel="uniform"`` (their rectangular
window, the larger of the two is used), times Harvey, Leybourne & Newbold's (1997)
factor, against Student's t with N - 1 degrees of freedom; the lag is the one the rule
``max(h - 1, floor(4 (N / 100)^(2/9)))`` picks when h - 1 is the larger. The loss
differential is recomputed from the stored h-step forecasts (``one_step`` holds the
first horizon's forecasts, here the only one) and the observed frames. The companion
test at h = 1 (``test_diebold_mariano_hac.py``) has the rule's ``floor`` term larger
than h - 1, so it cannot tell h - 1 from h.
"""

import numpy as np
import pytest
import statsmodels.api as sm
from scipy import stats
from scipy.signal import lfilter

from modalinfo.forecast import LinearPredictor, evaluate

H = 12


def test_dm_statistic_at_a_long_horizon_uses_lag_h_minus_1():
    rng = np.random.default_rng(5)
    x = lfilter([1.0, 0.6], [1.0, -0.9], rng.standard_normal((900, 2)), axis=0)
    ev = evaluate({"linear": LinearPredictor(a=1.5, b=-0.5, horizon=H)}, x, train=500,
                  horizons=[H],
                  keep_series=5000)
    n = ev.origins.size
    rule = int(np.floor(4 * (n / 100.0) ** (2.0 / 9.0)))
    assert H - 1 > rule  # the case this test is for: the horizon sets the lag
    assert ev.one_step.shape[1] == n
    target = ev.truth[H : n + H]
    loss = {name: np.sum((target - ev.one_step[ev.index(name)]) ** 2, axis=1)
            for name in ev.names}
    d = loss["linear"] - loss[ev.baseline[0]]
    i = ev.index("linear")

    def se(lag, kernel):
        return sm.OLS(d, np.ones(n)).fit(cov_type="HAC", cov_kwds={
            "maxlags": lag, "kernel": kernel, "use_correction": False}).bse[0]

    def dm(lag):  # the larger of the Bartlett and rectangular variances, HLN's factor
        hln = np.sqrt((n + 1 - 2 * H + H * (H - 1) / n) / n)
        return d.mean() / max(se(lag, "bartlett"), se(lag, "uniform")) * hln

    assert ev.dm_statistic[i, 0] == pytest.approx(dm(H - 1), rel=1e-9)
    assert ev.pvalue[i, 0] == pytest.approx(stats.t.cdf(dm(H - 1), n - 1), rel=1e-9)
    # one lag more is another statistic on this series, beyond the tolerance above
    assert abs(dm(H) - dm(H - 1)) > 1e-6 * abs(dm(H - 1))


def test_the_test_keeps_its_size_on_equally_good_h_step_forecasts():
    # audit 9 (issue 27): with Bartlett weights alone and the normal law the one-sided
    # test at a nominal 5 % rejected 8-9 % of true nulls at h = 5-10 even at N = 2000
    # and 17-21 % at N = 20 (the weights under-count the MA(h - 1) covariances of h-step
    # errors). Reference: the nominal level itself. Two forecasts of the sum of the next
    # h white-noise innovations with independent, equally large errors (each error is
    # itself such a sum, MA(h - 1)): every rejection is a false claim of skill. 800
    # draws: the binomial standard deviation at 5 % is 0.8 %.
    from modalinfo.forecast.evaluate import _dm_test

    rng = np.random.default_rng(11)
    n, h, draws = 300, 8, 800
    rejected = 0
    for _ in range(draws):
        e = rng.standard_normal((2, n + h - 1, 2))
        err = lfilter(np.ones(h), [1.0], e, axis=1)[:, h - 1 :]   # (2, n, 2) MA(h - 1)
        loss = np.sum(err**2, axis=2)
        rejected += _dm_test(loss[0] - loss[1], h)[1] < 0.05
    assert rejected / draws < 0.075   # 0.059; Bartlett-normal: 0.086 on these draws
