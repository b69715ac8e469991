"""``modalinfo info LOG > /dev/full``: one line naming standard output, status 1.

Fixes 47-e item 3 (issue 27, the leftover of fixes 47-b): ``info`` wrote its lines
straight to ``sys.stdout``, so a stdout that refuses every byte (``/dev/full``, ENOSPC)
ended "modalinfo info: error: [Errno 28] No space left on device" with status 2, the
status of an input error, naming no stream. Reference: the kernel's ENOSPC of
``/dev/full`` (``errno.ENOSPC``, ``os.strerror``), and the status and words every other
command uses for a refused stdout (``convert``, ``batch``: round 38 PART b, W3).
"""

from __future__ import annotations

import errno
import os
import subprocess
import sys

import numpy as np
import pytest

from modalinfo.cli import main as modalinfo_main


class _Full:
    """A stdout that refuses every write as /dev/full does."""

    encoding = "utf-8"

    def write(self, text):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def flush(self):
        pass

    def isatty(self):
        return False


def test_info_on_a_full_stdout_names_standard_output_with_status_1(tmp_path, monkeypatch,
                                                                   capsys):
    log = tmp_path / "log.npy"
    np.save(log, np.random.default_rng(0).standard_normal((200, 3)))
    monkeypatch.setattr(sys, "stdout", _Full())
    assert modalinfo_main(["info", str(log), "--rate", "1000", "--quiet"]) == 1
    err = capsys.readouterr().err
    assert err == ("modalinfo info: error: could not write standard output "
                   f"({os.strerror(errno.ENOSPC)})\n"), err


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full")
def test_info_to_dev_full_in_a_process(tmp_path):
    log = tmp_path / "log.npy"
    np.save(log, np.random.default_rng(0).standard_normal((200, 3)))
    with open("/dev/full", "w") as full:
        done = subprocess.run([sys.executable, "-m", "modalinfo", "info", str(log),
                               "--rate", "1000", "--quiet"], stdout=full,
                              stderr=subprocess.PIPE, text=True, timeout=300,
                              env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert done.returncode == 1, done.stderr
    assert done.stderr.startswith("modalinfo info: error: could not write standard output")
    assert done.stderr.count("\n") == 1 and "Traceback" not in done.stderr
