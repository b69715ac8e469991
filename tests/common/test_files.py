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


def test_a_symlink_to_nothing_is_named_as_such(tmp_path):
    # audit 10-env: a symlink loop given as a log, config or result was "no such file" /
    # "does not exist" although `ls` shows it. Reference: POSIX symlink(7), stat(2)
    # ELOOP / ENOENT on a link whose target cannot be reached.
    from closedloop.config import load_config
    from closedloop.result import SimulationResult
    from modalinfo.common.files import check_readable

    for name in ("a.npz", "c.toml", "r.h5"):
        (tmp_path / ("x" + name)).symlink_to(tmp_path / name)
        (tmp_path / name).symlink_to(tmp_path / ("x" + name))
    with pytest.raises(FileNotFoundError, match="symbolic link to nothing"):
        check_readable(tmp_path / "a.npz")
    with pytest.raises(FileNotFoundError, match="symbolic link to nothing"):
        load_config(tmp_path / "c.toml")
    with pytest.raises(FileNotFoundError, match="symbolic link to nothing"):
        SimulationResult.load(tmp_path / "r.h5")
    with pytest.raises(FileNotFoundError, match="no such file"):
        check_readable(tmp_path / "missing.npz")  # a plain missing file keeps its words
