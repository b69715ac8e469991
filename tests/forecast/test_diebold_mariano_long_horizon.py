"""Diebold-Mariano statistic at a horizon whose h - 1 exceeds the Newey-West rule's lag.

Reference: ``statsmodels`` OLS on a constant with ``cov_type="HAC"`` (Newey-West,
Bartlett kernel, no small-sample correction) and ``maxlags = h - 1``, the lag an
h-step forecast error's MA(h - 1) structure needs (Diebold & Mariano 1995, J. Bus.
Econ. Stat. 13, 253, Sect. 1.1), which the documented rule
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

    def dm(lag):
        fit = sm.OLS(d, np.ones(n)).fit(cov_type="HAC",
                                         cov_kwds={"maxlags": lag, "use_correction": False})
        return fit.params[0] / fit.bse[0]

    assert ev.dm_statistic[i, 0] == pytest.approx(dm(H - 1), rel=1e-9)
    assert ev.p_value[i, 0] == pytest.approx(stats.norm.cdf(dm(H - 1)), rel=1e-9)
    # one lag more is another statistic on this series, beyond the tolerance above
    assert abs(dm(H) - dm(H - 1)) > 1e-6 * abs(dm(H - 1))
