"""``Predictor.predict`` of a ModalLog: read by labels, refused on another clock or units.

Reference: round trip: ``predict(log)`` equals ``predict(log.coeffs)`` bit for bit
where the log is the kind the predictor was fitted on; and the definition of the
predictor's parameters, which count frames (a 2 kHz fit forecasts another series at
1 kHz) and are in the training log's units (an intercept and a training mean in rad are
wrong on nm). Round 55 PART b, X01-X07: ``fit`` took a ModalLog (fix54-b) but
``predict`` refused one with "(use log.coeffs)", whose array drops the labels, rate and
units that tell another log.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import LinearPredictor
from modalinfo.telemetry import ModalLog


def _log(rate=2000.0, seed=0, n=3000):
    rng = np.random.default_rng(seed)
    x = lfilter([1.0], [1.0, -0.9], rng.standard_normal((n, 3)), axis=0) * 0.1
    return ModalLog(x, rate=rate, modes=[2, 3, 4], units="rad", wavelength=5e-7)


@pytest.fixture(scope="module")
def fitted():
    return LinearPredictor(horizon=2, fit_weights=True).fit(_log()[:2000])


def test_same_kind_of_log_equals_its_values(fitted):
    other = _log(seed=1)
    assert np.array_equal(fitted.predict(other), fitted.predict(np.asarray(other.coeffs)))


def test_other_rate_refused(fitted):
    with pytest.raises(ValueError, match=r"LinearPredictor was fitted on frames at 2000 Hz; "
                                         r"`history` is at 1000 Hz"):
        fitted.predict(_log(rate=1000.0))


def test_other_units_and_wavelength_refused(fitted):
    log = _log(seed=1)
    with pytest.raises(ValueError, match=r"LinearPredictor was fitted on a log in rad; "
                                         r"`history` is in nm"):
        fitted.predict(log.to_units("nm"))
    with pytest.raises(ValueError, match=r"LinearPredictor was fitted on phase \[rad\] at "
                                         r"5e-07 m; `history` is phase at 6e-07 m"):
        fitted.predict(log.to_units("nm").to_units("rad", wavelength=6e-7))


def test_other_labels_refused(fitted):
    log = _log(seed=1)
    with pytest.raises(ValueError, match=r"has columns \(Z4, Z2, Z3\) .*history\.select"):
        fitted.predict(log.select(modes=["Z4", "Z2", "Z3"]))
    kl = ModalLog(np.asarray(log.coeffs), rate=2000.0, modes=["KL1", "KL2", "KL3"],
                  convention="labels", units="rad", wavelength=5e-7)
    with pytest.raises(ValueError, match=r"has columns \(KL1, KL2, KL3\)"):
        fitted.predict(kl)
    with pytest.raises(ValueError, match=r"must have 3 mode\(s\)"):
        fitted.predict(log.select(modes=["Z2", "Z3"]))


def test_array_fit_takes_a_log():
    p = LinearPredictor(horizon=1, fit_weights=True).fit(np.asarray(_log().coeffs))
    other = _log(rate=1000.0, seed=2)  # nothing known of the fit: read by position
    assert np.array_equal(p.predict(other), p.predict(np.asarray(other.coeffs)))


def test_update_takes_one_frame_of_a_log(fitted):
    # X09: update(log[k:k + 1]) read the log as x_t[0] and refused an indexing the caller
    # never wrote ("a ModalLog is indexed by a frame slice ...; got 0")
    log = _log(seed=1)
    p, q = fitted.clone().fit(_log()[:2000]), fitted.clone().fit(_log()[:2000])
    for k in range(5):
        assert np.array_equal(p.update(log[k:k + 1]), q.update(np.asarray(log.coeffs)[k]))
    with pytest.raises(ValueError, match=r"is at 1000 Hz"):
        p.update(_log(rate=1000.0)[0:1])
    with pytest.raises(ValueError, match=r"must be one sample; got a ModalLog of 2 frames"):
        p.update(log[0:2])
