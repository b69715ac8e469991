"""Short closed-loop logs raise no calibration-event warning in ``order_modes``.

Reference: ``kaos_like`` closed-loop logs are stationary by construction (no event was put
in them), so every CalibrationEventWarning on them is false; before the frame floor, 12 of
20 logs of 120 frames warned (a "mean step" at p < 1e-8 from the modes' own wander). The
events of round 52 PART a are still named on their 20,000-frame logs
(tests/ordering/test_calibration_events_fix53a.py).
"""

import warnings

import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes
from modalinfo.ordering.orderings import CALIBRATION_MIN_FRAMES
from modalinfo.telemetry import CalibrationEventWarning
from modalinfo.telemetry.synthetic import kaos_like


@pytest.mark.parametrize("n_frames", [120, 200])
def test_short_stationary_logs_are_silent(n_frames):
    assert n_frames < CALIBRATION_MIN_FRAMES
    warned = 0
    for seed in range(8):
        log = kaos_like(n_frames=n_frames, seed=seed)
        basis = ZernikeBasis(Pupil(24), log.modes)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            order_modes(log, basis, "variance", n_resamples=0)
        warned += any(issubclass(w.category, CalibrationEventWarning) for w in caught)
    assert warned == 0
