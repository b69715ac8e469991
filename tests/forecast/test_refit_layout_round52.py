"""A refit that moves the ARMA orders at the same p + q rebuilds the running state (fix52-d).

The running state of the recursion holds ``p`` AR lags then ``q`` innovations (``p + q +
1`` columns): a refit from ARMA(2, 4) to ARMA(3, 3) keeps its size, so the state's shape
alone (the test of round 34 PART a, L01-L02) let the recursion carry on and read the old
innovations as AR lags. Found when the order search's fix (fix52-d) made
``test_refit_round34.py``'s grow case pick (2, 4) then (3, 3): 94 % off its reference.

Reference: the independent NumPy innovations recursion of ``test_refit_round34.py``
(Brockwell & Davis sec. 3.3 and 5.2, zero lags at the first sample of the refit window),
with the parameters the refit chose. The predictor's orders are scripted (ARMA(2, 4) at
``fit``, then ARMA(3, 3) and (2, 4) in turn at the refits) so the case does not hang on
what a search selects. (A refit that keeps the orders carries on from its state, as
documented, and is not compared with a zero start.)
"""

import numpy as np

from modalinfo.forecast import ARMAPredictor
from tests.forecast.test_refit_round34 import _arma_path

R, W, H = 50, 300, 3


class _Scripted(ARMAPredictor):
    """ARMA(2, 4) at ``fit``, then (3, 3) and (2, 4) in turn at the refits."""

    def _fit_params(self, X, previous, name):
        order = (3, 3) if previous is not None and previous["phi"].shape[1] == 2 else (2, 4)
        return ARMAPredictor(order=order, burn_in=self.burn_in)._fit_params(X, None, name)


def test_refit_to_another_layout_of_the_same_size_forecasts_with_the_new_model():
    rng = np.random.default_rng(52)
    e = rng.standard_normal(700)
    x = np.zeros(700)
    for t in range(2, 700):
        x[t] = 1.5 * x[t - 1] - 0.7 * x[t - 2] + e[t] + 0.5 * e[t - 1]
    p = _Scripted(order=(2, 4), refit_every=R, window=W, horizon=H).fit(x[:W])
    assert tuple(p.orders_[0]) == (2, 4)
    p.reset()
    checked = 0
    for t in range(len(x)):
        f = p.update(x[t])
        if t >= W and (t + 1) % R == 7:                  # 7 frames after a refit
            r = t - 7
            prm = p._run.params
            assert tuple(prm["orders"][0]) == ((3, 3), (2, 4))[(r + 1 - W) // R % 2]
            ref = _arma_path(x[r + 1 - W:t + 1], prm["mu"][0], prm["phi"][0],
                             prm["theta"][0], H)
            np.testing.assert_allclose(f, ref, rtol=1e-10, atol=1e-12)
            checked += 1
    assert checked >= 6
