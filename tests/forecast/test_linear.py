"""Linear extrapolation versus persistence, against closed-form error variances.

References (derived from the model definitions, Brockwell & Davis 2002 ch. 3):
- smooth series: increments ``d_t = x_t - x_{t-1}`` form an AR(1) with coefficient
  ``c`` (a low-pass-filtered random walk). Persistence error ``d_{t+1}`` has variance
  ``s^2 / (1 - c^2)``; the paper's ``2 x_t - x_{t-1}`` error ``d_{t+1} - d_t`` has
  ``s^2 (1 + (1 - c)^2 / (1 - c^2))``.
- AR(1), ``x_t = f x_{t-1} + e_t``: persistence MSE ``s^2 2 / (1 + f)``; linear
  extrapolation MSE ``s^2 (1 + (2 - f)^2 + (1 - f)^4 / (1 - f^2))``, about twice the
  innovation variance at f = 0.98, so linear extrapolation loses. At horizon h
  (``x_hat = (1 + h) x_t - h x_{t-1}``, ``x_{t+h} = f^h x_t + sum_{j<h} f^j e_{t+h-j}``):
  linear ``s^2 (sum_{j<h} f^(2j) + (1 + h - f^h)^2 + (f^(h+1) - (1 + h) f + h)^2 /
  (1 - f^2))``, persistence ``2 s^2 (1 - f^h) / (1 - f^2)``; their ratio is ``3 - f`` at
  h = 1 (expand both) and tends to 3 at h = 2 as f -> 1 (RMSE x1.41 and x1.73), the issue-30 log's
  numbers (lag-1 correlation 0.95-0.999: RMSE 0.0703 vs 0.0496, 0.1217 vs 0.0701).
- least-squares weights ``(a, b)`` against ``numpy.linalg.lstsq``.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import LinearPredictor, PersistencePredictor, evaluate
from modalinfo.forecast.presets import make_predictor


def _mse_one_step(pred, x, n_train):
    pred.fit(x[:n_train])
    path, _ = pred._forecast_path(x[:, None], 1)
    return np.mean((x[n_train:] - path[n_train - 1 : -1, 0, 0]) ** 2)


def test_linear_beats_persistence_on_smooth_series():
    c, n = 0.9, 60000
    rng = np.random.default_rng(0)
    d = lfilter([1.0], [1.0, -c], rng.standard_normal(n))
    x = np.cumsum(d)
    mse_p = _mse_one_step(PersistencePredictor(horizon=1), x, 1000)
    mse_l = _mse_one_step(LinearPredictor(horizon=1), x, 1000)
    # closed forms with s = 1; 59000 samples: relative sampling error ~1-2%
    assert mse_p == pytest.approx(1 / (1 - c**2), rel=0.06)
    assert mse_l == pytest.approx(1 + (1 - c) ** 2 / (1 - c**2), rel=0.03)
    assert mse_l < mse_p / 4
    ev = evaluate({"linear": LinearPredictor()}, x[:6000], train=1000, horizons=[1, 2])
    assert ev.gain_wavefront[ev.index("linear"), 0] > 2.0
    assert ev.beats_baseline[ev.index("linear"), 0]


def test_linear_loses_to_persistence_on_ar1():
    f, n = 0.98, 60000
    rng = np.random.default_rng(1)
    x = lfilter([1.0], [1.0, -f], rng.standard_normal(n))
    mse_p = _mse_one_step(PersistencePredictor(horizon=1), x, 1000)
    mse_l = _mse_one_step(LinearPredictor(horizon=1), x, 1000)
    expect_p = 2 / (1 + f)
    expect_l = 1 + (2 - f) ** 2 + (1 - f) ** 4 / (1 - f**2)
    assert mse_p == pytest.approx(expect_p, rel=0.03)
    assert mse_l == pytest.approx(expect_l, rel=0.03)
    assert mse_l / mse_p == pytest.approx(expect_l / expect_p, rel=0.04)  # ~2.02
    # the least-squares weights recover a ~ f, b ~ 0 and then tie with persistence
    # (an intercept column since fix 41-a: x_t = c + a x_{t-1} + b x_{t-2})
    fitted = LinearPredictor(fit_weights=True, horizon=1)
    mse_f = _mse_one_step(fitted, x, 30000)
    design = np.column_stack([np.ones(29998), x[1:29999], x[:29998]])
    c_a_b = np.linalg.lstsq(design, x[2:30000], rcond=None)[0]
    np.testing.assert_allclose(fitted.coef_[0], c_a_b[1:], rtol=1e-10)
    assert fitted.coef_[0, 0] == pytest.approx(f, abs=0.02)
    assert mse_f < mse_p * 1.01


def _ar1_linear_mse(f, h):
    """Linear extrapolation's h-step MSE on a unit-innovation AR(1) (module notes)."""
    f = np.asarray(f, dtype=float)
    head = sum(f ** (2 * j) for j in range(h))
    return head + (1 + h - f**h) ** 2 + (f ** (h + 1) - (1 + h) * f + h) ** 2 / (1 - f**2)


def _ar1_persistence_mse(f, h):
    return 2 * (1 - np.asarray(f, dtype=float) ** h) / (1 - np.asarray(f, dtype=float) ** 2)


def test_linear_preset_on_ar1_log_up_to_0999_is_the_expected_loss():
    """The `linear` preset loses to persistence on AR(1) modes as the formulas say."""
    n, f = 40_000, np.linspace(0.95, 0.999, 5)
    sigma = (np.arange(f.size) + 2.0) ** (-11 / 12)     # stationary std of each mode
    s = sigma * np.sqrt(1 - f**2)                        # innovation std
    rng = np.random.default_rng(2)
    # started in the stationary law (x_0 ~ N(0, sigma^2)), so every frame is stationary
    x = np.column_stack([lfilter([1.0], [1.0, -fm], s_m * rng.standard_normal(n),
                                 zi=[fm * sm * rng.standard_normal()])[0]
                         for fm, s_m, sm in zip(f, s, sigma, strict=True)])
    ev = evaluate({"linear": make_predictor("linear")}, x, train=1000, horizons=[1, 2])
    lin, per = ev.index("linear"), ev.index("persistence")
    for j, h in enumerate((1, 2)):
        expect_l = np.sum(s**2 * _ar1_linear_mse(f, h))
        expect_p = np.sum(s**2 * _ar1_persistence_mse(f, h))
        # 39,000 origins: MSEs of MA(h + 1) errors known to ~1 % (one sigma)
        assert ev.rmse_wavefront[lin, j] ** 2 == pytest.approx(expect_l, rel=0.04)
        assert ev.rmse_wavefront[per, j] ** 2 == pytest.approx(expect_p, rel=0.04)
        ratio = ev.rmse_wavefront[lin, j] / ev.rmse_wavefront[per, j]
        assert ratio == pytest.approx(np.sqrt(expect_l / expect_p), rel=0.02)
    # the limit f -> 1: the loss is the physics of extrapolating a random-walk-like mode
    np.testing.assert_allclose(_ar1_linear_mse(f, 1) / _ar1_persistence_mse(f, 1), 3 - f,
                               rtol=1e-12)
    assert _ar1_linear_mse(0.999, 2) / _ar1_persistence_mse(0.999, 2) == pytest.approx(3, rel=1e-2)
