"""The untested-DM warning calls a periodic loss differential periodic, not persistent.

Adversarial round 41 PART b, issue 27 (row F01): `modalinfo forecast` of a clean 50 Hz
line at 1 kHz with the paper's fixed-weight linear predictor said "no honest
Diebold-Mariano test ... linear at h = 3 (~3.1e+06 effective origins) ... too persistent
for its 1998 origins": more effective origins than origins. The predictor's error on a
sinusoid is a sinusoid (x[t+h] - (x[t] + h (x[t] - x[t-1])), analytic), so the squared
loss differential is periodic: its spectrum vanishes at frequency 0, where
N gamma_0 / (2 pi f(0)) (the effective origins) exceeds N. Reference: that algebra and
numpy's sinusoid.
"""

from __future__ import annotations

import warnings

import numpy as np

from modalinfo.forecast import LinearPredictor, evaluate
from modalinfo.telemetry import ModalLog


def test_a_periodic_differential_is_not_called_persistent_with_more_origins():
    t = np.arange(4000) / 1000.0
    x = np.sin(2 * np.pi * 50.0 * t + 0.3)[:, None]
    x = x + 1e-3 * np.random.default_rng(41).standard_normal(x.shape)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        evaluate({"linear": LinearPredictor()}, ModalLog(x, rate=1000.0), horizons=[3])
    msgs = [str(w.message) for w in caught if "Diebold-Mariano" in str(w.message)]
    assert len(msgs) == 1
    assert "periodic" in msgs[0]
    assert "effective origins)" not in msgs[0]
