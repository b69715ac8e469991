"""Mutation round 36 (review36): ``order_modes``' calibration-event warning.

Plants that escaped stop 60's tests (docs/MUTATION.md, "Round 36"):
``CALIBRATION_LEVEL_P`` 1e-8 -> 1e-7, a numpy ``True`` for ``quality`` refused, and the
ordering without a dead mode running the pass (and warning) a second time.

References (outside the code): the documented level, 1e-6 since fix56-a (1e-8 before;
``CALIBRATION_LEVEL_P``'s comment and docs/ADVERSARIAL.md "Long memory, what fix54-a left
(fix56-a)"; the plant of review 36 was the next decade up, 1e-7 -> here 1e-5), applied
to level steps given in the report (p values by construction); the planted +3 sd step
and the planted dead mode.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes
from modalinfo.telemetry import CalibrationEventWarning, ModalLog, assess_quality

MODES = list(range(2, 10))
N, STEP = 20000, 12000
RMS = np.linspace(1.0, 0.3, len(MODES))
BASIS = ZernikeBasis(Pupil(32), MODES)


def _clean(seed: int = 1) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((N + 2000, len(MODES))) * np.sqrt(1.0 - 0.81)
    return lfilter([1.0], [1.0, -0.9], e, axis=0)[2000:] * RMS


def _log(c):
    return ModalLog(c, rate=2000.0, modes=MODES, units="rad")


@pytest.mark.parametrize("p_value, warned", [(5e-6, False), (5e-7, True)])
def test_level_steps_are_named_below_one_in_1e6(p_value, warned):
    c = _clean()
    report = dataclasses.replace(assess_quality(_log(c)),
                                 level_steps=(("Z5", STEP, 0.5, p_value),),
                                 variance_steps=(), step_lines=(), scale_steps=())
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        order_modes(_log(c), BASIS, "variance", quality=report)
    named = [str(w.message) for w in rec if w.category is CalibrationEventWarning]
    assert len(named) == int(warned)
    if warned:
        assert "Z5: the mean steps or drifts by +0.5 at frame 12000" in named[0]


def test_a_numpy_true_runs_the_pass():
    c = _clean()
    c[STEP:, MODES.index(5)] += 3.0 * c[:, MODES.index(5)].std()
    with pytest.warns(CalibrationEventWarning, match="Z5: the mean steps"):
        order_modes(_log(c), BASIS, "variance", quality=np.bool_(True))


def test_a_dead_mode_does_not_warn_twice():
    # the modes but the dead one are ordered by a second order_modes call, which must
    # not run the pass again
    c = _clean()
    c[STEP:, MODES.index(5)] += 3.0 * c[:, MODES.index(5)].std()
    c[:, MODES.index(9)] = 0.0
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        result = order_modes(_log(c), BASIS, "mi_marginal", n_resamples=0, seed=1)
    named = [w for w in rec if w.category is CalibrationEventWarning]
    assert len(named) == 1
    assert BASIS.labels[result.order[-1]] == "Z9"   # the dead mode appended last


def test_two_events_of_one_mode_count_one_mode():
    c = _clean()
    report = dataclasses.replace(
        assess_quality(_log(c)), level_steps=(("Z5", 3000, 0.8, 1e-30),),
        variance_steps=(("Z5", 15000, 10.0, 1e-30),), step_lines=(), scale_steps=())
    with pytest.warns(CalibrationEventWarning,
                      match=r"event in 1 of the 8 modes ranked \(Z5: the mean steps or "
                            r"drifts by \+0.8 at frame 3000; Z5: the spread steps x10 at "
                            r"frame 15000\)"):
        order_modes(_log(c), BASIS, "variance", quality=report)


def test_a_report_of_other_frames_is_refused():
    c = _clean()
    shorter = assess_quality(_log(c[:15000]))        # same labels, 15,000 frames
    with pytest.raises(ValueError, match="got one of 15000 frames"):
        order_modes(_log(c), BASIS, "variance", quality=shorter)
