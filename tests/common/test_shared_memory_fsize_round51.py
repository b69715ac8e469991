"""Stop 57, fix51-c item 3 (round 50 PART b, R91): a cluster refused under ``ulimit -f``.

Reference: the kernel. Under ``RLIMIT_FSIZE = 0`` (``ulimit -f 0``, set in the child by
``resource.setrlimit`` before exec) glibc's ``sem_open`` cannot write the semaphore's
file in ``/dev/shm`` (``EFBIG``), so a local Dask cluster cannot start; /dev/shm itself
is fine. ``modalinfo batch DIR --out OUT`` said "... /dev/shm ... is not usable here
(File too large); mount a writable /dev/shm": the line must name the file-size limit
(RLIMIT_FSIZE) and the file it could not write, in one line, exit 2, before any work.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

resource = pytest.importorskip("resource")
pytest.importorskip("distributed")


def test_batch_under_file_size_limit_zero_names_the_limit(tmp_path):
    (tmp_path / "logs").mkdir()
    np.save(tmp_path / "logs" / "a.npy", np.random.default_rng(91).standard_normal((200, 3)))

    def cap():  # in the child: stdout / stderr are pipes, which the limit does not cover
        resource.setrlimit(resource.RLIMIT_FSIZE, (0, resource.RLIM_INFINITY))

    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
           "NUMBA_NUM_THREADS": "1"}
    proc = subprocess.run([sys.executable, "-m", "modalinfo", "batch", "logs", "--out", "out"],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300,
                          preexec_fn=cap)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr, proc.stderr
    line = proc.stderr
    assert "RLIMIT_FSIZE" in line and "0 B" in line, line
    assert "/dev/shm/sem." in line, line  # the file it could not write
    assert "mount a writable /dev/shm" not in line, line  # /dev/shm is fine
    assert not (tmp_path / "out").exists()


def test_the_line_without_a_file_size_limit_still_names_dev_shm(monkeypatch):
    # another cause (/dev/shm read-only or missing) keeps round 15's advice
    import errno
    import multiprocessing

    from modalinfo.common import cli

    class _Context:
        @staticmethod
        def Lock():  # noqa: N802 - multiprocessing's name
            raise OSError(errno.EROFS, "Read-only file system")

    monkeypatch.setattr(multiprocessing, "get_context", lambda method: _Context)
    with pytest.raises(cli.CommandError, match="mount a writable /dev/shm"):
        cli._check_shared_memory()  # noqa: SLF001 - the check itself
