"""Round 16 PART b (issue 27), B06: a local worker's heartbeat traceback after a batch.

Reference from outside the code: the standard library's ``logging`` (a filter on the
``distributed.worker`` logger decides which records a handler sees) and the message
distributed's ``Worker.heartbeat`` logs with ``logger.exception`` (distributed/worker.py).
"""

from __future__ import annotations

import logging

import pytest

from modalinfo.common.tasks import worker_signals


@pytest.fixture
def seen():
    logger = logging.getLogger("distributed.worker")
    records: list[logging.LogRecord] = []

    class Keep(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            records.append(record)

    handler = Keep()
    before = list(logger.filters)
    logger.addHandler(handler)
    yield logger, records
    logger.removeHandler(handler)
    logger.filters[:] = before


def test_the_heartbeat_failure_is_dropped_other_errors_kept(seen):
    logger, records = seen
    worker_signals.quiet_heartbeat_logs()
    worker_signals.quiet_heartbeat_logs()  # twice: one filter
    try:
        raise OSError("Stream is closed")
    except OSError:
        logger.exception("Failed to communicate with scheduler during heartbeat.")
    logger.error("Compute Failed")
    assert [r.getMessage() for r in records] == ["Compute Failed"]
    assert sum(f is worker_signals._not_heartbeat_failure for f in logger.filters) == 1
