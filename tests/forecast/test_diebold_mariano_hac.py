"""Diebold-Mariano statistic of ``evaluate`` against statsmodels' HAC variance.

Reference: the DM statistic recomputed from the stored one-step forecasts and the
observed frames: the loss differential d_t (summed squared error of the predictor
minus that of the best trivial baseline) regressed on a constant with
``statsmodels`` OLS and ``cov_type="HAC"`` (Newey-West, Bartlett kernel, ``maxlags``
the documented lag ``max(h - 1, floor(4 (N / 100)^(2/9)))``, no small-sample
correction), or the iid one (the rectangular window of lag h - 1 = 0, Diebold &
Mariano 1995) where it is larger: DM = mean(d) / se(mean) times Harvey, Leybourne &
Newbold's (1997) factor sqrt((N + 1 - 2h + h (h - 1) / N) / N); the p-value against
``scipy.stats.t.cdf`` with N - 1 degrees of freedom.
"""

import numpy as np
import pytest
import statsmodels.api as sm
from scipy import stats
from scipy.signal import lfilter

from modalinfo.forecast import ARMAPredictor, evaluate


def test_dm_statistic_equals_statsmodels_hac():
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
    base = ev.baseline[0]
    d = loss["arma"] - loss[base]
    lag = max(0, int(np.floor(4 * (n / 100.0) ** (2.0 / 9.0))))
    fit = sm.OLS(d, np.ones(n)).fit(cov_type="HAC",
                                     cov_kwds={"maxlags": lag, "use_correction": False})
    # the rectangular window of lag h - 1 = 0 is the iid variance; the larger is used
    se = max(fit.bse[0], d.std() / np.sqrt(n))
    dm = fit.params[0] / se * np.sqrt((n - 1) / n)  # HLN factor at h = 1
    i = ev.index("arma")
    assert ev.dm_statistic[i, 0] == pytest.approx(dm, rel=1e-9)
    assert ev.pvalue[i, 0] == pytest.approx(stats.t.cdf(dm, n - 1), rel=1e-9)
    # the choice matters here: the Bartlett variance alone gives another statistic
    bartlett = fit.params[0] / fit.bse[0] * np.sqrt((n - 1) / n)
    assert abs(bartlett - dm) > 0.05 * abs(dm)
