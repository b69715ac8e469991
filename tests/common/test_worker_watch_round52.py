"""The watch for running workers reads the scheduler's workers, not the client's totals (fix52-c).

tests/batch/test_batch_cluster.py::test_batch_equals_single_process_bit_for_bit ended
under a load of ~20-30 with ``NoWorkersError`` ("no Dask worker ran a task for 61 s")
while both workers ran (sampled once a second: 653 of 657 samples "running", the other 4
an empty worker table). ``Client.scheduler_info()`` returns the client's cached identity,
which its periodic refresh writes as ``identity(n_workers=0)``: the totals, no workers.

Reference: the scheduler's own worker table (``cluster.scheduler.workers``), on a real
in-process ``LocalCluster``; the client's cache is put in the state its failed refresh
leaves (its own refresh replaced by a no-op, as when distributed catches the
``OSError``).
"""

from __future__ import annotations

import time

import pytest

distributed = pytest.importorskip("distributed")

from modalinfo.common.tasks.watch import (  # noqa: E402
    NoWorkersError,
    _running_workers,
    gather_watched,
)


@pytest.fixture
def stale_client(monkeypatch):
    from distributed.client import SchedulerInfo

    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        totals = client.sync(client.scheduler.identity, n_workers=0)
        assert totals["n_workers"] == 1 and totals["workers"] == {}

        async def failed_refresh(n_workers=0):  # distributed logs the OSError, keeps the cache
            return None

        client._scheduler_identity = SchedulerInfo(totals)
        monkeypatch.setattr(client, "_update_scheduler_info", failed_refresh)
        yield cluster, client


def test_running_workers_are_counted_from_the_scheduler(stale_client):
    cluster, client = stale_client
    assert client.scheduler_info()["workers"] == {}  # what the watch read before
    running = sum(1 for ws in cluster.scheduler.workers.values()
                  if ws.status.name == "running")
    assert running == 1
    assert _running_workers(client) == running


def test_a_task_longer_than_the_wait_is_not_refused(stale_client):
    # before: "no Dask worker ran a task for 1 s" while the one worker ran the task
    _, client = stale_client
    future = client.submit(lambda: time.sleep(2.5) or 7, pure=False)
    assert gather_watched(client, [future], worker_wait=1.0) == [7]


def test_no_worker_is_still_refused(monkeypatch):
    # the guard kept: a cluster of 0 workers (totals 0) ends the wait
    with distributed.LocalCluster(n_workers=0, processes=False,
                                  dashboard_address=":0") as cluster, \
            distributed.Client(cluster) as client:
        future = client.submit(lambda: 1, pure=False)
        with pytest.raises(NoWorkersError, match="no Dask worker ran a task for"):
            gather_watched(client, [future], worker_wait=1.0)
