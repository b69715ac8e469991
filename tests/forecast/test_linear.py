"""Linear extrapolation versus persistence, against closed-form error variances.

References (derived from the model definitions, Brockwell & Davis 2002 ch. 3):
- smooth series: increments ``d_t = x_t - x_{t-1}`` form an AR(1) with coefficient
  ``c`` (a low-pass-filtered random walk). Persistence error ``d_{t+1}`` has variance
  ``s^2 / (1 - c^2)``; the paper's ``2 x_t - x_{t-1}`` error ``d_{t+1} - d_t`` has
  ``s^2 (1 + (1 - c)^2 / (1 - c^2))``.
- AR(1), ``x_t = f x_{t-1} + e_t``: persistence MSE ``s^2 2 / (1 + f)``; linear
  extrapolation MSE ``s^2 (1 + (2 - f)^2 + (1 - f)^4 / (1 - f^2))``, about twice the
  innovation variance at f = 0.98, so linear extrapolation loses.
- least-squares weights ``(a, b)`` against ``numpy.linalg.lstsq``.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import LinearPredictor, PersistencePredictor, evaluate


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
    fitted = LinearPredictor(fit_weights=True, horizon=1)
    mse_f = _mse_one_step(fitted, x, 30000)
    design = np.column_stack([x[1:29999], x[:29998]])
    np.testing.assert_allclose(fitted.coef_[0], np.linalg.lstsq(design, x[2:30000],
                                                                 rcond=None)[0], rtol=1e-10)
    assert fitted.coef_[0, 0] == pytest.approx(f, abs=0.02)
    assert mse_f < mse_p * 1.01
