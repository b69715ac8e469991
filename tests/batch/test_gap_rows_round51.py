"""A batch row on a log with gaps names what batch can do (round 51 PART b, C101 / C105).

``modalinfo batch`` has no ``--split-gaps``; the forecast row and the ordering row (its
stability windows, its block bootstrap) on a log with a gap said "(command line:
--split-gaps)", and batch refused that option. Reference: the remedy each row names is
checked by running it (``--set ordering.windows=0`` gives an ok row on the same log), and
the gap itself is the test's own (frames 200..219 removed from a 1 kHz log's timestamps).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.common.tasks.threads import _limited_call
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


@pytest.fixture
def gapped(tmp_path):
    rng = np.random.default_rng(51)
    n = 620
    x = np.zeros((n, 3))
    e = rng.normal(size=(n, 3))
    for t in range(1, n):  # AR(1), phi 0.8: a forecastable series
        x[t] = 0.8 * x[t - 1] + e[t]
    keep = np.r_[0:200, 220:n]
    log = ModalLog(x[keep], timestamps=keep / 1000.0, modes=[2, 3, 4], units="rad",
                   wavelength=5e-7)
    path = tmp_path / "gapped.npz"
    save(log, path)
    return str(path)


def _row(path, analysis, **params):
    payload = {"path": path, "fmt": None, "hints": {}, "analysis": analysis,
               "params": resolve_params(analysis, params)}
    return _limited_call(run_log_task, payload, 1)


def test_forecast_row_names_the_command_not_a_batch_option(gapped):
    row = _row(gapped, "forecast", predictors="linear-ls", horizon=1)
    assert row["status"] == "error"
    message = row["error_message"]
    assert "batch has no --split-gaps" in message
    assert "modalinfo forecast LOG --split-gaps" in message
    assert "frames 200..599" in message  # the longest contiguous segment, 400 frames


_ORDERING = {"estimator": "gaussian", "budget": 2000, "pupil_pixels": 16}


def test_ordering_row_names_the_parameter_that_avoids_the_windows(gapped):
    row = _row(gapped, "ordering", **_ORDERING)  # windows 4 by default
    assert row["status"] == "error"
    assert "--set ordering.windows=0" in row["error_message"]
    assert "modalinfo reorder LOG --split-gaps" in row["error_message"]
    # the remedy named works: the pooled ordering runs on the log with its gap
    ok = _row(gapped, "ordering", windows=0, **_ORDERING)
    assert ok["status"] == "ok", ok.get("error_message")
    assert sorted(ok["order"].split()) == ["Z2", "Z3", "Z4"]


def test_ordering_bootstrap_row_names_resamples(gapped):
    row = _row(gapped, "ordering", windows=0, resamples=5, **_ORDERING)
    assert row["status"] == "error"
    assert "--set ordering.resamples=0" in row["error_message"]
