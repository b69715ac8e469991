"""``available_cpus`` falls back to ``os.cpu_count()`` when the affinity call fails (review30 H2).

Its docstring and ``except (AttributeError, OSError)`` promise the fallback both where
``os.sched_getaffinity`` is missing (macOS, Windows: tested in
test_cpu_affinity_round47.py) and where it raises (a sandbox's seccomp filter answers
EPERM, an old kernel ENOSYS); a planted ``except AttributeError:`` passed every test.
Reference: ``os.cpu_count()`` (set to 3 here), as the docstring says.
"""

import errno
import os

from modalinfo.common.tasks import threads


def test_an_affinity_call_that_fails_falls_back_to_cpu_count(monkeypatch):
    def refused(pid):
        raise OSError(errno.EPERM, "Operation not permitted")

    monkeypatch.setattr(os, "cpu_count", lambda: 3)
    monkeypatch.setattr(os, "sched_getaffinity", refused, raising=False)
    assert threads.available_cpus() == 3
    assert threads.task_threads(1, 1) == 3
