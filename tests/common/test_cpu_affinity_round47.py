"""The local cluster's default workers and a task's threads count the CPUs the job may use.

Round 47 PART b T01: under ``taskset -c 0`` on a 2-CPU machine (a Slurm job or cgroup
cpuset allotted fewer CPUs than the node has) ``batch`` / ``sweep`` started
``os.cpu_count()`` = 2 workers on 1 CPU; on a 128-core node allotted 4 CPUs, 128 workers
with a memory limit of RAM / 128 each. Reference: the process's affinity mask as the
operating system reports it (``os.sched_getaffinity(0)``, Python's documented way to the
CPUs "the calling thread is restricted to"), here replaced by a 1-CPU mask on an
8-CPU machine; no cluster is started (LocalCluster is replaced by a recorder).
"""

import os

import pytest

from modalinfo.common.tasks import cluster, threads


@pytest.fixture
def one_of_eight(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 8)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0}, raising=False)


def test_task_threads_counts_the_affinity_mask(one_of_eight):
    assert threads.task_threads(1, 1) == 1  # was 8: 8 threads on the job's 1 CPU


class _StartedError(Exception):
    pass


def test_default_workers_are_the_allotted_cpus(one_of_eight, monkeypatch):
    import distributed

    seen = {}

    def recorder(**kwargs):
        seen.update(kwargs)
        raise _StartedError

    monkeypatch.setattr(distributed, "LocalCluster", recorder)
    with pytest.raises(_StartedError), cluster.open_client():
        pass
    assert seen["n_workers"] == 1  # was 8
    assert seen["env"]["OMP_NUM_THREADS"] == "1"


def test_no_affinity_falls_back_to_cpu_count(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 3)
    monkeypatch.delattr(os, "sched_getaffinity", raising=False)
    assert threads.available_cpus() == 3
