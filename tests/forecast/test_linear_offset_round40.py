"""LinearPredictor(fit_weights=True) is fitted about the training mean (round 40 PART a S01).

References: the translation law (a forecast of ``x + c`` is the forecast of ``x`` plus ``c``
for any predictor that models a stationary series about its mean) and statsmodels'
``AutoReg(trend="c")`` least-squares AR(2) with an intercept (its lag weights equal the
centred fit's to O(1/n)). Before the fix the weights were fitted without an intercept: a
static offset of 1e6 on an AR(1) 0.9 mode of 1e-3 rad turned the h = 5 gain 1.107 into 1.001.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import LinearPredictor, evaluate


def _ar(coefs, n, seed, scale=1.0):
    rng = np.random.default_rng(seed)
    return scale * lfilter([1.0], np.r_[1.0, -np.asarray(coefs)], rng.standard_normal(n))


def test_offset_leaves_the_fitted_gains_unchanged():
    x = _ar([0.9], 4000, 0, 1e-3)[:, None]
    base = evaluate({"ls": LinearPredictor(fit_weights=True)}, x, train=2000, horizons=[1, 5])
    shifted = evaluate({"ls": LinearPredictor(fit_weights=True)}, x + 1e6, train=2000,
                       horizons=[1, 5])
    # the offset costs the float error of 1e6 against 1e-3 values: 1e6 * eps / 1e-3 ~ 2e-7
    np.testing.assert_allclose(shifted.gain_wavefront, base.gain_wavefront, rtol=1e-5)
    assert base.gain_wavefront[base.index("ls"), 1] > 1.05  # the skill the offset erased


def test_one_sd_offset_keeps_the_weights_of_an_intercept_fit():
    statsmodels = pytest.importorskip("statsmodels.tsa.ar_model")
    x = _ar([1.2, -0.4], 20000, 1) + 3.0              # stationary sd ~1.5; offset 2 sd
    fitted = LinearPredictor(fit_weights=True, horizon=1).fit(x[:, None])
    ref = statsmodels.AutoReg(x, lags=2, trend="c").fit().params[1:]
    # centred vs intercept least squares differ by O(1/n) = 5e-5 in the weights
    np.testing.assert_allclose(fitted.coef_[0], ref, atol=1e-3)
    np.testing.assert_allclose(fitted.coef_[0], [1.2, -0.4], atol=0.03)  # ~4 s.e.


def test_fixed_weights_still_ignore_the_mean():
    x = _ar([0.9], 500, 2)[:, None]
    a = LinearPredictor(horizon=3).fit(x[:100])
    b = LinearPredictor(horizon=3).fit(x[:100] + 50.0)
    pa, _ = a._forecast_path(x, 3)
    pb, _ = b._forecast_path(x + 50.0, 3)
    # from the second frame on (the first forecast has one sample of history)
    np.testing.assert_allclose(pb[1:] - 50.0, pa[1:], atol=1e-12)
