"""A fitted predictor refuses data it certainly was not trained for (fix56-b).

References: the exact AR(1) process (phi 0.9, unit innovations), whose one-step mean
squared error with the true coefficient is 1 (the innovation variance), so a fit fed its
own process in its own units forecasts at MSE 1; the same data in other units (x80:
nm against rad at 500 nm, x1e-7: m) have the training rms times that factor, exactly.
A ``ModalLog``'s stated rate and units are compared as stated. Before fix56-b a
predictor fitted on an array ran in ``closedloop.simulate`` unchecked (fix54-b's Left):
``Predictor.check_fed`` did not exist (every test here fails on c423e5eb).

False-failure rate: the MSE test's margin is 5 standard errors of a mean of 3,999 x 8
squared unit normals (s.e. sqrt(2 / 31,992) = 0.0079; the two fitted weights add
O(2 / n) = 5e-4), P < 1e-6; the scale ratio of two draws of one process is within
x1.2 (seeds fixed), far from the x10 cut.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import LinearPredictor
from modalinfo.telemetry.log import ModalLog

PHI = 0.9


def _ar1(n: int, m: int, seed: int) -> np.ndarray:
    e = np.random.default_rng(seed).standard_normal((n, m))
    return lfilter([1.0], [1.0, -PHI], e, axis=0)


def _fitted() -> LinearPredictor:
    # least-squares (a, b): on AR(1) a -> phi, b -> 0, the exact one-step predictor
    return LinearPredictor(fit_weights=True, horizon=1).fit(_ar1(4000, 8, 56201))


def test_its_own_process_passes_and_forecasts_at_the_exact_mse():
    p = _fitted()
    fresh = _ar1(4000, 8, 56202)
    said = p.check_fed(fresh[::250], rate=1000.0, units="rad", wavelength=5e-7)
    assert said.startswith("scale x")  # an array states no rate nor units
    # one-step forecasts over the fresh series (online, as the loop feeds it)
    p.reset()
    out = np.array([p.update(x)[0] for x in fresh[:-1]])
    mse = float(np.mean((out[50:] - fresh[51:]) ** 2))
    assert mse == pytest.approx(1.0, abs=5 * np.sqrt(2 / out[50:].size))


@pytest.mark.parametrize("factor", [79.577, 1e-7, 1e7])
def test_data_in_other_units_are_refused(factor):
    p = _fitted()
    fresh = _ar1(4000, 8, 56203)
    with pytest.raises(ValueError, match=r"times the rms of the data LinearPredictor was "
                       r"fitted on .*beyond x10 either way"):
        p.check_fed(fresh[::250] * factor, name="the feed")
    p.check_fed(fresh[::250] * 3.0)  # seeing: x3 in rms is not a unit mix-up


def test_the_ratio_is_the_median_of_the_modes():
    p = _fitted()
    fresh = _ar1(4000, 8, 56204)
    scaled = fresh.copy()
    scaled[:, :3] *= 1e6  # 3 of 8 modes off: the median stays with the 5 others
    p.check_fed(scaled)
    scaled[:, :5] *= 1e6
    with pytest.raises(ValueError, match="times the rms"):
        p.check_fed(scaled)


def test_a_logs_rate_and_units_are_compared():
    x = _ar1(4000, 4, 56205)
    p = LinearPredictor(fit_weights=True).fit(ModalLog(x, rate=1000.0))
    assert "rate 1000 Hz" in p.check_fed(rate=1000.5)  # within 1 %
    with pytest.raises(ValueError, match="fitted on frames at 1000 Hz; the data is at 2000 Hz"):
        p.check_fed(rate=2000.0)
    nm = LinearPredictor(fit_weights=True).fit(
        ModalLog(x, rate=1000.0, units="nm", wavelength=5e-7))
    with pytest.raises(ValueError, match="fitted on a log in nm; the data is in rad"):
        nm.check_fed(units="rad")
    rad = LinearPredictor(fit_weights=True).fit(ModalLog(x, units="rad", wavelength=5e-7))
    with pytest.raises(ValueError, match="phase .rad. at 5e-07 m; the data is phase at 1e-06"):
        rad.check_fed(units="rad", wavelength=1e-6)
    assert rad.check_fed(units="rad", wavelength=5e-7) == "units rad at 5e-07 m"


def test_an_array_fit_states_no_rate_nor_units():
    p = _fitted()
    assert not hasattr(p, "training_log_")  # an array states no clock nor units
    assert p.check_fed(rate=2000.0, units="nm", wavelength=1e-6) == ""
    np.testing.assert_allclose(p.training_rms_,
                               np.sqrt(np.mean(_ar1(4000, 8, 56201) ** 2, axis=0)),
                               rtol=1e-12)


def test_a_sample_of_other_modes_is_refused():
    with pytest.raises(ValueError, match=r"`sample` must have 8 mode\(s\)"):
        _fitted().check_fed(np.ones((16, 7)))


def test_fit_names_a_loop_closing_by_the_innovations_scale():
    # the first 5 % at x10 (round 52 a's L39, the loop closing): the level and spread
    # rules name none of 20 such logs, the scale rule 20 of 20 (docs/ADVERSARIAL.md,
    # fix56-b); before fix56-b fit left the scale rule out and stayed silent
    from modalinfo.telemetry import CalibrationEventWarning

    x = _ar1(5000, 10, 56206) * np.sqrt(1 - PHI**2)
    x[:250] *= 10.0
    with pytest.warns(CalibrationEventWarning, match=r"innovations' scale changes x[\d.]+ in "
                      r"frames 4-"):
        LinearPredictor(fit_weights=True).fit(x)


def test_fixed_weights_learn_nothing_and_take_any_scale():
    # the paper's a = 2, b = -1 and persistence: the parameters are the same whatever the
    # data, so data of another scale serve them (a legitimate use, not refused)
    from modalinfo.forecast import PersistencePredictor

    fresh = _ar1(4000, 8, 56207)
    for p in (LinearPredictor(horizon=1), PersistencePredictor(horizon=1)):
        p.fit(_ar1(300, 8, 56208) * 0.01)
        assert "no scale" in p.check_fed(fresh[::250])
