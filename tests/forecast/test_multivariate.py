"""Multivariate (VAR) predictors against least-squares references.

References: scikit-learn ``Ridge`` (the Tikhonov-regularised least-squares solution
with the same penalty, on unit-norm regressors), the change-of-units law (one mode in
other units changes only that mode's forecasts, by the same factor),
``numpy.linalg.lstsq`` for the unregularised VAR, the exact
equivalence of recursive least squares (forgetting factor 1) with the batch solution
on all the data seen (Haykin, Adaptive Filter Theory, ch. 10), and a simulated VAR(1)
with cross-coupling, whose optimal one-step error is the innovation covariance.
"""

import numpy as np
import pytest
from sklearn.linear_model import Ridge

from modalinfo.forecast import (
    ARMAPredictor,
    MultivariatePredictor,
    RLSMultivariatePredictor,
)


def _var1(n, seed):
    rng = np.random.default_rng(seed)
    A = np.array([[0.5, 0.0, 0.0], [0.6, 0.3, 0.0], [0.0, -0.5, 0.4]])  # x_t = A x_{t-1} + e
    x = np.zeros((n, 3))
    e = rng.standard_normal((n, 3))
    for t in range(1, n):
        x[t] = A @ x[t - 1] + e[t]
    return x, A


def test_batch_solution_matches_sklearn_ridge():
    x, _ = _var1(2000, 0)
    pred = MultivariatePredictor(order=2, alpha=0.05).fit(x)
    xc = x - x.mean(axis=0)
    Z = np.hstack([xc[1:-1], xc[:-2]])
    # the penalty alpha diag(Z^T Z) is sklearn's ridge (alpha) on unit-norm regressors
    scale = np.sqrt(np.sum(Z**2, axis=0))
    ridge = Ridge(alpha=0.05, fit_intercept=False).fit(Z / scale, xc[2:])
    np.testing.assert_allclose(pred.coef_.reshape(6, 3), ridge.coef_.T / scale[:, None],
                               rtol=1e-8, atol=1e-12)


@pytest.mark.parametrize("cls", [MultivariatePredictor, RLSMultivariatePredictor])
def test_a_change_of_units_of_one_mode_changes_only_that_mode(cls):
    # audit 9 (issue 27): a common ridge lambda I shrank the lags of a mode of small
    # variance to its mean (its RMSE 16 % above the same log in common units when one
    # mode was x 1e6 and another x 1e-6). The law: expressing mode k in other units
    # (x s_k) multiplies mode k's forecasts by s_k and leaves every other mode's alone.
    x, _ = _var1(1500, 5)
    s = np.array([1e6, 1.0, 1e-6])
    a = cls(order=2, alpha=1e-3, horizon=3).fit(x[:1000]).predict(x)
    b = cls(order=2, alpha=1e-3, horizon=3).fit(x[:1000] * s).predict(x * s)
    np.testing.assert_allclose(b / s, a, rtol=1e-7, atol=1e-9)


def test_recovers_var1_and_beats_univariate():
    x, A = _var1(8000, 1)
    pred = MultivariatePredictor(order=1, alpha=0.0).fit(x[:6000])
    np.testing.assert_allclose(pred.coef_[0].T, A, atol=0.03)
    Z = x[:5999] - x[:6000].mean(0)
    np.testing.assert_allclose(
        pred.coef_[0], np.linalg.lstsq(Z, x[1:6000] - x[:6000].mean(0), rcond=None)[0],
        rtol=1e-8, atol=1e-10)
    path, _ = pred._forecast_path(x, 1)
    mse = np.mean((x[6001:] - path[6000:-1, 0]) ** 2, axis=0)
    np.testing.assert_allclose(mse, 1.0, rtol=0.08)  # innovation variance
    uni = ARMAPredictor(order=(2, 0), horizon=1).fit(x[:6000])
    upath, _ = uni._forecast_path(x, 1)
    mse_uni = np.mean((x[6001:] - upath[6000:-1, 0]) ** 2, axis=0)
    assert mse_uni[1] > 1.15 * mse[1]  # mode 1 is driven by mode 0


def test_rls_with_unit_forgetting_equals_batch_on_all_data():
    x, _ = _var1(3000, 2)
    mu_fix = x[:1000].mean(0)
    rls = RLSMultivariatePredictor(order=2, alpha=1e-6, forgetting=1.0).fit(x[:1000])
    rls.reset()
    for row in x[:2500]:
        rls.update(row)
    # batch solve on x[:2500] with the fitted mean and the same (tiny) regulariser
    xc = x[:2500] - mu_fix
    Z = np.hstack([xc[1:-1], xc[:-2]])
    Z0 = np.hstack([(x[:1000] - mu_fix)[1:-1], (x[:1000] - mu_fix)[:-2]])
    # RLS started from the batch fit on x[:1000] (whose Gram includes the ridge) and then saw
    # every regression row of x[:2500], so it solves Gram(all rows) + Gram(first rows)
    # + 1e-6 diag(Gram(first rows)): the first 998 rows are counted twice.
    G = Z.T @ Z + Z0.T @ Z0 + 1e-6 * np.diag(np.diag(Z0.T @ Z0))
    B = np.linalg.solve(G, Z.T @ xc[2:] + Z0.T @ (x[:1000] - mu_fix)[2:])
    np.testing.assert_allclose(rls.adapted_coef_.reshape(6, 3), B, rtol=1e-6, atol=1e-9)


def test_rls_tracks_a_change_that_batch_misses():
    x1, _ = _var1(3000, 3)
    rng = np.random.default_rng(4)
    x2 = np.zeros((3000, 3))
    B = np.array([[-0.6, 0.0, 0.0], [0.0, 0.3, 0.5], [0.0, 0.0, -0.4]])
    for t in range(1, 3000):
        x2[t] = B @ x2[t - 1] + rng.standard_normal(3)
    x = np.vstack([x1, x2])
    batch = MultivariatePredictor(order=1, horizon=1).fit(x[:2000])
    rls = RLSMultivariatePredictor(order=1, forgetting=0.99, horizon=1).fit(x[:2000])
    errs = {}
    for name, p in (("batch", batch), ("rls", rls)):
        path, _ = p._forecast_path(x, 1)
        errs[name] = np.mean((x[4001:] - path[4000:-1, 0]) ** 2)
    assert errs["rls"] < 0.8 * errs["batch"]
    assert errs["rls"] == pytest.approx(1.0, rel=0.1)
