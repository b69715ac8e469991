"""Tests of modalinfo.batch.analyses: a FIFO among the inputs is named, never read.

Reference: POSIX file types (``os.mkfifo``); opening a FIFO for reading blocks until a
writer comes, so ``modalinfo batch fifo.npz`` hung in its hashing step (adversarial
round 5, row b06), and the analysis step said "no such file" of a file that exists.
The frame-rate rule: the range ``--rate`` documents, 1 mHz - 1 MHz (adversarial round 6,
row b01: ``modalinfo reorder`` refused a log whose stored rate is 1e300 Hz, ``batch``
ordered it without a word); a log written by the test with that rate.
"""

import os

import numpy as np
import pytest

from modalinfo.batch.analyses import resolve_params, run_log_task, sha256_file
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


@pytest.fixture
def fifo(tmp_path):
    path = tmp_path / "log.npz"
    os.mkfifo(path)
    return path


def test_hashing_a_fifo_is_refused_at_once(fifo):
    with pytest.raises(OSError, match=r"log\.npz' is a FIFO, not a regular file"):
        sha256_file(str(fifo))


def test_the_analysis_step_names_a_fifo_as_such(fifo):
    with pytest.raises(OSError, match="is a FIFO"):
        run_log_task({"path": str(fifo), "analysis": "summary", "params": {}})


def test_a_missing_file_is_still_no_such_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        run_log_task({"path": str(tmp_path / "gone.npz"), "analysis": "summary",
                      "params": {}})


@pytest.mark.parametrize("rate, refused", [(1e300, True), (2e9, True), (1e6, False)])
def test_analyses_refuse_a_rate_outside_the_range_the_summary_reports_it(tmp_path, rate,
                                                                         refused):
    coeffs = np.random.default_rng(0).standard_normal((64, 3))
    # a file written before ModalLog refused (1e300, 2e9) or warned on (1e6) such rates
    # (Leftovers 23-plaus): the log's stored rate set past the constructor
    log = ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4], units="rad")._derive(_rate=rate)
    path = save(log, tmp_path / "fast.npz")
    row = run_log_task({"path": str(path), "analysis": "summary",
                        "params": resolve_params("summary")})
    assert row["rate"] == rate
    task = {"path": str(path), "analysis": "forecast",
            "params": resolve_params("forecast", {"predictors": "linear", "horizon": 1})}
    if refused:
        with pytest.raises(ValueError, match=r"'fast\.npz': its stored rate gives a frame "
                                             r"rate of .* outside 0\.001-1e\+06 Hz"):
            run_log_task(task)
    else:
        assert run_log_task(task)["rate"] == rate


def test_log_columns_state_a_rate_change_and_the_span():
    # Reference: the time axis by construction: 1500 frames at 2 kHz then 1500 at
    # 1980 Hz (no gap: the row said 'uniform'); two nights 8 h apart span 28800.75 s
    from modalinfo.batch.analyses import log_columns

    t = np.r_[np.arange(1500) / 2000.0, 0.7495 + np.arange(1, 1501) / 1980.0]
    row = log_columns(ModalLog(np.zeros((3000, 1)), timestamps=t))
    assert "changes by 1% along the log (1980 to 2000 Hz" in row["sampling"]
    nights = np.r_[np.arange(1500), np.arange(1500)] / 2000.0
    nights[1500:] += 8 * 3600.0
    row = log_columns(ModalLog(np.zeros((3000, 1)), timestamps=nights))
    assert row["duration"] == pytest.approx(28800.75, abs=1e-6)
