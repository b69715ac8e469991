"""Round 39 PART a, M43 / M46: ``evaluate`` gives ``InfoPredictor`` the log's modes.

``InfoPredictor(candidates="radial")`` reads radial orders from ``mode_labels``
(default ``Z2, Z3, ...``). Under ``evaluate`` it was never told the log's modes: on a log
without tip-tilt (Z4..Z9) its columns were read as Z2..Z7, so the radial candidate sets
were those of other modes (RMSE 0.2 % off); ``mode_labels`` of another log were taken.
Reference: the radial orders of Noll (1976) (Z4-Z6 n = 2, Z7-Z9 n = 3), i.e. the same
predictor fitted with ``mode_labels`` = the log's labels, and the refusal rule.
"""

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.forecast import InfoPredictor, evaluate
from modalinfo.telemetry import ModalLog


def _log(modes, convention="noll"):
    r = np.random.default_rng(5)
    e = r.normal(size=(1500, len(modes)))
    x = lfilter([1.0], [1.0, -0.9], e, axis=0)
    x[:, 1:] += 0.6 * np.roll(x[:, :-1], 1, axis=0)  # couplings across radial orders
    return ModalLog(x, rate=1000.0, modes=modes, convention=convention)


def _info(**kw):
    return InfoPredictor(candidates="radial", radial_width=0, horizon=1, max_lag=3, **kw)


def test_the_log_modes_are_the_radial_labels():
    log = _log(list(range(4, 10)))
    got = evaluate({"info": _info()}, log, horizons=[1])
    ref = evaluate({"info": _info(mode_labels=list(log.labels))}, log, horizons=[1])
    np.testing.assert_array_equal(got.rmse, ref.rmse)
    # an array has no modes: the documented default Z2.. holds, and differs here
    default = evaluate({"info": _info()}, np.asarray(log.coeffs), horizons=[1])
    assert not np.array_equal(default.rmse[-1], ref.rmse[-1])


def test_an_ansi_log_is_read_in_noll():
    log = _log(list(range(3, 9)), convention="ansi")  # A3..A8: radial orders 2 and 3
    from modalinfo.bases import ansi_to_noll

    noll = [f"Z{ansi_to_noll(j)}" for j in range(3, 9)]
    got = evaluate({"info": _info()}, log, horizons=[1])
    ref = evaluate({"info": _info(mode_labels=noll)}, log, horizons=[1])
    np.testing.assert_array_equal(got.rmse, ref.rmse)


def test_mode_labels_of_another_log_refused():
    log = _log(list(range(2, 8)))
    with pytest.raises(ValueError, match=r"`predictors\['info'\]\.mode_labels`"):
        evaluate({"info": _info(mode_labels=[f"Z{j}" for j in range(4, 10)])}, log,
                 horizons=[1])


def test_level_step_warning_names_the_column_not_a_mode_number():
    """M42: under ``evaluate`` the ARMA fit's ``LevelStepWarning`` said "mode 5" for the
    log's column 5 (Z7 of a Z2.. log). Reference: the column numpy holds the step in."""
    from modalinfo._stats import LevelStepWarning
    from modalinfo.forecast import ARMAPredictor

    r = np.random.default_rng(2)
    x = r.normal(size=(3000, 6))
    x[700:1500, 5] += 3.0  # a level step in column 5 of the training half
    log = ModalLog(x, rate=1000.0)  # Z2..Z7: column 5 is Z7
    with pytest.warns(LevelStepWarning, match=r"column 5: sample") as rec:
        evaluate({"arma": ARMAPredictor(order=(1, 0))}, log, horizons=[1])
    assert not any("mode 5" in str(w.message) for w in rec)
