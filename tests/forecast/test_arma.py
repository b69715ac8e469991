"""ARMA estimation and forecasting against statsmodels and closed forms.

References:
- statsmodels ``ARIMA(order=(2, 0, 3)).fit()`` (exact Gaussian ML via the Kalman
  filter), its fixed-parameter filtering for one-step out-of-sample forecasts;
- statsmodels ``acovf``, ``yule_walker(method="mle")`` and ``arma2ma`` (psi-weights);
- Brockwell & Davis (2002): AR(1) h-step error variance
  ``sigma^2 (1 - phi^{2h}) / (1 - phi^2)`` (eq. 5.3), the non-invertible MA(1)
  ``theta = 2, sigma^2 = 1`` having the autocovariance of ``theta = 1/2, sigma^2 = 4``
  (section 2.3), and the nominal coverage of Gaussian one-step intervals.
"""

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter
from statsmodels.regression.linear_model import yule_walker
from statsmodels.tsa.arima.model import ARIMA
from statsmodels.tsa.arima_process import arma2ma
from statsmodels.tsa.stattools import acovf

from modalinfo.forecast import ARMAPredictor, psi_weights
from modalinfo.forecast.arma import sample_autocovariance

PHI = np.array([1.3, -0.4])          # inverse roots 0.8 and 0.5
THETA = np.array([-0.5, 0.2, 0.15])


def _arma23(n, seed):
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n + 1000)
    return lfilter(np.r_[1.0, THETA], np.r_[1.0, -PHI], e)[1000:] + 0.5


def _one_step_rmse(pred, x, n_train):
    path, _ = pred._forecast_path(x[:, None], 1)
    return np.sqrt(np.mean((x[n_train:] - path[n_train - 1 : -1, 0, 0]) ** 2))


@pytest.fixture(scope="module")
def arma_split():
    x = _arma23(7000, seed=3)
    return x, 5000


def test_simulated_model_is_causal_and_invertible():
    assert np.all(np.abs(np.roots(np.r_[1.0, -PHI])) < 1)
    assert np.all(np.abs(np.roots(np.r_[1.0, THETA])) < 1)


def test_one_step_rmse_within_2pct_of_statsmodels_ml(arma_split):
    x, n_train = arma_split
    ours = ARMAPredictor(order=(2, 3), horizon=1).fit(x[:n_train])
    rmse_ours = _one_step_rmse(ours, x, n_train)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # statsmodels' optimiser chatter
        res = ARIMA(x[:n_train], order=(2, 0, 3)).fit()
        full = ARIMA(x, order=(2, 0, 3)).filter(res.params)
    pred_sm = full.predict(start=n_train, end=x.size - 1)
    rmse_sm = np.sqrt(np.mean((x[n_train:] - pred_sm) ** 2))
    assert abs(rmse_ours / rmse_sm - 1) < 0.02
    # and both near the innovation standard deviation (1) of the true process
    assert 0.95 < rmse_ours < 1.05


def test_aic_selects_23_or_equally_good(arma_split):
    x, n_train = arma_split
    fixed = ARMAPredictor(order=(2, 3), horizon=1).fit(x[:n_train])
    sel = ARMAPredictor(order="aic", horizon=1).fit(x[:n_train])
    p, q = sel.orders_[0]
    assert sel.criterion_.shape == (1, 6, 6)
    assert np.nanargmin(sel.criterion_[0]) == p * 6 + q
    if (p, q) != (2, 3):
        assert abs(_one_step_rmse(sel, x, n_train) / _one_step_rmse(fixed, x, n_train)
                   - 1) < 0.005
    # white noise: the criterion must not invent dynamics worth more than noise
    wn = np.random.default_rng(0).standard_normal(3000)
    bic = ARMAPredictor(order="bic", max_order=3).fit(wn)
    assert tuple(bic.orders_[0]) == (0, 0)


def test_one_step_interval_coverage(arma_split):
    x, n_train = arma_split
    pred = ARMAPredictor(order=(2, 3), horizon=1, level=0.95).fit(x[:n_train])
    path, _ = pred._forecast_path(x[:, None], 1)
    err = x[n_train:] - path[n_train - 1 : -1, 0, 0]
    std = pred.forecast_std(1)[0, 0]
    coverage = np.mean(np.abs(err) <= 1.959963984540054 * std)
    assert abs(coverage - 0.95) <= 0.02
    iv = pred.predict_interval(x[:n_train + 10], horizon=3)
    np.testing.assert_allclose(iv.upper - iv.mean, 1.959963984540054 * iv.std, rtol=1e-12)
    np.testing.assert_array_equal(iv.mean, pred.predict(x[:n_train + 10], horizon=3))


def test_psi_weights_match_statsmodels():
    phi, theta = np.array([0.5, 0.2, -0.1]), np.array([0.4, -0.3])
    np.testing.assert_allclose(psi_weights(phi, theta, 12),
                               arma2ma(np.r_[1, -phi], np.r_[1, theta], lags=12), rtol=1e-12)


def test_ar1_forecast_variance_closed_form():
    rng = np.random.default_rng(5)
    x = lfilter([1.0], [1.0, -0.8], rng.standard_normal(20000))
    pred = ARMAPredictor(order=(1, 0), horizon=6).fit(x)
    phi = pred.ar_coef_[0, 0]
    s2 = pred.sigma2_[0]
    h = np.arange(1, 7)
    np.testing.assert_allclose(pred.forecast_std()[:, 0] ** 2,
                               s2 * (1 - phi ** (2 * h)) / (1 - phi**2), rtol=1e-12)
    assert phi == pytest.approx(0.8, abs=0.01)
    assert s2 == pytest.approx(1.0, rel=0.03)


def test_autocovariance_and_yule_walker_match_statsmodels():
    x = _arma23(3000, seed=9)
    np.testing.assert_allclose(sample_autocovariance(x, 20),
                               acovf(x, adjusted=False, demean=True, fft=False, nlag=20),
                               rtol=1e-10, atol=1e-12)
    pred = ARMAPredictor(order=(4, 0)).fit(x)
    rho, _ = yule_walker(x, order=4, method="mle", demean=True, result_object=False)
    np.testing.assert_allclose(pred.ar_coef_[0], rho, rtol=1e-9)


def test_noninvertible_ma_is_reflected():
    rng = np.random.default_rng(11)
    e = rng.standard_normal(20000)
    x = e.copy()
    x[1:] += 2.0 * e[:-1]  # MA(1), theta = 2: same ACF as theta = 0.5, sigma^2 = 4
    pred = ARMAPredictor(order=(0, 1)).fit(x)
    assert pred.ma_coef_[0, 0] == pytest.approx(0.5, abs=0.03)
    assert pred.sigma2_[0] == pytest.approx(4.0, rel=0.05)


def test_unit_root_series_gives_causal_model():
    rng = np.random.default_rng(2)
    x = np.cumsum(rng.standard_normal(3000))
    pred = ARMAPredictor(order=(2, 2), root_margin=1e-3).fit(x)
    ar = np.roots(np.r_[1.0, -pred.ar_coef_[0]])
    ma = np.roots(np.r_[1.0, pred.ma_coef_[0]])
    assert np.all(np.abs(ar) <= 1 / (1 + 1e-3) + 1e-12)
    assert np.all(np.abs(ma) <= 1 / (1 + 1e-3) + 1e-12)
    assert np.all(np.isfinite(pred.predict(x, horizon=50)))


def test_psi_weights_take_lists_and_leave_inputs_unchanged():
    """Audit 9: lists raised AttributeError, and a (q, 1) theta was modified in place
    (its rows are views). Reference: statsmodels' arma2ma (lag polynomials with the
    opposite AR sign)."""
    phi, theta = [0.5, 0.2], [0.3]
    want = arma2ma(np.r_[1.0, -np.array(phi)], np.r_[1.0, theta], lags=8)
    np.testing.assert_allclose(psi_weights(phi, theta, 8), want, rtol=1e-12)
    column = np.array([[0.3]])
    with pytest.raises(ValueError, match="`theta` must be 1-D; got 2-D"):
        psi_weights(np.array(phi), column, 8)
    assert column[0, 0] == 0.3
    with pytest.raises(TypeError, match="`phi` must be real"):
        psi_weights(np.array(phi) + 1j, theta, 8)


def test_sample_autocovariance_checks_its_series():
    """Audit 9: a list raised AttributeError, an empty series OverflowError, and a
    (T, M) table was read as one series. Reference: statsmodels' acovf (biased, fft)."""
    x = list(np.random.default_rng(3).standard_normal(64))
    np.testing.assert_allclose(sample_autocovariance(x, 5), acovf(np.array(x), nlag=5, fft=True),
                               rtol=1e-10, atol=1e-14)
    with pytest.raises(ValueError, match="`x` must be 1-D; got 2-D"):
        sample_autocovariance(np.ones((10, 2)), 3)
    with pytest.raises(ValueError, match="`x` needs at least 1 samples"):
        sample_autocovariance(np.zeros(0), 3)
    with pytest.raises(TypeError, match="`n_lags` must be an int; got 3.5"):
        sample_autocovariance(x, 3.5)
