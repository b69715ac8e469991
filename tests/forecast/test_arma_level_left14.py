"""ARMAPredictor.fit warns when the training series' mean steps (issue 27, left14-level).

References, outside the code under test: planted facts. Round 14 PART a d02: an AR(1)
series of phi = 0.9 with a step in its mean half way was fitted with phi = 0.994 and no
word; the fitted coefficient of the step-free series is within its sampling error of 0.9
(sd sqrt((1 - 0.81) / 4000) = 0.007); the same series without the step is not warned.
Since fix54-b the step of this 4,000-sample history is named by ``Predictor.fit``'s
calibration-event warning, ARMA's ``LevelStepWarning`` staying for what that one leaves
(shorter histories, steps below its p cut).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo._stats import LevelStepWarning
from modalinfo.forecast import ARMAPredictor
from modalinfo.telemetry import CalibrationEventWarning


def _series(seed: int, step: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((7000, 2))
    x = lfilter([1.0], [1.0, -0.9], e, axis=0)[3000:] * math.sqrt(1 - 0.81)
    x[2000:, 0] += step
    return x


def test_a_level_step_fitted_as_persistence_is_warned_once():
    # fix54-b: on a history of >= 2,000 frames Predictor.fit's calibration-event warning
    # (the quality pass's rule) names the step, and ARMA's own rule does not repeat it
    x = _series(20, 6.5)
    with pytest.warns(CalibrationEventWarning, match=r"column 0: the mean steps or drifts "
                      r"by \+6\.\d+ at frame 20\d\d") as rec:
        fit = ARMAPredictor(order=(1, 0)).fit(x)
    assert sum(issubclass(w.category, (LevelStepWarning, CalibrationEventWarning))
               for w in rec) == 1
    assert fit.ar_coef_[0, 0] > 0.97  # the step read as persistence (what is warned)
    assert fit.ar_coef_[1, 0] == pytest.approx(0.9, abs=0.03)  # 4 sd of 0.007


def test_a_stationary_series_is_not_warned():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        fit = ARMAPredictor(order=(1, 0)).fit(_series(21, 0.0))
    assert fit.ar_coef_[0, 0] == pytest.approx(0.9, abs=0.03)
