"""The batch forecast row names the Diebold-Mariano pairs ``forecast`` warns of (fix48-b).

Fixes 47-c left it: ``modalinfo/batch/analyses.py``'s ``_forecast`` silences ``evaluate``'s
two Diebold-Mariano warnings (no honest test; persistent volatility), a worker's warning
reaching no one, and the row said only ``beats_baseline_h1``: a batch user could not learn
which pairs ``modalinfo forecast`` would have named. The row now carries ``dm_untested`` /
``dm_flagged`` (counts over every horizon) and ``dm_untested_pairs`` /
``dm_flagged_pairs``. References, outside the batch code: the same log through
:func:`modalinfo.forecast.evaluate` called directly, whose warnings name the pairs (round 46
PART a P43's seed 9152, two forecasts of equal MSE, flagged; the batch suite's AR(1) log 2,
whose ARMA pair is declined), and a hand-written mask for the compact text.
"""

from __future__ import annotations

import warnings

import numpy as np
from scipy.signal import lfilter

from modalinfo.batch import analyses
from modalinfo.forecast import LinearPredictor, evaluate
from modalinfo.telemetry import ModalLog


def _warned(log, predictors):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        evaluate(predictors, log, train=0.5, horizons=[1], keep_series=1, chunk_frames=2048)
    return [str(w.message) for w in caught]


def test_a_flagged_pair_is_named_in_the_row(monkeypatch):
    e = np.random.default_rng(9152).normal(size=2000)
    x = lfilter([1.0], [1.0, -0.9], e)[1000:]
    log = ModalLog(x[:, None], rate=1000.0, modes=[2], units="rad")
    said = _warned(log, {"c": LinearPredictor(a=0.8, b=0.0)})
    assert any("persistent volatility" in m and "c at h = 1" in m for m in said), said
    import modalinfo.forecast.presets as presets
    monkeypatch.setattr(presets, "make_predictor", lambda name: LinearPredictor(a=0.8, b=0.0))
    params = {"predictors": "c", "horizon": 1, "train": 0.5, "modes": None}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the row says it; nothing escapes the task
        row = analyses._forecast(log, params)
    assert row["beats_baseline_h1.c"] is False
    assert (row["dm_flagged"], row["dm_flagged_pairs"]) == (1, "c h1")
    assert (row["dm_untested"], row["dm_untested_pairs"]) == (0, "")


def test_an_untested_pair_is_named_in_the_row(helpers):
    from modalinfo.forecast.presets import make_predictor

    log = helpers.make_log(2)  # test_forecast_untested_merge12's log: ARMA declined at h = 1
    said = _warned(log, {"arma": make_predictor("arma")})
    assert any("no honest Diebold-Mariano test" in m and "arma at h = 1" in m
               for m in said), said
    params = {"predictors": "arma", "horizon": 1, "train": 0.5, "modes": None}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        row = analyses._forecast(log, params)
    assert (row["dm_untested"], row["dm_untested_pairs"]) == (1, "arma h1")
    assert np.isnan(row["pvalue_h1.arma"])


def test_pairs_text_is_compact_per_predictor():
    mask = np.array([[True, True, True, False, True],
                     [False, False, False, False, False],
                     [False, True, False, False, False]])
    text = analyses._pairs_text(("ar", "mean", "var"), np.arange(1, 6), mask)
    assert text == "ar h1-3,5; var h2"
