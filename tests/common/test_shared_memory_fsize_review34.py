"""The cluster's file-size refusal names the shell's way out (review34, mutation round 34).

``common.cli._check_shared_memory`` (stop 57, fix51-c; round 50 PART b, R91): where the
semaphore's file cannot be written (``EFBIG``) the line names the limit and how to raise
it. Reference: POSIX ``ulimit -f`` is the shell's command for ``RLIMIT_FSIZE`` (bash's
``help ulimit``: "-f the maximum size of files written by the shell and its children"),
and ``errno.EFBIG`` is the kernel's "File too large". The lock is made to fail here as
``sem_open`` fails under ``ulimit -f 0`` (``test_shared_memory_fsize_round51.py`` runs
the real limit).
"""

from __future__ import annotations

import errno
import multiprocessing

import pytest

from modalinfo.common import cli


def test_efbig_names_the_limit_and_ulimit_f(monkeypatch):
    class _Context:
        @staticmethod
        def Lock():  # noqa: N802 - multiprocessing's name
            raise OSError(errno.EFBIG, "File too large")

    monkeypatch.setattr(multiprocessing, "get_context", lambda method: _Context)
    with pytest.raises(cli.CommandError) as info:
        cli._check_shared_memory()  # noqa: SLF001 - the check itself
    line = str(info.value)
    assert "(File too large)" in line
    assert "raise it (ulimit -f)" in line
    assert "/dev/shm/sem." in line and "mount a writable /dev/shm" not in line
