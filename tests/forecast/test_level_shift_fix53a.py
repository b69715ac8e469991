"""A level change between the training and the test frames, named by ``evaluate`` (fix53-a).

Round 52 PART a, L05 / L45: ``evaluate`` named a scale shift between the training and test
frames but scored a +3 sd (or +1 sd) level change in the test frames without a word (the
mean baseline's gain 0.557 -> 0.202). ``ForecastEvaluation.level_shift`` is now the test
frames' mean minus the training frames', in units of the training frames' sd, tested
against the sampling error of the two means under the mode's persistence.

References (outside the code): the planted step (its size in training sds, by numpy's
means and standard deviation of the two segments); stationary AR(1) logs simulated with
``scipy.signal.lfilter`` for the silent cases (measured false warnings, docs/ADVERSARIAL.md
"Calibration events inside a log (fix53-a)": 0 of 150 AR(1) 0.9 / 0.95 logs of 10 modes,
2 of 50 at 0.99, 0 of 50 ``kaos_like`` closed-loop logs; the seeds below are fixed).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import evaluate


def _ar1(seed: int, n: int = 6000, m: int = 3, phi: float = 0.9) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n + 2000, m)) * np.sqrt(1.0 - phi**2)
    return lfilter([1.0], [1.0, -phi], e, axis=0)[2000:]


def _numpy_shift(x: np.ndarray, n_train: int) -> np.ndarray:
    return (x[n_train:].mean(axis=0) - x[:n_train].mean(axis=0)) / x[:n_train].std(axis=0)


def test_a_level_step_in_the_test_frames_is_named():
    x = _ar1(1)
    x[3600:, 1] += 3.0 * x[:, 1].std()        # +3 sd from 60 % of the log (L05's event)
    with pytest.warns(UserWarning, match="differ in level from the training frames") as rec:
        ev = evaluate({}, x, train=0.5, horizons=(1, 2))
    assert sum("differ in level" in str(w.message) for w in rec) == 1   # once
    msg = next(str(w.message) for w in rec if "differ in level" in str(w.message))
    assert ev.level_shifted_modes == (ev.labels[1],) and ev.labels[1] in msg
    np.testing.assert_allclose(ev.level_shift, _numpy_shift(x, 3000), rtol=1e-10,
                               atol=1e-12)
    assert 2.0 < ev.level_shift[1] < 2.8      # 3 sd over 80 % of the test frames
    assert any(ln.startswith("Train/test level shift") for ln in ev.summary().splitlines())


def test_every_mode_one_sd_up_is_named():
    # L45: every mode + 1 sd from 60 % of the log, 0.8 sd on the test frames' mean
    x = _ar1(2, n=20000)
    x[12000:] += x.std(axis=0)
    with pytest.warns(UserWarning, match="differ in level"):
        ev = evaluate({}, x, train=0.5, horizons=(1,))
    assert ev.level_shifted_modes == ev.labels


@pytest.mark.parametrize("seed", [11, 12, 13])
@pytest.mark.parametrize("phi", [0.9, 0.95])
def test_stationary_logs_are_silent(seed, phi):
    # the rule's level is 1 % family-wise over the modes: about 0.4 % per 4-mode log,
    # ~2.4 % that one of these 6 fails for a new seed (measured 0 of 100 10-mode logs at
    # these phi; at 0.99, 2 of 50 10-mode logs warned)
    x = _ar1(seed, n=20000, m=4, phi=phi)
    ev = evaluate({}, x, train=0.5, horizons=(1,))   # filterwarnings = error: no warning
    assert ev.level_shifted_modes == ()
    np.testing.assert_allclose(ev.level_shift, _numpy_shift(x, 10000), rtol=1e-10,
                               atol=1e-12)


def test_a_shift_under_half_an_sd_is_not_named():
    # significant (20,000 frames of white noise: the means' error is 0.014 sd) but under
    # LEVEL_SHIFT_MIN_SD = 0.5
    rng = np.random.default_rng(5)
    x = rng.standard_normal((20000, 2))
    x[10000:, 0] += 0.3
    ev = evaluate({}, x, train=0.5, horizons=(1,))
    assert ev.level_shifted_modes == ()
    assert 0.25 < ev.level_shift[0] < 0.35
