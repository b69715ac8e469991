"""Forecast kernels against slow NumPy references.

References: the ARMA recursion against ``scipy.signal.lfilter`` (innovations) and an
explicit h-step loop written from Brockwell & Davis eq. 5.3.x (with an intercept ``c``
added to every step, ``x_t = c + sum phi x_{t-i} + ...``: fix 41-a, round 40 S01);
the MLP forward pass against ``sklearn.neural_network.MLPRegressor.predict``; the VAR
recursion against a NumPy matrix loop; the RLS update against the textbook
matrix-inversion-lemma form (Haykin, Adaptive Filter Theory, eq. 10.x) written in
NumPy. Each kernel is also called from inside an njit function.
"""

import warnings

import numba as nb
import numpy as np
import pytest
from scipy.signal import lfilter
from sklearn.exceptions import ConvergenceWarning
from sklearn.neural_network import MLPRegressor

from modalinfo.forecast import _kernels as K  # noqa: N812


def _arma_reference(x, mu, phi, theta, H, c=0.0):
    """h-step forecasts after every sample, plain Python (intercept ``c`` about ``mu``)."""
    n = x.size
    xc = x - mu
    # innovations from zero state (the forecast of the first sample is 0, c after it)
    e = lfilter([1.0], np.r_[1.0, theta],
                lfilter(np.r_[1.0, -phi], [1.0], xc) - c * (np.arange(n) >= 1))
    out = np.empty((n, H))
    p, q = phi.size, theta.size
    for t in range(n):
        fc = []
        for h in range(1, H + 1):
            s = c
            for i in range(1, p + 1):
                k = t + h - i
                s += phi[i - 1] * (fc[k - t - 1] if k > t else (xc[k] if k >= 0 else 0.0))
            for j in range(h, q + 1):
                k = t + h - j
                s += theta[j - 1] * (e[k] if k >= 0 else 0.0)
            fc.append(s)
        out[t] = np.array(fc) + mu
    return out


@pytest.mark.parametrize("c", [0.0, 0.3])
@pytest.mark.parametrize("p,q", [(0, 0), (1, 0), (2, 3), (3, 1), (0, 2)])
def test_arma_filter_matches_reference(p, q, c):
    rng = np.random.default_rng(p * 10 + q)
    n, H = 60, 5
    x = rng.standard_normal(n) + 0.7
    phi = rng.uniform(-0.4, 0.4, p)
    theta = rng.uniform(-0.4, 0.4, q)
    out = np.zeros((n, H, 1))
    status = np.zeros(1, dtype=np.int64)
    coef = np.r_[0.7, c, phi, theta][None].copy()  # centring, intercept, AR, MA
    K.arma_filter(x[:, None].copy(), coef, p, q, np.zeros((1, p + q + 1)), np.zeros(H), out,
                  status)
    assert status[0] == 0
    np.testing.assert_allclose(out[:, :, 0], _arma_reference(x, 0.7, phi, theta, H, c),
                               rtol=1e-12, atol=1e-12)


def test_arma_filter_last_only_and_nonfinite():
    x = np.arange(10.0)[:, None]
    last = np.zeros((1, 3, 1))
    full = np.zeros((10, 3, 1))
    coef = np.array([[0.0, 0.0, 1.0]])  # persistence: mu = 0, c = 0, phi = 1
    for out in (last, full):
        K.arma_filter(x, coef, 1, 0, np.zeros((1, 2)), np.zeros(3), out,
                      np.zeros(1, dtype=np.int64))
    np.testing.assert_array_equal(last[0], full[-1])
    x[4, 0] = np.nan
    status = np.zeros(1, dtype=np.int64)
    K.arma_filter(x, coef, 1, 0, np.zeros((1, 2)), np.zeros(3), full, status)
    assert status[0] == 5


def test_mlp_filter_matches_sklearn():
    rng = np.random.default_rng(0)
    k, J = 6, 5
    X = rng.standard_normal((200, k))
    y = X @ rng.standard_normal(k) + 0.1 * rng.standard_normal(200)
    for act, code in [("relu", 1), ("tanh", 2), ("logistic", 3), ("identity", 0)]:
        model = MLPRegressor(hidden_layer_sizes=(J,), activation=act, solver="lbfgs", max_iter=50,
                             random_state=0)
        with warnings.catch_warnings():  # may stop at max_iter: irrelevant here
            warnings.simplefilter("ignore", ConvergenceWarning)
            model.fit(X, y)
        series = rng.standard_normal(40)
        out = np.zeros((40, 1, 1))
        K.mlp_filter(series[:, None].copy(), np.zeros(1), np.ones(1),
                     model.coefs_[0][None].copy(), model.intercepts_[0][None].copy(),
                     model.coefs_[1][:, 0][None].copy(), model.intercepts_[1].copy(), code,
                     np.zeros((1, k)), np.zeros(1 + k), out, np.zeros(1, dtype=np.int64))
        windows = np.stack([series[t - k + 1 : t + 1] for t in range(k - 1, 40)])
        np.testing.assert_allclose(out[k - 1 :, 0, 0], model.predict(windows), rtol=1e-12,
                                   atol=1e-12)


def test_var_filter_matches_numpy():
    rng = np.random.default_rng(1)
    P, M, H, n = 3, 4, 4, 30
    coef = 0.2 * rng.standard_normal((P, M, M))
    mu = rng.standard_normal(M)
    x = rng.standard_normal((n, M))
    out = np.zeros((n, H, M))
    K.var_filter(x, mu, coef, np.zeros((P, M)), np.zeros((H, M)), out,
                 np.zeros(1, dtype=np.int64))
    xc = np.vstack([np.zeros((P, M)), x - mu])
    for t in range(n):
        hist = list(xc[: t + P + 1])
        for h in range(H):
            nxt = sum(hist[-1 - i] @ coef[i] for i in range(P))
            hist.append(nxt)
            np.testing.assert_allclose(out[t, h], nxt + mu, rtol=1e-12, atol=1e-12)


def test_rls_filter_matches_textbook_rls():
    rng = np.random.default_rng(2)
    P, M, n, lam = 2, 3, 50, 0.97
    D = P * M
    coef0 = 0.1 * rng.standard_normal((P, M, M))
    A = rng.standard_normal((D, D))
    Pm0 = np.linalg.inv(A @ A.T + D * np.eye(D))
    x = rng.standard_normal((n, M))
    mu = np.zeros(M)
    coef = coef0.copy()
    Pm = Pm0.copy()
    out = np.zeros((n, 1, M))
    K.rls_var_filter(x, mu, coef, Pm, lam, np.zeros((P, M)), np.zeros(1, dtype=np.int64),
                     np.zeros(D), np.zeros(D), np.zeros((1, M)), out,
                     np.zeros(1, dtype=np.int64))
    # textbook RLS: W (D, M), regression vector z = [x_{t-1}, x_{t-2}]
    W = coef0.reshape(D, M).copy()
    Pr = Pm0.copy()
    for t in range(P, n):
        z = np.concatenate([x[t - 1 - i] for i in range(P)])
        k = Pr @ z / (lam + z @ Pr @ z)
        W = W + np.outer(k, x[t] - W.T @ z)
        Pr = (Pr - np.outer(k, z @ Pr)) / lam
    np.testing.assert_allclose(coef.reshape(D, M), W, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(Pm, Pr, rtol=1e-9, atol=1e-12)
    z_last = np.concatenate([x[n - 1 - i] for i in range(P)])
    np.testing.assert_allclose(out[-1, 0], W.T @ z_last, rtol=1e-9, atol=1e-12)


def test_kernels_callable_from_njit():
    @nb.njit
    def run(x, out, status):
        K.arma_filter(x, np.array([[0.0, 0.0, 1.0]]), 1, 0, np.zeros((1, 2)), np.zeros(2), out,
                      status)
        return out[0, 1, 0]

    out = np.zeros((1, 2, 1))
    assert run(np.array([[1.0], [3.0]]), out, np.zeros(1, dtype=np.int64)) == 3.0
