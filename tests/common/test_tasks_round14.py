"""Adversarial round 14, PART b: a Ctrl-C reaches the local Dask workers too.

Reference, outside the code under test: the operating system's signal dispositions as
Python's :func:`signal.getsignal` reports them inside a worker process of a real
``distributed.LocalCluster`` (``Client.run``), and a terminal's Ctrl-C, which POSIX
delivers to every process of the foreground group (``os.killpg``). Row S08b of
docs/ADVERSARIAL.md "Round 14 PART b". Fails on the code before the fix.
"""

from __future__ import annotations

import signal

import pytest

pytest.importorskip("distributed")

from modalinfo.common.tasks.cluster import open_client  # noqa: E402


def test_local_workers_leave_ctrl_c_to_the_command():
    # before: Python's default handler in each worker, so a Ctrl-C of the process group
    # printed "Process Dask Worker process (from Nanny): Traceback ... KeyboardInterrupt"
    with open_client(n_workers=1, threads_per_worker=1, memory_limit="1GB") as client:
        seen = client.run(lambda: str(signal.getsignal(signal.SIGINT)))  # by value
    assert list(seen.values()) == [str(signal.SIG_IGN)]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # the command's own
