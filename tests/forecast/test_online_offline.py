"""Online (reset + update per sample) and offline (predict) forecasts agree exactly.

Reference: the offline ``predict(history)`` of the same fitted predictor, compared with
``np.testing.assert_array_equal`` (bit-for-bit), for every predictor, with and without
a refit policy; and the interface contract of DESIGN.md (fixed-size state, 1-D in ->
1-D out, not-fitted error, sklearn-style parameters). Persistence and the paper's
linear extrapolation are also checked against their closed forms.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import (
    ARMAPredictor,
    InfoPredictor,
    LinearPredictor,
    MeanPredictor,
    MultivariatePredictor,
    NeuralNetPredictor,
    NotFittedError,
    PersistencePredictor,
    RLSMultivariatePredictor,
)


def _series(T=900, M=3, seed=0):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((T + 200, M))
    X = lfilter([1, 0.5, 0.3], [1, -0.6, -0.25], e, axis=0)[200:]
    X[:, -1] += 0.4 * X[:, 0]
    return np.ascontiguousarray(X)


PREDICTORS = {
    "persistence": lambda: PersistencePredictor(horizon=4),
    "mean": lambda: MeanPredictor(horizon=4),
    "linear": lambda: LinearPredictor(horizon=4),
    "linear_ls": lambda: LinearPredictor(fit_weights=True, horizon=4),
    "arma23": lambda: ARMAPredictor(horizon=4),
    "arma_aic": lambda: ARMAPredictor(order="aic", max_order=2, horizon=4),
    "nn": lambda: NeuralNetPredictor(n_patterns=200, max_iter=100, horizon=4),
    "var": lambda: MultivariatePredictor(order=3, horizon=4),
    "rls": lambda: RLSMultivariatePredictor(order=2, forgetting=0.99, horizon=4),
    "arma_refit": lambda: ARMAPredictor(order=(1, 1), horizon=4, refit_every=70, window=300),
    "nn_refit": lambda: NeuralNetPredictor(n_patterns=60, max_iter=30, horizon=4,
                                           refit_every=250, window=300),
    "rls_refit": lambda: RLSMultivariatePredictor(horizon=4, refit_every=100, window=250),
    "mean_refit": lambda: MeanPredictor(horizon=4, refit_every=1, window=5),
    "info": lambda: InfoPredictor(max_lag=5, max_inputs=4, horizon=4),
    "info_refit": lambda: InfoPredictor(max_lag=3, max_inputs=3, horizon=4, refit_every=90,
                                        window=300),
}


@pytest.mark.parametrize("name", list(PREDICTORS))
def test_online_equals_offline_exactly(name):
    X = _series()
    pred = PREDICTORS[name]().fit(X[:400])
    history = X[:700]
    offline = pred.predict(history)
    pred.reset()
    online = [pred.update(x) for x in history]
    np.testing.assert_array_equal(online[-1], offline)
    # also at an intermediate origin, and the offline path of the evaluator
    np.testing.assert_array_equal(online[512], pred.predict(history[:513]))
    path, _ = pred._forecast_path(history, 4)
    np.testing.assert_array_equal(np.stack(online), path)
    # reset really restarts (same numbers on a second pass)
    pred.reset()
    again = [pred.update(x) for x in history]
    np.testing.assert_array_equal(again[-1], offline)


def test_scalar_series_round_trip_shapes():
    x = _series(M=1)[:, 0]
    pred = ARMAPredictor(order=(2, 1), horizon=3).fit(x[:500])
    assert pred.predict(x[:600]).shape == (3,)
    assert pred.predict(x[:600], horizon=7).shape == (7,)
    pred.reset()
    for v in x[:600]:
        out = pred.update(float(v))
    assert out.shape == (3,)
    np.testing.assert_array_equal(out, pred.predict(x[:600]))
    pred.reset()
    assert pred.update(np.float64(x[0])).shape == (3,)


def test_longer_horizon_prefix_consistent():
    X = _series()
    pred = ARMAPredictor(horizon=3).fit(X[:500])
    np.testing.assert_allclose(pred.predict(X, horizon=10)[:3], pred.predict(X), rtol=0,
                               atol=1e-15)


def test_state_is_fixed_size():
    X = _series(T=3000)
    for name in ("arma23", "linear", "var", "rls", "nn", "info"):
        pred = PREDICTORS[name]().fit(X[:400])
        pred.reset()
        pred.update(X[0])
        sizes = {k: v.nbytes for k, v in pred._run.state.items() if isinstance(v, np.ndarray)}
        for x in X[1:]:
            pred.update(x)
        after = {k: v.nbytes for k, v in pred._run.state.items() if isinstance(v, np.ndarray)}
        assert sizes == after, name
        assert pred._run.ring is None  # no ring buffer without a refit policy


def test_persistence_and_paper_linear_closed_forms():
    X = _series()
    p = PersistencePredictor(horizon=5).fit(X[:10])
    np.testing.assert_array_equal(p.predict(X[:50]), np.tile(X[49], (5, 1)))
    lin = LinearPredictor(horizon=5).fit(X[:10])
    h = np.arange(1, 6)[:, None]
    np.testing.assert_allclose(lin.predict(X[:50]), X[49] + h * (X[49] - X[48]),
                               rtol=1e-13, atol=1e-13)
    m = MeanPredictor(horizon=2).fit(X[:100])
    np.testing.assert_allclose(m.predict(X[:300]), np.tile(X[:100].mean(0), (2, 1)),
                               rtol=1e-14)


def test_refit_schedule_uses_window_before_origin():
    # MeanPredictor refitted every sample on the last 5 samples = moving average
    x = np.arange(40.0) ** 1.5
    m = MeanPredictor(horizon=1, refit_every=1, window=5).fit(x[:5])
    path, refits = m._forecast_path(x[:, None], 1)
    # forecast made after sample t uses the refit at t - 1: mean of x[t-5 : t]
    for t in range(6, 40):
        assert path[t, 0, 0] == pytest.approx(x[t - 5 : t].mean(), rel=1e-14)
    assert [r[0] for r in refits] == list(range(4, 40))


def test_sklearn_style_parameters():
    pred = ARMAPredictor(order=(1, 2), horizon=3)
    assert pred.get_params()["order"] == (1, 2)
    clone = pred.clone(horizon=5)
    assert clone.horizon == 5 and clone.order == (1, 2) and not hasattr(clone, "params_")
    assert "order=(1, 2)" in repr(pred)
    with pytest.raises(ValueError, match="`bogus` is not a parameter of ARMAPredictor"):
        pred.set_params(bogus=1)
    with pytest.raises(NotFittedError, match="not fitted yet"):
        pred.predict(np.zeros(10))
    with pytest.raises(NotFittedError, match="not fitted yet"):
        pred.update(1.0)
    with pytest.raises(NotFittedError, match="not fitted yet"):
        pred.reset()
    with pytest.raises(NotFittedError):
        _ = pred.ar_coef_
