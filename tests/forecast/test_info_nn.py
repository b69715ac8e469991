"""The ``info-nn`` predictor: the ``info`` model plus random tanh features of its inputs.

References, from outside the code under test:

- online == offline: the offline ``predict`` of the same fitted predictor, bit for
  bit (``assert_array_equal``), with and without a refit policy, and the evaluator's
  offline path;
- the forecast recomputed in the test with numpy from the fitted parameters (the
  formula of the module notes), independent of the numba kernel, to float rounding
  (1e-12 relative: a sum of at most 8 + 32 terms of O(1) in a different order);
- where the network is switched off (``beta = 0``) the forecast equals the ``info``
  predictor's, bit for bit (same selection, same weights, same linear kernel);
- a process whose future depends on a past value through ``sin``: the network must
  beat the linear model on fresh data (the conditional mean is nonlinear, so the
  best linear forecast has a known excess error); and a linear Gaussian VAR, where
  the best forecast is linear: the hold-out must keep the network from doing worse
  than ``info`` by more than 1 % (it cannot gain there);
- the protocol: preset name, sklearn-style parameters, fixed-size state; refusals by
  message.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import InfoNNPredictor, InfoPredictor, evaluate, make_predictor


def _nonlinear(T: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((T + 100, 3)) * [1.0, 0.3, 1.0]
    x = np.zeros((T + 100, 3))
    for t in range(2, T + 100):
        x[t, 0] = 0.6 * x[t - 1, 0] + e[t, 0]
        x[t, 1] = 0.5 * x[t - 1, 1] + np.sin(2 * x[t - 2, 0]) + e[t, 1]
        x[t, 2] = 0.9 * x[t - 1, 2] + 0.3 * x[t - 1, 0] + e[t, 2]
    return x[100:] + [0.0, 1.0, -2.0]


def _linear(T: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((T + 200, 3))
    X = lfilter([1, 0.5, 0.3], [1, -0.6, -0.25], e, axis=0)[200:]
    X[:, -1] += 0.4 * X[:, 0]
    return np.ascontiguousarray(X)


@pytest.mark.parametrize("refit", [None, 150])
def test_online_equals_offline_exactly(refit):
    X = _nonlinear(1400, 0)
    pred = InfoNNPredictor(max_lag=4, max_inputs=4, n_features=8, horizon=3,
                           refit_every=refit, window=None if refit is None else 700)
    pred.fit(X[:700])
    assert pred.n_active_.any()  # the test exercises the network
    history = X[:1100]
    offline = pred.predict(history)
    pred.reset()
    online = [pred.update(x) for x in history]
    np.testing.assert_array_equal(online[-1], offline)
    np.testing.assert_array_equal(online[800], pred.predict(history[:801]))
    path, _ = pred._forecast_path(history, 3)
    np.testing.assert_array_equal(np.stack(online), path)


def test_forecast_is_the_formula_of_its_parameters():
    X = _nonlinear(1500, 1)
    pred = InfoNNPredictor(max_lag=4, max_inputs=4, n_features=8, horizon=2).fit(X[:1000])
    p = pred.params_
    hist = X[:1200]
    xc = hist - p["mu"]  # no constant column here
    ref = np.empty((2, 3))
    for h in range(2):
        for m in range(3):
            used = np.flatnonzero(p["coef"][h, m] != 0)
            u = xc[-1 - p["lag"][h, m, used], p["src"][h, m, used]]
            z = p["b"][h, m] + p["w"][h, m][:, used] @ (u / p["scale"][p["src"][h, m, used]])
            ref[h, m] = p["mu"][m] + p["coef"][h, m, used] @ u + p["beta"][h, m] @ np.tanh(z)
    np.testing.assert_allclose(pred.predict(hist), ref, rtol=1e-12, atol=1e-12)


def test_without_its_network_it_is_the_info_predictor():
    X = _linear(1500, 2)
    kw = dict(max_lag=4, max_inputs=4, horizon=3)
    nn = InfoNNPredictor(n_features=8, **kw).fit(X[:900])
    lin = InfoPredictor(**kw).fit(X[:900])
    for key in ("mu", "src", "lag", "coef"):
        np.testing.assert_array_equal(nn.params_[key], lin.params_[key])
    nn.params_["beta"][:] = 0.0
    np.testing.assert_array_equal(nn.predict(X), lin.predict(X))


def test_gains_on_a_nonlinear_process_and_not_on_a_linear_one():
    kw = dict(max_lag=4, max_inputs=6, horizon=2)
    ev = evaluate({"info": InfoPredictor(**kw), "info-nn": InfoNNPredictor(**kw)},
                  _nonlinear(8000, 3), train=0.5, horizons=range(1, 3))
    rmse = dict(zip(ev.names, ev.rmse_wavefront, strict=True))
    assert rmse["info-nn"][0] < 0.95 * rmse["info"][0]
    ev = evaluate({"info": InfoPredictor(**kw), "info-nn": InfoNNPredictor(**kw)},
                  _linear(8000, 4), train=0.5, horizons=range(1, 3))
    rmse = dict(zip(ev.names, ev.rmse_wavefront, strict=True))
    assert (rmse["info-nn"] <= 1.01 * rmse["info"]).all()


def test_protocol():
    pred = make_predictor("info-nn")
    assert isinstance(pred, InfoNNPredictor) and pred.get_params()["n_features"] == 32
    clone = pred.clone(n_features=4, horizon=2)
    assert clone.n_features == 4 and clone.horizon == 2 and not hasattr(clone, "params_")
    X = _nonlinear(900, 5)
    clone.max_lag = 3
    clone.fit(X[:600])
    clone.reset()
    clone.update(X[0])
    sizes = {k: v.nbytes for k, v in clone._run.state.items() if isinstance(v, np.ndarray)}
    for x in X[1:300]:
        out = clone.update(x)
    assert out.shape == (2, 3)
    assert sizes == {k: v.nbytes for k, v in clone._run.state.items()
                     if isinstance(v, np.ndarray)}
    with pytest.raises(ValueError, match="`horizon` must be <= 2"):
        clone.predict(X[:700], horizon=3)


def test_refusals_name_the_argument():
    X = _nonlinear(900, 6)
    with pytest.raises(ValueError, match="`n_features` must be"):
        InfoNNPredictor(n_features=0).fit(X)
    with pytest.raises(ValueError, match="`ridge_grid` must be a non-empty sequence"):
        InfoNNPredictor(ridge_grid=[], max_lag=3, horizon=2).fit(X)
    with pytest.raises(ValueError, match="`ridge_grid` must be"):
        InfoNNPredictor(ridge_grid=[1.0, -1.0], max_lag=3, horizon=2).fit(X)
    with pytest.raises(ValueError, match="`holdout` must be"):
        InfoNNPredictor(holdout=0.7, max_lag=3, horizon=2).fit(X)
    with pytest.raises(ValueError, match="10 rows per hidden unit x 32"):
        InfoNNPredictor(max_lag=3, horizon=2).fit(X[:200])
