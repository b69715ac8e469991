"""``linear-ls`` fits an intercept: static offsets cost no skill (round 40 PART a, S01).

``LinearPredictor(fit_weights=True)`` fitted ``x_t = a x_{t-1} + b x_{t-2}`` with no
intercept, so an offset of a mode forced ``a + b`` toward 1: on an AR(1) 0.9 mode of
1e-3 rad + 1e6 rad the h = 5 gain over persistence fell from 1.11 to 1.00. Fix 41-a
fits ``x_t = c + a x_{t-1} + b x_{t-2}``. References, from outside the code:

- the translation law: forecasts of ``x + d`` are the forecasts of ``x`` plus ``d``
  (an intercept model is translation-invariant), to the float error of values of
  size ``d`` (64 ulps of 1e6, 1.5e-8, against fluctuations of 2e-3);
- statsmodels ``AutoReg(lags=2, trend="c")``: the same least-squares problem, its
  ``params`` (const, a, b) to rtol 1e-8 on well-conditioned data;
- an analytic law: a noise-free AR(2) ``x_k = 1.5 x_{k-1} - 0.7 x_{k-2}`` about 0 is
  fitted exactly (``c = 0``), about 5 exactly too (``c = 5 (1 - 1.5 + 0.7) = 1``);
- the h-step forecast written out in NumPy from the fitted ``(c, a, b)``.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate

from .conftest import ar1


def _ar2_law(n, start=(1.0, 0.3), level=0.0):
    x = np.zeros(n)
    x[:2] = start
    for t in range(2, n):
        x[t] = 1.5 * x[t - 1] - 0.7 * x[t - 2]
    return x + level


@pytest.mark.parametrize("offset", [1e3, 1e6])
def test_forecasts_translate_with_the_series(offset):
    x = ar1(0, 600) * 1e-3  # AR(1) 0.9 of 1e-3 rad
    tol = 64 * np.finfo(float).eps * offset
    plain = LinearPredictor(fit_weights=True, horizon=5).fit(x[:300])
    moved = LinearPredictor(fit_weights=True, horizon=5).fit(x[:300] + offset)
    np.testing.assert_allclose(moved.coef_, plain.coef_, rtol=1e-6)
    for end in (310, 450, 600):
        np.testing.assert_allclose(moved.predict(x[:end] + offset) - offset,
                                   plain.predict(x[:end]), rtol=0, atol=tol)
    # online (the closed loop's path) = offline
    moved.reset()
    for t in range(450):
        online = moved.update(x[t] + offset)
    np.testing.assert_array_equal(online, moved.predict(x[:450] + offset))


def test_skill_is_unchanged_by_an_offset():
    x = ar1(0, 4000) * 1e-3
    gains = [evaluate({"linear-ls": LinearPredictor(fit_weights=True)}, x + d,
                      horizons=[1, 5]).gain[-1] for d in (0.0, 1e3, 1e6)]
    # before fix 41-a: h = 5 gains ~1.11 fell to ~1.00 at 1e3 and 1e6
    assert np.all(gains[0][1] > 1.08)
    np.testing.assert_allclose(gains[1], gains[0], rtol=1e-6)
    np.testing.assert_allclose(gains[2], gains[0], rtol=1e-6)


@pytest.mark.parametrize("offset", [0.0, 3.0, 1e3])
def test_params_are_statsmodels_autoreg_with_a_constant(offset):
    from statsmodels.tsa.ar_model import AutoReg

    rng = np.random.default_rng(7)
    x = np.zeros(800)
    for t in range(2, x.size):
        x[t] = 1.2 * x[t - 1] - 0.5 * x[t - 2] + rng.standard_normal()
    x += offset
    fit = AutoReg(x, lags=2, trend="c").fit()
    pred = LinearPredictor(fit_weights=True).fit(x)
    np.testing.assert_allclose(pred.coef_[0], fit.params[1:], rtol=1e-8)
    # the constant: rtol 1e-8 of the offset's size (0 at offset 0: atol of the noise's)
    np.testing.assert_allclose(pred.intercept_[0], fit.params[0], rtol=1e-8,
                               atol=1e-10 * (1.0 + offset))


@pytest.mark.parametrize("level", [0.0, 5.0])
def test_a_noise_free_law_is_fitted_exactly(level):
    x = _ar2_law(120, level=level)
    pred = LinearPredictor(fit_weights=True, horizon=4).fit(x)
    np.testing.assert_allclose(pred.coef_[0], [1.5, -0.7], rtol=0, atol=1e-8)
    np.testing.assert_allclose(pred.intercept_[0], level * 0.2, rtol=0, atol=1e-8)
    # the h-step forecasts continue the law (NumPy's own continuation)
    more = _ar2_law(130, level=level)
    np.testing.assert_allclose(pred.predict(x), more[120:124], rtol=0, atol=1e-8)


def test_forecasts_follow_the_fitted_recursion():
    x = ar1(3, 400)[:, 0] + 2.5
    pred = LinearPredictor(fit_weights=True, horizon=3).fit(x)
    (a, b), c = pred.coef_[0], pred.intercept_[0]
    hist = list(x[-2:])
    for _ in range(3):
        hist.append(c + a * hist[-1] + b * hist[-2])
    np.testing.assert_allclose(pred.predict(x), hist[2:], rtol=1e-12)


def test_fixed_weights_have_no_intercept_and_the_rule_counts_three_parameters():
    x = ar1(1, 50)[:, 0] * 1e-3 + 4.0
    fixed = LinearPredictor().fit(x)
    np.testing.assert_array_equal(fixed.intercept_, [0.0])
    np.testing.assert_allclose(fixed.predict(x, 2), x[-1] + np.array([1, 2]) * (x[-1] - x[-2]),
                               rtol=1e-15)
    assert LinearPredictor(fit_weights=True).min_samples() == 32
    with pytest.raises(ValueError, match=r"at least 32 samples .*3 parameters"):
        LinearPredictor(fit_weights=True).fit(x[:31])
