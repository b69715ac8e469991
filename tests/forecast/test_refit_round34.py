"""ARMA refits that change the selected orders (adversarial round 34 PART a, L01-L02).

Reference: an independent NumPy implementation of the ARMA innovations recursion and
its h-step forecasts (Brockwell & Davis, *Introduction to Time Series and Forecasting*,
sec. 3.3 and 5.2: x_hat[n+1] = sum_i phi_i x[n+1-i] + sum_j theta_j e[n+1-j], future
innovations 0), started from zero lags at the first sample of the refit window, with the
parameters the refit chose. With ``order="aic"`` and a refit policy, a refit may select
other (p, q) than the fit: the running state must follow (before the fix it kept the
old layout, so the kernel read old AR lags as innovations, or wrote past the state's
end and corrupted the heap). And no look-ahead: the forecasts made up to a frame do not
move when the frames after it change.
"""

import warnings

import numpy as np
import pytest

from modalinfo.forecast import ARMAPredictor

H = 3
R, W = 50, 300


def _arma_path(x: np.ndarray, mu: float, phi: np.ndarray, theta: np.ndarray,
               horizon: int) -> np.ndarray:
    """Forecasts of x[n + 1 .. n + horizon] after the last sample of x (zero start)."""
    xc = np.asarray(x, dtype=float) - mu
    p, q = len(phi), len(theta)
    e = np.zeros(len(xc))
    pred = 0.0
    for n in range(len(xc)):
        e[n] = xc[n] - pred
        pred = (sum(phi[i] * xc[n - i] for i in range(p) if n - i >= 0)
                + sum(theta[j] * e[n - j] for j in range(q) if n - j >= 0))
    n = len(xc) - 1
    fut = {}
    out = np.empty(horizon)
    for h in range(1, horizon + 1):
        s = 0.0
        for i in range(1, p + 1):
            k = n + h - i
            s += phi[i - 1] * (fut[k] if k > n else (xc[k] if k >= 0 else 0.0))
        for j in range(h, q + 1):
            k = n + h - j
            s += theta[j - 1] * (e[k] if k >= 0 else 0.0)
        fut[n + h] = s
        out[h - 1] = s + mu
    return out


def _series(seed: int, grow: bool) -> np.ndarray:
    """Two regimes: an ARMA(2, 2)-like resonance and white noise, in either order."""
    rng = np.random.default_rng(seed)
    n = 900
    e = rng.standard_normal(n + 2)
    ar = np.zeros(n)
    for t in range(2, n):
        ar[t] = 1.6 * ar[t - 1] - 0.8 * ar[t - 2] + e[t] + 0.7 * e[t - 1] + 0.4 * e[t - 2]
    white = rng.standard_normal(n)
    first, second = (white, ar) if grow else (ar, white)
    return np.r_[first[:450], second[:450]]


@pytest.mark.parametrize("grow", [False, True], ids=["orders-shrink", "orders-grow"])
def test_refit_that_changes_the_orders_forecasts_with_the_new_model(grow):
    x = _series(34, grow)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # level-step warnings of the regime change
        p = ARMAPredictor(order="aic", max_order=4, refit_every=R, window=W,
                          horizon=H).fit(x[:300])
        fitted = tuple(p.orders_[0])
        p.reset()
        changed = []
        for t in range(len(x)):
            before = p._run.params
            f = p.update(x[t])
            after = p._run.params
            if after is not before and tuple(after["orders"][0]) != tuple(
                    before["orders"][0]):
                changed.append((t, after))
            elif changed and t == changed[-1][0] + 7:  # a few frames after a change
                r, prm = changed[-1]
                pq = prm["orders"][0]
                ref = _arma_path(x[r + 1 - W:t + 1], prm["mu"][0], prm["phi"][0, :pq[0]],
                                 prm["theta"][0, :pq[1]], H)
                np.testing.assert_allclose(f, ref, rtol=1e-10, atol=1e-12)
    assert changed, f"no refit changed the orders (fit {fitted}): the test tests nothing"


@pytest.mark.parametrize("grow", [False, True], ids=["orders-shrink", "orders-grow"])
def test_refit_forecasts_do_not_see_later_frames(grow):
    x = _series(35, grow)
    y = x.copy()
    cut = 700
    y[cut + 1:] = np.random.default_rng(1).standard_normal(len(x) - cut - 1) * 5.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p = ARMAPredictor(order="aic", max_order=4, refit_every=R, window=W,
                          horizon=H).fit(x[:300])
        paths = []
        for series in (x, y):
            p.reset()
            paths.append(np.array([p.update(v) for v in series]))
        # and the offline road: predict from the history up to the cut
        offline = p.predict(y[:cut + 1])
    np.testing.assert_array_equal(paths[0][:cut + 1], paths[1][:cut + 1])
    np.testing.assert_array_equal(offline, paths[0][cut])
