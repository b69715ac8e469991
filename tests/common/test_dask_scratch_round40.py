"""A Dask ``temporary-directory`` that cannot take files is refused before the cluster starts.

Round 40 PART b E53: ``DASK_TEMPORARY_DIRECTORY=<read-only mount> modalinfo batch ...``
ended in "the local Dask cluster could not start its workers (Cluster failed to start:
[Errno 30] Read-only file system: '.../dask-scratch-space': a worker process ended during
start-up, e.g. killed); run the command again (a batch or sweep resumes), with fewer
--workers if memory is short" - advice that cannot help. Reference: Dask's documented
``temporary-directory`` key (``DASK_TEMPORARY_DIRECTORY``; each worker's
``dask-scratch-space`` goes there) and the file system itself: ``/proc`` takes no new
files, also as root. The refusal names the folder and the variable, as a ValueError (the
command line's one line, exit 2), and no worker process is started.
"""

from __future__ import annotations

import sys

import pytest

pytest.importorskip("distributed")
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc is Linux's")


def test_an_unwritable_dask_temporary_directory_is_named_before_the_cluster(monkeypatch):
    import dask
    import distributed

    from modalinfo.common.tasks.cluster import open_client

    def no_cluster(*args, **kwargs):
        raise AssertionError("a LocalCluster was started before the refusal")

    monkeypatch.setattr(distributed, "LocalCluster", no_cluster)
    with dask.config.set({"temporary-directory": "/proc/dask-scratch-40"}), \
            pytest.raises(ValueError) as caught:
        with open_client(n_workers=1, dashboard_address=None):
            pass
    message = str(caught.value)
    assert "\n" not in message
    assert "temporary-directory '/proc/dask-scratch-40'" in message, message
    assert "DASK_TEMPORARY_DIRECTORY" in message and "('/proc':" in message, message
