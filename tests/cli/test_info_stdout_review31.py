"""``modalinfo info``: a stdout refusing ANY of its lines is one line, status 1 (review 31).

Round 31 mutation, plant I1: one of ``info``'s lines written by ``print`` rather than
``common.cli.write_stdout`` passed ``tests/cli/test_info_stdout_full_fix47e.py``, whose
stdout refuses the first write (the later lines are never reached). Here a stdout
refuses the k-th write, for every k up to the writes of a whole report. Reference: the
promise of ``write_stdout``'s docstring and fixes 47-e item 3 ("could not write standard
output" with status 1, the status of every other command's refused stdout), and the
kernel's ENOSPC (``os.strerror``).
"""

from __future__ import annotations

import errno
import io
import os
import sys

import numpy as np
import pytest

from modalinfo.cli import main as modalinfo_main


class _FullAt(io.StringIO):
    """A stdout that refuses its ``k``-th write (ENOSPC), and keeps the others."""

    def __init__(self, k: int) -> None:
        super().__init__()
        self.k, self.n = k, 0

    def write(self, text):
        self.n += 1
        if self.n == self.k:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return super().write(text)


@pytest.fixture(scope="module")
def log(tmp_path_factory):
    path = tmp_path_factory.mktemp("info") / "log.npy"
    np.save(path, np.random.default_rng(0).standard_normal((200, 3)))
    return path


def _info(log, out, monkeypatch) -> int:
    monkeypatch.setattr(sys, "stdout", out)
    return modalinfo_main(["info", str(log), "--rate", "1000", "--quiet"])


def test_every_line_refused_is_one_error_with_status_1(log, monkeypatch, capsys):
    whole = _FullAt(0)
    assert _info(log, whole, monkeypatch) == 0
    assert whole.getvalue().count("\n") >= 8 and "integrity" in whole.getvalue()
    capsys.readouterr()
    for k in range(1, whole.n + 1):
        code = _info(log, _FullAt(k), monkeypatch)
        err = capsys.readouterr().err
        assert code == 1, (k, err)
        assert err == ("modalinfo info: error: could not write standard output "
                       f"({os.strerror(errno.ENOSPC)})\n"), (k, err)
