"""``predict`` refuses a history shorter than the predictor's lags (audit 10, feedback,
rows pr-predict-1, mv-predict-1).

Reference: the predictors' definitions. The fixed linear extrapolator forecasts
``x_hat[n + 1] = a x[n] + b x[n - 1]`` (a = 2, b = -1), computed here by hand from the
last two samples: with two samples ``predict`` gives it; with one it answered 2 x[0] (the
missing lag taken as 0) without a word. Persistence needs one sample (``x_hat = x[n]``),
a VAR of order 3 three.
"""

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, MultivariatePredictor, PersistencePredictor


@pytest.fixture(scope="module")
def series():
    return np.cumsum(np.random.default_rng(2).standard_normal((300, 2)), axis=0)


def test_linear_needs_its_two_lags(series):
    p = LinearPredictor(horizon=1).fit(series)
    x = series[:2]
    np.testing.assert_allclose(p.predict(x)[0], 2.0 * x[1] - x[0], rtol=1e-14)
    with pytest.raises(ValueError, match="at least 2 samples.*LinearPredictor.*got 1"):
        p.predict(series[:1])


def test_var_needs_its_order_and_persistence_one_sample(series):
    p = MultivariatePredictor(order=3, horizon=1).fit(series)
    assert p.predict(series[:3]).shape == (1, 2)
    with pytest.raises(ValueError, match="at least 3 samples"):
        p.predict(series[:2])
    q = PersistencePredictor(horizon=2).fit(series)
    np.testing.assert_array_equal(q.predict(series[:1]), np.repeat(series[:1], 2, axis=0))
