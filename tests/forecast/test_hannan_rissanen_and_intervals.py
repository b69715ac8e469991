"""The Hannan-Rissanen step alone, and Gaussian prediction intervals at any level.

References:
- statsmodels ``hannan_rissanen(..., unbiased=False)`` (steps 1-2: Yule-Walker long
  AR, then least squares on lagged data and lagged long-AR residuals), with the same
  long-AR order; the truth of the simulated ARMA(2, 3) (innovation variance 1);
- ``scipy.stats.norm.ppf`` for the interval half-width ``z_(1/2 + level/2) std`` at
  levels other than 0.95, on both sides of the mean;
- the binomial distribution of the number of covered one-step errors (nominal
  coverage 0.8), its tolerance computed in the test;
- the conditional-sum-of-squares optimum found by ``scipy.optimize.least_squares`` on
  the same innovations (zero initial state, first ``burn_in`` discarded), which the
  Gauss-Newton refinement must reach;
- the documented validation rules and defaults of ``ARMAPredictor``;
- the order of a simulated AR(2) and ARMA(1, 1) (10^4 samples), which BIC must select
  (Schwarz's criterion is consistent) and AIC must not drop a term of.
"""

import warnings

import numpy as np
import pytest
from scipy import stats
from scipy.optimize import least_squares
from scipy.signal import lfilter
from statsmodels.tsa.arima.estimators.hannan_rissanen import hannan_rissanen

from modalinfo.forecast import ARMAPredictor, evaluate

PHI = np.array([1.3, -0.4])
THETA = np.array([-0.5, 0.2, 0.15])


def _arma23(n, seed):
    e = np.random.default_rng(seed).standard_normal(n + 1000)
    return lfilter(np.r_[1.0, THETA], np.r_[1.0, -PHI], e)[1000:] + 0.5


def test_hannan_rissanen_step_alone_matches_statsmodels():
    x = _arma23(20_000, 21)
    long_order = 30
    ours = ARMAPredictor(order=(2, 3), n_iter=0, long_order=long_order).fit(x)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # statsmodels' own chatter
        ref, _ = hannan_rissanen(x, ar_order=2, ma_order=3, demean=True,
                                 initial_ar_order=long_order, unbiased=False)
    # same regression on the same rows (t >= long_order + q): equal to rounding
    np.testing.assert_allclose(ours.ar_coef_[0], ref.ar_params, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(ours.ma_coef_[0], ref.ma_params, rtol=1e-8, atol=1e-10)
    # and the two-step estimate alone already has the innovation variance of the
    # truth: sd of a variance estimate from 2e4 samples is 0.01, the two-step
    # estimator's inefficiency adds a few per cent (measured 1.01)
    assert ours.sigma2_[0] == pytest.approx(1.0, abs=0.05)
    assert ref.sigma2 == pytest.approx(ours.sigma2_[0], rel=0.05)


@pytest.mark.parametrize("level", [0.5, 0.8, 0.99])
def test_interval_bounds_at_any_level(level):
    x = _arma23(3000, 22)
    pred = ARMAPredictor(order=(2, 3), horizon=4).fit(x[:2500])
    iv = pred.predict_interval(x[:2600], level=level)
    z = stats.norm.ppf(0.5 + level / 2)
    assert iv.level == level
    np.testing.assert_allclose(iv.lower, iv.mean - z * iv.std, rtol=1e-12)
    np.testing.assert_allclose(iv.upper, iv.mean + z * iv.std, rtol=1e-12)
    np.testing.assert_array_equal(iv.std, pred.forecast_std(4)[:, 0])
    assert np.all(iv.lower < iv.mean) and np.all(iv.mean < iv.upper)


def test_coverage_at_level_080_within_binomial_tolerance():
    # one-step errors of a well-specified ARMA(2, 3), 4000 test origins, nominal 0.8:
    # covered count ~ Binomial(N, 0.8) (errors nearly independent at h = 1); accept
    # 5 binomial sd plus 1 % for the estimated parameters
    x = _arma23(8000, 23)
    pred = ARMAPredictor(order=(2, 3), horizon=1, level=0.8)
    ev = evaluate({"arma": pred}, x, train=4000, horizons=[1], level=0.8)
    n = ev.origins.size
    tol = 5 * np.sqrt(0.8 * 0.2 / n) + 0.01
    cov = ev.coverage[ev.index("arma"), 0]
    assert cov == pytest.approx(0.8, abs=tol)
    # the same errors checked by hand against the lower and the upper bound
    err = ev.truth[1 : n + 1, 0] - ev.one_step[ev.index("arma"), :n, 0]
    fitted = ARMAPredictor(order=(2, 3), horizon=1).fit(x[:4000])
    half = stats.norm.ppf(0.9) * fitted.forecast_std(1)[0, 0]
    assert np.mean(np.abs(err) <= half) == pytest.approx(cov, abs=1e-12)


def test_refinement_reaches_the_conditional_least_squares_optimum():
    x = _arma23(5000, 24)
    xc, burn = x - x.mean(), 50

    def innovations(p):
        return lfilter(np.r_[1.0, -p[:2]], np.r_[1.0, p[2:]], xc)[burn:]

    ref = least_squares(innovations, np.r_[PHI, THETA], xtol=1e-14, ftol=1e-14, gtol=1e-14)
    ours = ARMAPredictor(order=(2, 3), burn_in=burn).fit(x)
    np.testing.assert_allclose(np.r_[ours.ar_coef_[0], ours.ma_coef_[0]], ref.x, atol=1e-4)
    assert ours.sigma2_[0] == pytest.approx(np.mean(ref.fun**2), rel=1e-8)
    # the two-step estimate alone is not at the optimum (the refinement matters)
    hr = ARMAPredictor(order=(2, 3), burn_in=burn, n_iter=0).fit(x)
    assert np.abs(np.r_[hr.ar_coef_[0], hr.ma_coef_[0]] - ref.x).max() > 1e-2


def test_interval_validation_and_defaults():
    pred = ARMAPredictor(order=(1, 1)).fit(_arma23(600, 25))
    # n_iter caps the damped Newton steps run to convergence (was 10 fixed Gauss-Newton
    # steps, which stopped short on closed-loop series: issue 18)
    assert (pred.n_iter, pred.burn_in, pred.horizon, pred.level) == (50, 50, 10, 0.95)
    assert pred.forecast_std().shape == (10, 1) and pred.forecast_std(3).shape == (3, 1)
    assert pred.predict_interval(np.zeros(50)).mean.shape == (10,)
    assert pred.predict_interval(np.zeros(50), horizon=1).mean.shape == (1,)
    for bad in (0.0, 1.0, 1.5, -0.2):
        with pytest.raises(ValueError, match=r"`level` must be (>|<) "):
            pred.predict_interval(np.zeros(50), level=bad)
    with pytest.raises(ValueError, match=r"`horizon` must be an int >= 1; got 0"):
        pred.predict_interval(np.zeros(50), horizon=0)
    with pytest.raises(ValueError, match=r"`horizon` must be an int >= 1; got 0"):
        pred.forecast_std(0)
    with pytest.raises(ValueError, match=r"`history`"):
        pred.predict_interval(np.zeros((50, 3)))


@pytest.mark.parametrize("ma,ar", [([1.0], [1.0, -1.3, 0.6]),   # AR(2), complex roots
                                   ([1.0, 0.6], [1.0, -0.8])])   # ARMA(1, 1)
def test_order_search_finds_the_true_order(ma, ar):
    """BIC selects the simulated order; AIC (not consistent) may add terms, not drop one.

    At n = 10^4 a spurious term lowers ``n log sigma^2`` by a chi-square(1) variable,
    below BIC's ``log n = 9.2`` with probability 0.998, while a missing term of these
    processes costs ``n log`` of a variance inflation of ~1e-2 or more (hundreds of
    units) under either criterion.
    """
    true = (len(ar) - 1, len(ma) - 1)
    for seed in range(3):
        x = lfilter(ma, ar, np.random.default_rng(seed).standard_normal(10_000))
        assert tuple(ARMAPredictor(order="bic").fit(x).orders_[0]) == true
        p, q = ARMAPredictor(order="aic").fit(x).orders_[0]
        assert p >= true[0] and q >= true[1], (seed, p, q)


def test_order_options_validation_and_full_aic_grid():
    x = _arma23(1500, 26)
    sel = ARMAPredictor(order="bic", max_order=2).fit(x)
    assert sel.criterion_.shape == (1, 3, 3) and np.all(np.isfinite(sel.criterion_))
    assert ARMAPredictor(order=(0, 0)).fit(x).orders_.tolist() == [[0, 0]]
    assert ARMAPredictor(order="aic", max_order=0).fit(x).orders_.tolist() == [[0, 0]]
    cases = [
        ({"order": "hqic"}, ValueError, r"`order` must be one of 'aic', 'bic'; got 'hqic'"),
        ({"order": "aic", "max_order": -1}, ValueError, r"`max_order` must be an int >= 0; got -1"),
        ({"order": "aic", "max_order": 21}, ValueError,
         r"`max_order` must be an int <= 20; got 21"),
        ({"order": 3}, TypeError, r"`order` must be a \(p, q\) tuple or 'aic'/'bic'; got 3"),
        ({"order": (-1, 1)}, ValueError, r"`order\[0\] \(p\)` must be an int >= 0; got -1"),
        ({"order": (51, 1)}, ValueError, r"`order\[0\] \(p\)` must be an int <= 50; got 51"),
        ({"order": (1, -1)}, ValueError, r"`order\[1\] \(q\)` must be an int >= 0; got -1"),
        ({"order": (1, 51)}, ValueError, r"`order\[1\] \(q\)` must be an int <= 50; got 51"),
        ({"order": (2, 3), "long_order": 2}, ValueError, r"`long_order` must be an int >= 3"),
    ]
    for kwargs, exc, msg in cases:
        with pytest.raises(exc, match=msg):
            ARMAPredictor(**kwargs).fit(x)
