"""Adversarial round 15, PART b: a local Dask cluster without usable shared memory.

Reference, outside the code under test: POSIX ``sem_open`` fails with EROFS when
``/dev/shm`` is a read-only mount (measured: ``multiprocessing`` raises
``OSError: [Errno 30] Read-only file system`` under ``unshare -m`` with a read-only
tmpfs there, and Dask's nanny then fails to start with two tracebacks); the command
must refuse in one line before the cluster. Row R12 of docs/ADVERSARIAL.md "Round 15
PART b"; fails on d06a533.
"""

from __future__ import annotations

import argparse
import errno
import multiprocessing

import pytest

pytest.importorskip("distributed")

from modalinfo.common.cli import CommandError, check_cluster_args  # noqa: E402


def _args(**changes):
    base = dict(command="batch", workers=1, threads_per_worker=None, worker_wait=None,
                scheduler=None, memory_limit=None)
    return argparse.Namespace(**{**base, **changes})


def test_no_shared_memory_is_one_line_before_the_cluster(monkeypatch):
    context = multiprocessing.get_context("spawn")

    def read_only(*args, **kwargs):
        raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(type(context), "Lock", read_only)
    with pytest.raises(CommandError, match=r"/dev/shm.*Read-only file system.*--scheduler"):
        check_cluster_args(_args())
    check_cluster_args(_args(scheduler="tcp://127.0.0.1:1"))  # a remote cluster: no check


def test_a_trailing_double_dash_ends_the_options(tmp_path, capsys):
    # POSIX utility syntax guideline 10: '--' ends the options; nothing after it is
    # legal. argparse refused it as "unrecognized arguments: --" (row S02)
    from closedloop.cli import main

    assert main(["config", "--preset", "kaos", "--fmt", "json", "--"]) == 0
    assert '"name": "kaos"' in capsys.readouterr().out
