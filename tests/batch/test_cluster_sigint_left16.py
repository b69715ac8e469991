"""Leftovers 16-dask (issue 27): a Ctrl-C while the local Dask cluster starts.

A SIGINT to the process group while ``LocalCluster`` spawned its workers left a
half-started cluster whose ``atexit`` close printed a traceback (``AssertionError:
Status.init``) after "interrupted", and killed the worker in its interpreter start-up
("Fatal Python error: init_import_site"). Now: one line, exit 130, no process left.

Reference from outside the code: a terminal's Ctrl-C as POSIX delivers it, ``os.killpg``
of the command's own session (``start_new_session``), sent at a controlled point - right
after the first worker process was spawned (``distributed.process.AsyncProcess.start``
returned: the worker is in its start-up, the command inside ``LocalCluster``); the exit
status by the shell's convention (128 + SIGINT = 130); the processes left in the
session read from ``/proc/<pid>/stat`` (field 6, the session id).
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parents[2]

DRIVER = '''
import os, signal, sys
from distributed.process import AsyncProcess

_start, _sent = AsyncProcess.start, []

async def start(self):
    out = await _start(self)
    if not _sent:  # the first worker process exists and is starting up
        _sent.append(1)
        os.killpg(0, signal.SIGINT)
    return out

AsyncProcess.start = start
if __name__ == "__main__":
    from modalinfo.cli import main
    sys.exit(main(sys.argv[1:]))
'''


def _session_processes(sid: int) -> list[int]:
    pids = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            fields = stat.rsplit(")", 1)[1].split()
            if int(fields[3]) == sid and fields[0] != "Z":
                pids.append(int(entry.name))
    return pids


@pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")
def test_ctrl_c_while_the_workers_start_is_one_line(tmp_path, helpers):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    (tmp_path / "drv.py").write_text(DRIVER)
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1"}
    proc = subprocess.Popen(
        [sys.executable, str(tmp_path / "drv.py"), "batch", str(tmp_path / "log000.npz"),
         "--out", str(tmp_path / "out"), "--workers", "1", "--quiet"],
        cwd=tmp_path, env=env, start_new_session=True,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        out, err = proc.communicate(timeout=240)
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, 9)
    assert (proc.returncode, err) == (130, "modalinfo: interrupted\n"), err
    deadline = time.monotonic() + 30  # the workers' exit is asynchronous to the command's
    while _session_processes(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert _session_processes(proc.pid) == []
    out_dir = tmp_path / "out"  # nothing lost: absent or a batch folder the next run resumes
    assert not out_dir.exists() or (out_dir / "rows").is_dir()
