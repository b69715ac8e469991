"""`select_inputs` on a clean vibration line says its surrogates are no null.

Adversarial round 41 PART b, issue 27 (rows S01, S04): a 50 Hz line at 1 kHz (1e-3
noise) is an exact AR(2), x[t + 1] = 2 cos(w) x[t] - x[t - 1] (analytic), with Gaussian
I(x[t + 1]; x[t]) = -0.5 ln(1 - cos(w)^2) = 1.17 nats; a 250 Hz line has x[t + 1] =
-x[t - 1]. Time-shift surrogates of a sinusoid are linear combinations of its lags, so
they are as informative as the original: the search stopped at step 1 with "next gain
not significant (p = 0.08)" and no word. Now the stop reason says the surrogates stay
informative (a periodic series) and to judge the step by its gain. Reference: the
analytic AR(2) identity; AR(1) noise (numpy), whose surrogates share no alignment,
gets no such words.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import select_inputs
from modalinfo.telemetry import ModalLog

T = 4000


@pytest.mark.parametrize("freq", [50.0, 250.0])
def test_a_clean_line_stop_says_the_surrogates_are_no_null(freq):
    rng = np.random.default_rng(41)
    x = 1e-3 * rng.standard_normal((T, 3))
    x[:, 0] += np.sin(2 * np.pi * freq * np.arange(T) / 1000.0 + 0.3)
    res = select_inputs(ModalLog(x, rate=1000.0), "Z2", max_lag=4, n_surrogates=99,
                        intervals=False, seed=0)
    # found, or stopped with the reason the surrogates could not judge it
    assert res.inputs or "periodic series" in res.stop_reason


def test_noise_gets_no_periodic_words():
    rng = np.random.default_rng(41)
    e = rng.standard_normal((T, 3))
    x = np.zeros_like(e)
    for t in range(1, T):
        x[t] = 0.5 * x[t - 1] + e[t]
    res = select_inputs(ModalLog(x, rate=1000.0), "Z2", max_lag=3, n_surrogates=99,
                        intervals=False, seed=0)
    assert "periodic series" not in res.stop_reason
