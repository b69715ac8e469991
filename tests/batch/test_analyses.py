"""Tests of modalinfo.batch.analyses: a FIFO among the inputs is named, never read.

Reference: POSIX file types (``os.mkfifo``); opening a FIFO for reading blocks until a
writer comes, so ``modalinfo batch fifo.npz`` hung in its hashing step (adversarial
round 5, row b06), and the analysis step said "no such file" of a file that exists.
"""

import os

import pytest

from modalinfo.batch.analyses import run_log_task, sha256_file


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
