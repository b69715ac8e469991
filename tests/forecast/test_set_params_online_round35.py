"""Round 35 PART a (issue 27, T1, S1, S2): hyper-parameters changed after ``fit``.

References: (1) a predictor built with the same hyper-parameters from the start and
fitted on the same frames (the same question asked by another road: ``set_params``
then ``predict`` must answer as the predictor the parameters describe); (2) ``predict``
for the online path (the module's promise: ``reset`` then one ``update`` per sample
equals ``predict`` bit for bit); (3) an independent NumPy recursion for the linear
predictor's forecasts (x_hat[t + h] = x[t] + h (x[t] - x[t - 1]) for a = 2, b = -1).

Before the fixes: ``set_params(window=300)`` after a fit on 600 frames left the refits on
600 frames while ``refit_every`` set the same way applied at once (S2); after
``set_params(horizon=5)`` ``update`` kept returning 3 steps while ``predict`` returned
5 (S1); after ``set_params(refit_every=None)`` mid-pass the next ``update`` raised
``TypeError: unsupported operand type(s) for %`` (T1).
"""

import numpy as np
import pytest

from modalinfo.forecast import ARMAPredictor, LinearPredictor, MultivariatePredictor


def _ar1(n: int, m: int, phi: float = 0.7, seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n, m))
    x = np.zeros((n, m))
    for t in range(1, n):
        x[t] = phi * x[t - 1] + e[t]
    return x


X = _ar1(900, 2)

MAKERS = [
    lambda **kw: LinearPredictor(fit_weights=True, **kw),
    lambda **kw: ARMAPredictor(order=(2, 1), **kw),
    lambda **kw: MultivariatePredictor(order=2, **kw),
]


@pytest.mark.parametrize("make", MAKERS)
def test_window_set_after_fit_is_the_window_used(make):
    late = make(horizon=2).fit(X[:600])
    late.set_params(refit_every=50, window=300)
    built = make(horizon=2, refit_every=50, window=300).fit(X[:600])
    np.testing.assert_array_equal(late.predict(X[:900]), built.predict(X[:900]))


@pytest.mark.parametrize("make", MAKERS)
@pytest.mark.parametrize("change", [{"horizon": 5}, {"refit_every": None},
                                    {"window": 250}])
def test_update_after_a_change_is_refused_then_reset_follows_predict(make, change):
    p = make(horizon=3, refit_every=50, window=200).fit(X[:400])
    for x in X[:120]:
        p.update(x)
    p.set_params(**change)
    name = next(iter(change))
    with pytest.raises(ValueError, match=rf"`{name}`.*reset\(\)"):
        p.update(X[120])
    p.reset()
    for x in X[:500]:
        online = p.update(x)
    np.testing.assert_array_equal(online, p.predict(X[:500]))
    assert online.shape == (p.horizon, 2)


def test_horizon_set_after_fit_online_against_numpy():
    p = LinearPredictor(horizon=2).fit(X[:300])
    p.set_params(horizon=4)
    p.reset()
    for x in X[:300]:
        online = p.update(x)
    h = np.arange(1, 5)[:, None]
    want = X[299] + h * (X[299] - X[298])
    np.testing.assert_allclose(online, want, rtol=1e-12, atol=1e-12)
