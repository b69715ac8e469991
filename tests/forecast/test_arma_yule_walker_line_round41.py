"""A Yule-Walker AR(p) that fits far worse than least squares is said, not silent.

Adversarial round 41 PART a, issue 27 (row V28): ``ARMAPredictor(order=(2, 0))`` on a
noise-free 37.3 Hz line (1 kHz) fits phi = (1.9345, -0.9894) by Yule-Walker on the biased
autocovariance, where the line is exactly ``x_t = 2 cos(w) x_{t-1} - x_{t-2}`` (1.9453,
-1): a 5-step RMSE of 0.022 of the amplitude, numpy's least squares 7e-14. The fit is kept
(the paper's estimator); ``fit`` warns. References: the recursion's exact coefficients
(trigonometric identity), numpy ``lstsq`` of the same AR(2) (its in-sample residuals),
and, for the series that must stay unwarned, AR(1) / white noise from numpy's generator
(Yule-Walker and least squares agree there to ~p / n).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import ARMAPredictor


def _fit(x, order):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = ARMAPredictor(order=order).fit(x)
    return model, [str(w.message) for w in caught]


def test_a_noise_free_line_warns_with_the_ratio_and_keeps_the_yule_walker_fit():
    w = 2 * np.pi * 37.3 / 1000.0
    x = np.sin(w * np.arange(2000) + 0.3)
    model, msgs = _fit(x, (2, 0))
    yw = [m for m in msgs if "Yule-Walker" in m]
    assert len(yw) == 1, msgs
    assert "column 0: AR(2), x" in yw[0]
    assert "least-squares" in yw[0] and "linear-ls" in yw[0]
    # the ratio it names: numpy's least squares is exact on the line (residual ~1e-14)
    design = np.column_stack([x[1:-1], x[:-2]])
    coef = np.linalg.lstsq(design, x[2:], rcond=None)[0]
    np.testing.assert_allclose(coef, [2 * np.cos(w), -1.0], atol=1e-9)
    ratio = float(yw[0].split("AR(2), x")[1].split(")")[0])
    assert ratio > 10
    # warned, not switched: the Yule-Walker coefficients are still off by ~1e-2
    assert abs(model.ar_coef_[0, 1] + 1.0) > 1e-3


@pytest.mark.parametrize("noise", [0.0, 1e-6])
def test_a_line_warns_at_every_noise_floor_far_below_its_amplitude(noise):
    rng = np.random.default_rng(41)
    x = np.sin(2 * np.pi * 5.0 / 1000.0 * np.arange(2000) + 0.3)
    x = x + noise * rng.standard_normal(x.size)
    _, msgs = _fit(x, (3, 0))
    assert sum("Yule-Walker" in m for m in msgs) == 1, msgs


@pytest.mark.parametrize("a", [0.0, 0.9, 0.99, 0.999])
def test_ar1_and_white_noise_stay_unwarned(a):
    rng = np.random.default_rng(7)
    x = lfilter([1.0], [1.0, -a], rng.standard_normal(2500))[500:]
    for order in [(1, 0), (2, 0)]:
        _, msgs = _fit(x, order)
        assert not [m for m in msgs if "Yule-Walker" in m], msgs


def test_a_noisy_line_stays_unwarned():
    # noise 0.1 of the amplitude: Yule-Walker and least squares agree (ratio 1.00)
    rng = np.random.default_rng(3)
    x = np.sin(2 * np.pi * 37.3 / 1000.0 * np.arange(2000) + 0.3)
    x = x + 0.1 * rng.standard_normal(x.size)
    _, msgs = _fit(x, (2, 0))
    assert not [m for m in msgs if "Yule-Walker" in m], msgs
