"""Neural-net forecaster: scikit-learn agreement and the measured behaviour.

References: ``sklearn.neural_network.MLPRegressor.predict`` on the same windows (the
numba forward pass must reproduce it to rounding); persistence and a Yule-Walker
AR(2) (the optimal linear predictor of an AR(2) process) as yardsticks on simulated
series with known dynamics.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import ARMAPredictor, NeuralNetPredictor, PersistencePredictor


def _smooth(n, seed):
    # ARMA(2, 1) with a strong, smooth resonance: predictable beyond persistence
    rng = np.random.default_rng(seed)
    return lfilter([1.0, 0.5], [1.0, -1.6, 0.7], rng.standard_normal(n + 500))[500:]


def _rmse(pred, x, n_train):
    path, _ = pred._forecast_path(x[:, None], 1)
    return np.sqrt(np.mean((x[n_train:] - path[n_train - 1 : -1, 0, 0]) ** 2))


def test_kernel_forward_matches_sklearn_predict():
    x = _smooth(1500, 0)
    nn = NeuralNetPredictor(n_patterns=300, max_iter=200).fit(x[:1000])
    model = nn.models_[0]
    k = nn.n_inputs
    path, _ = nn._forecast_path(x[:, None], 1)
    z = (x - x[:1000].mean()) / x[:1000].std()
    windows = np.stack([z[t - k + 1 : t + 1] for t in range(k - 1, x.size)])
    expect = model.predict(windows) * x[:1000].std() + x[:1000].mean()
    np.testing.assert_allclose(path[k - 1 :, 0, 0], expect, rtol=1e-10, atol=1e-12)


def test_default_beats_persistence_paper_config_does_not():
    x = _smooth(3000, 1)
    n_train = 2000
    pers = _rmse(PersistencePredictor(horizon=1).fit(x[:n_train]), x, n_train)
    ar2 = _rmse(ARMAPredictor(order=(2, 1), horizon=1).fit(x[:n_train]), x, n_train)
    default = _rmse(NeuralNetPredictor(horizon=1).fit(x[:n_train]), x, n_train)
    assert default < 0.9 * pers
    assert default > 0.98 * ar2  # never better than the optimal linear predictor
    paper = [_rmse(NeuralNetPredictor.paper(horizon=1, random_state=s).fit(x[:n_train]), x,
                   n_train) for s in range(3)]
    assert min(paper) > pers  # 10 patterns cannot constrain 121 weights


def test_seeded_and_convergence_recorded():
    x = _smooth(800, 2)
    a = NeuralNetPredictor(n_patterns=200, max_iter=5, random_state=3).fit(x)
    b = NeuralNetPredictor(n_patterns=200, max_iter=5, random_state=3).fit(x)
    assert not a.converged_[0]  # stopped at max_iter: recorded, no warning raised
    np.testing.assert_array_equal(a.predict(x), b.predict(x))
    c = NeuralNetPredictor(n_patterns=200, max_iter=5, random_state=4).fit(x)
    assert not np.array_equal(a.predict(x), c.predict(x))


def test_warm_start_refit_changes_weights_deterministically():
    x = _smooth(1200, 3)
    nn = NeuralNetPredictor(n_patterns=100, max_iter=40, refit_every=300, window=300)
    nn.fit(x[:300])
    _, refits = nn._forecast_path(x[:, None], 2)
    assert [r[0] for r in refits] == [299, 599, 899, 1199]
    w_fit = nn.params_["w1"]
    assert not np.array_equal(refits[0][1]["w1"], w_fit)
    # the fitted model objects are not mutated by refits (warm start uses copies)
    np.testing.assert_array_equal(nn.models_[0].coefs_[0], w_fit[0])


@pytest.mark.parametrize("n", [130, 131])
def test_shortest_history(n):
    # 10 inputs + one pattern per weight of the 10-10-1 network: 10 (10 + 2) + 1 = 121
    x = _smooth(200, 4)[:n]
    if n < 131:
        with pytest.raises(ValueError, match="`history` needs at least 131 samples"):
            NeuralNetPredictor().fit(x)
    else:
        assert NeuralNetPredictor(max_iter=20).fit(x).predict(x).shape == (10,)
