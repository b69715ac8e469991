"""Round 15 PART a: the ``evaluate`` verdict where no Diebold-Mariano test can run.

Reference: a pure sinusoid is predictable exactly by an AR(2) recursion
(``x[t+1] = 2 cos(w) x[t] - x[t-1]``, an analytic identity), so a fitted ARMA forecast is
orders of magnitude better than persistence; the summary must then not say that no
predictor beats the baseline when no test could be run (the test's p-values are NaN).
White noise (the training mean is the optimal forecast) keeps the "no predictor beats"
verdict.
"""

from __future__ import annotations

import warnings

import numpy as np

from modalinfo.forecast import ARMAPredictor, evaluate
from modalinfo.telemetry import ModalLog


def test_sinusoid_untestable_is_not_called_skill_free():
    t = np.arange(4000) / 1000.0
    log = ModalLog(np.c_[np.sin(2 * np.pi * 7 * t), np.cos(2 * np.pi * 13 * t)],
                   rate=1000.0, modes=[2, 3])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ev = evaluate({"arma": ARMAPredictor()}, log, train=0.5, horizons=[1])
    i = ev.index("arma")
    # the analytic AR(2) identity: far better than persistence
    assert ev.gain_wavefront[i, 0] > 100
    assert np.isnan(ev.pvalue[i, 0])
    text = ev.summary()
    assert "No predictor beats" not in text
    assert "Not tested against the best trivial baseline" in text


def test_white_noise_verdict_kept():
    x = np.random.default_rng(4).standard_normal((2000, 2))
    ev = evaluate({"arma": ARMAPredictor(order=(1, 1))}, x, train=0.5, horizons=[1, 2])
    assert not np.isnan(ev.pvalue[ev.index("arma")]).any()
    text = ev.summary()
    assert "No predictor beats the best trivial baseline" in text
    assert "could not be tested" not in text
