"""Tests of modalinfo.common.files: the input checks before any read.

Reference: POSIX file types (``os.mkfifo``, the character device ``/dev/zero``): a log
is read only from a regular file; reading a FIFO blocks until a writer comes and
``/dev/zero`` never ends (adversarial round 5, rows i02 and i03).
"""

import os
from pathlib import Path

import pytest

from modalinfo.common.files import check_readable
from modalinfo.io import load


def test_a_fifo_is_refused_before_it_is_opened(tmp_path):
    fifo = tmp_path / "log.npz"
    os.mkfifo(fifo)
    # no writer ever comes: an open() would block this test forever
    with pytest.raises(OSError, match=r"log\.npz' is a FIFO, not a regular file"):
        load(fifo)


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="no /dev/zero")
def test_an_endless_device_is_refused_before_it_is_read():
    with pytest.raises(OSError, match="'/dev/zero' is a character device"):
        load("/dev/zero", fmt="csv")


def test_a_regular_file_passes(tmp_path):
    path = tmp_path / "log.csv"
    path.write_text("Z2\n1.0\n")
    check_readable(path)  # no exception
    with pytest.raises(FileNotFoundError, match="no such file"):
        check_readable(tmp_path / "missing.csv")
