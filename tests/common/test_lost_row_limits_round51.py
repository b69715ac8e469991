"""Stop 57, fix51-c item 6 (review33's uncovered plant R33-D13): a lost row names the limits.

``common/tasks/runner.run_tasks`` writes a "lost" row when a task's worker dies; under a
memory limit its message gets ``lost_note()`` (the limits local workers inherit, so the
user raises them before a retry that would die alike: round 50 PART b, R09, R13).
review33's plant ``"error_message": error_line(exc)`` (the note dropped) escaped: the
note's own test (tests/common/test_memory_data_limit_round50.py) calls ``lost_note``
alone, and the only lost row of the suite (tests/batch/test_batch_cluster.py) runs
without a limit.

Reference: a real worker death (the task calls ``os._exit``, as a segfault in a reader,
on a one-worker local cluster with ``retries=0``) and the limits' text written out here:
``memory_limits_text`` stands in for a limit set (``ulimit -d`` would cap this test
process too), read where ``lost_note`` reads it. The row's message is Dask's line and
then the note naming that limit.
"""

from __future__ import annotations

import pytest

pytest.importorskip("distributed")

LIMIT = "the data-segment limit (ulimit -d, RLIMIT_DATA) is 300.00 MiB"


def _die(payload):
    import os as _os

    if payload["die"]:
        _os._exit(1)  # the worker process dies mid-task
    return {"double": 2 * payload["i"]}


def test_a_lost_row_names_the_inherited_limit(tmp_path, monkeypatch):
    from modalinfo.batch.engine import RowStore, TaskSpec, open_client, run_tasks
    from modalinfo.common import memory

    monkeypatch.setattr(memory, "memory_limits_text", lambda: LIMIT)
    specs = [TaskSpec("k0", {"i": 0, "die": True}, {"i": 0})]
    store = RowStore(tmp_path / "out")
    with open_client(n_workers=1, threads_per_worker=1, memory_limit="1GB", retries=0,
                     dashboard_address=None) as client:
        report = run_tasks(specs, _die, store, client, progress=False)
    assert report.n_lost == 1
    (row,) = store.rows()
    assert row["status"] == "lost" and row["error_type"] == "KilledWorker"
    message = row["error_message"]
    assert f"({LIMIT} in the command, which local workers inherit" in message, message
    assert message.endswith("raise it first)"), message
