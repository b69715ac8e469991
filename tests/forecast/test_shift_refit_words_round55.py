"""The train/test scale-shift words when the predictors are refitted (round 55 PART b, O01).

Reference: a planted change, an AR(1) 0.9 log (``scipy.signal.lfilter``) whose innovations
double from the middle frame, scored with ``refit_every``: the shift is real (named), but
the predictors were refitted on the recent frames, the very retraining the words advised
("split the log at the change or retrain") to a user who had just asked for it. Without
refits the advice stays.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import LinearPredictor, evaluate


@pytest.fixture(scope="module")
def stepped():
    rng = np.random.default_rng(55)
    e = rng.standard_normal((4000, 2))
    e[2000:] *= 2.0
    return lfilter([1.0], [1.0, -0.9], e, axis=0)


def _shift_warnings(rec):
    return [str(w.message) for w in rec if "differ in scale" in str(w.message)]


def test_refits_change_the_advice(stepped):
    with pytest.warns(UserWarning) as rec:
        ev = evaluate({"ls": LinearPredictor(fit_weights=True)}, stepped, horizons=1,
                      refit_every=200, window=1000)
    words = _shift_warnings(rec)
    assert len(words) == 1
    assert "refitted every 200 frames on the last 1000 frames" in words[0]
    assert "retrain" not in words[0]
    line = [s for s in ev.summary().splitlines() if s.startswith("Train/test scale shift")]
    assert line and "refitted every 200" in line[0] and "retrain" not in line[0]


def test_without_refits_the_advice_stays(stepped):
    with pytest.warns(UserWarning) as rec:
        ev = evaluate({"ls": LinearPredictor(fit_weights=True)}, stepped, horizons=1)
    words = _shift_warnings(rec)
    assert len(words) == 1 and "retrain on frames like the test ones" in words[0]
    assert "split the log at the change or retrain" in ev.summary()
