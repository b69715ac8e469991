"""A batch forecast row on a log too persistent for an honest Diebold-Mariano test.

Issue 27, the merge of left12-dm (the DM test by fixed smoothing declines a pair whose loss
differential is too persistent, with a warning) into ``modalinfo batch``: under
warnings-as-errors the task raised, so the batch-versus-one-process comparison of
tests/batch/test_batch_cluster.py failed. Reference, outside the batch code: the same
question asked by the other road, :func:`modalinfo.forecast.evaluate` on the same log
(whose warning names the declined pairs and whose ``pvalue`` is NaN there).
"""

from __future__ import annotations

import math
import warnings

import pytest

from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.forecast import evaluate
from modalinfo.forecast.presets import make_predictor
from modalinfo.io import save


def test_a_declined_pair_is_a_nan_pvalue_in_an_ok_row(tmp_path, helpers):
    # the batch suite's AR(1) log 2 (256 frames): ARMA's loss differential against
    # persistence at h = 1 is declined by the DM test (its AR(p) plug-in)
    log = helpers.make_log(2)
    save(log, tmp_path / "smooth.npz")
    with pytest.warns(UserWarning, match="no honest Diebold-Mariano test") as seen:
        ev = evaluate({"arma": make_predictor("arma")}, log, train=0.5, horizons=[1],
                      keep_series=1, chunk_frames=2048)
    assert any("arma at h = 1" in str(w.message) for w in seen)
    assert math.isnan(ev.pvalue[ev.index("arma"), 0])
    payload = {"path": str(tmp_path / "smooth.npz"), "fmt": None, "hints": {},
               "analysis": "forecast",
               "params": resolve_params("forecast", {"predictors": "arma", "horizon": 1})}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing a worker cannot show escapes the task
        row = run_log_task(payload)
    assert math.isnan(row["pvalue_h1.arma"])
    assert row["beats_baseline_h1.arma"] is False
