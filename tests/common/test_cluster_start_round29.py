"""A local Dask worker that dies while the cluster starts (adversarial round 29 PART b).

Reference: the project's rule for a failure the user can act on (one line, no
traceback: an ``OSError`` is the command line's one-line refusal) and Dask's own
failure, reproduced exactly: ``LocalCluster`` raises ``RuntimeError("Nanny failed to
start.")`` caused by ``RuntimeError("Nanny failed to start worker process")`` when a
worker process is killed during start-up. ``modalinfo batch`` with a worker SIGKILLed
25 s in (a loaded machine, still starting) printed 71 lines of traceback and exited 1
(row L01).
"""

from __future__ import annotations

import pytest

distributed = pytest.importorskip("distributed")


def _nanny_failure(*args, **kwargs):
    try:
        raise RuntimeError("Nanny failed to start worker process")
    except RuntimeError as exc:
        raise RuntimeError("Nanny failed to start.") from exc


def test_a_worker_dying_at_start_up_is_one_line_naming_the_cluster(monkeypatch):
    from modalinfo.common.tasks.cluster import open_client

    monkeypatch.setattr(distributed, "LocalCluster", _nanny_failure)
    with pytest.raises(ChildProcessError) as info, \
            open_client(n_workers=1, dashboard_address=None):
        pass
    message = str(info.value)
    assert isinstance(info.value, OSError)  # the command line's one-line refusal
    assert "\n" not in message
    assert "could not start its workers (Nanny failed to start" in message
    assert "run the command again" in message


def test_another_start_up_error_is_not_renamed(monkeypatch):
    from modalinfo.common.tasks.cluster import open_client

    def broken(*args, **kwargs):
        raise RuntimeError("something else")

    monkeypatch.setattr(distributed, "LocalCluster", broken)
    with pytest.raises(RuntimeError, match="something else"), \
            open_client(n_workers=1, dashboard_address=None):
        pass
