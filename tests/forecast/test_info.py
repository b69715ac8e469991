"""The ``info`` predictor: sparse direct least squares over CMI-selected inputs.

References: the planted coefficients of a simulated sparse VAR(2) (support and
weights, with tolerances from the least-squares standard error), the planted delay of
a frozen-flow pair, and a forecast recomputed in the test with numpy from the
reported inputs and weights (independent of the numba kernel). Online/offline
bit-identity is checked with every predictor in test_online_offline.py.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import InfoPredictor, make_predictor


def sparse_var2(n, seed):
    M = 5
    A1 = np.diag([0.5, 0.4, 0.6, 0.3, 0.0])
    A1[0, 2] = 0.3
    A1[1, 4] = -0.35
    A1[3, 0] = 0.3
    A2 = np.zeros((M, M))
    A2[2, 3] = 0.3
    A2[4, 4] = 0.5
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n + 300, M))
    X = np.zeros((n + 300, M))
    for t in range(2, n + 300):
        X[t] = A1 @ X[t - 1] + A2 @ X[t - 2] + e[t]
    return X[300:] + np.arange(M), A1, A2  # non-zero means on purpose


@pytest.mark.parametrize("selection", ["ebic", "surrogate"])
def test_one_step_model_recovers_the_planted_var(selection):
    X, A1, A2 = sparse_var2(20_000, 0)
    pred = InfoPredictor(max_lag=3, max_inputs=6, horizon=1, selection=selection,
                         alpha=0.01, n_surrogates=99).fit(X)
    extra = 0
    for m in range(X.shape[1]):
        got = {(j, lag): w for j, lag, w in pred.inputs(m, 1)}
        truth = {(j, 0): A1[m, j] for j in np.flatnonzero(A1[m])}
        truth |= {(j, 1): A2[m, j] for j in np.flatnonzero(A2[m])}
        assert set(truth) <= set(got), m
        extra += len(set(got) - set(truth))
        # LS standard error ~ 1 / sqrt(n var(x)) < 0.007 here; 0.03 is > 4 of them
        for key, w in truth.items():
            assert got[key] == pytest.approx(w, abs=0.03)
    # false inputs: EBIC admits a null candidate with P(chi2_1 > ln n + 2 ln m = 15.3)
    # ~ 1e-4 (x 15 candidates x 5 modes); the surrogate test at FWER 0.01 per search
    # expects 0.05 false inputs in all, P(>= 2) ~ 0.001
    assert extra <= (0 if selection == "ebic" else 1)


def test_frozen_flow_lag_and_weight():
    rng = np.random.default_rng(1)
    n, delay = 6000, 7
    a = lfilter([1.0], [1.0, -0.95], rng.standard_normal(n + delay))
    b = a[:-delay] + 0.3 * rng.standard_normal(n)
    X = np.column_stack([b, a[delay:]])
    pred = InfoPredictor(max_lag=10, max_inputs=4, horizon=3).fit(X)
    for h in (1, 2, 3):
        first = pred.inputs(0, h)[0]
        # b[t + h] = a[t + h - 7] + noise: mode 1 at lag 7 - h, weight ~1
        assert first[:2] == (1, delay - h)
        assert first[2] == pytest.approx(1.0, abs=0.05)


def test_forecast_equals_numpy_recomputation():
    X, _, _ = sparse_var2(3000, 2)
    pred = InfoPredictor(max_lag=4, max_inputs=5, horizon=3).fit(X[:2000])
    hist = X[:2500]
    got = pred.predict(hist)
    mu = pred.mean_
    for h in range(1, 4):
        for m in range(X.shape[1]):
            ref = mu[m] + sum(w * (hist[-1 - lag, j] - mu[j])
                              for j, lag, w in pred.inputs(m, h))
            assert got[h - 1, m] == pytest.approx(ref, rel=1e-12, abs=1e-12)


def test_constant_mode_horizon_limit_and_preset():
    X, _, _ = sparse_var2(1000, 3)
    X[:, 1] = 2.5
    pred = InfoPredictor(max_lag=3, max_inputs=3, horizon=2).fit(X)
    np.testing.assert_array_equal(pred.predict(X)[:, 1], [2.5, 2.5])
    assert pred.n_inputs_[:, 1].tolist() == [0, 0]
    assert all(j != 1 for m in range(5) for j, _, _ in pred.inputs(m, 1))
    with pytest.raises(ValueError, match="`horizon` must be <= 2 for this InfoPredictor"):
        pred.predict(X, horizon=3)
    with pytest.raises(ValueError, match="`history` needs at least"):
        InfoPredictor().fit(X[:50])
    with pytest.raises(ValueError, match="`selection` must be one of"):
        InfoPredictor(selection="aic").fit(X)
    assert isinstance(make_predictor("info"), InfoPredictor)


def test_ebic_penalty_is_chen_and_chens_price_per_input():
    # reference: Chen & Chen (2008), EBIC_1 = -2 ln L + k ln n + 2 ln C(m, k), with the
    # prior term at its bound 2 k ln m: per input ln n + 2 ln m, typed in from the
    # formula (n = 1000, m = 50: 6.907755 + 7.824046); the bound holds for every step
    from math import comb, log

    from modalinfo.forecast.info import ebic_penalty

    assert ebic_penalty(1000, 50) == pytest.approx(14.731801, abs=1e-6)
    assert ebic_penalty(1000, 0) == pytest.approx(6.907755, abs=1e-6)
    for k in range(8):
        step = log(1000) + 2 * (log(comb(50, k + 1)) - log(comb(50, k)))
        assert ebic_penalty(1000, 50) >= step
