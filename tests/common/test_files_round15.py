"""Adversarial round 15, PART b: outputs that are streams, foreign files, shutdown, old rows.

References, outside the code under test: the kernel's view of paths (``os.readlink``
of ``/proc/self/fd/1`` is the process's standard output, so a link to it is a stream,
not a file path; ``os.stat`` of the file after a refused save, its bytes unchanged);
POSIX ``rename(2)`` refusing with EPERM (here raised by a stand-in ``os.replace``);
Python's own report of an exception in an ``atexit`` callback ("Exception ignored",
a traceback on stderr); SHA-256 (``hashlib``) of the canonical JSON for the task key.
Rows S04, S12, F03, the interruption fuzz and O01-O05 of docs/ADVERSARIAL.md
"Round 15 PART b". Each test fails on the code before its fix (d06a533).
"""

from __future__ import annotations

import errno
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

import modalinfo  # the tree under test, wherever it is imported from
from modalinfo.common import files
from modalinfo.common.files import atomic_write, check_not_special
from modalinfo.common.tasks import keys

ROOT = Path(modalinfo.__file__).resolve().parents[1]


def test_dash_is_refused_not_written_as_a_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(OSError, match="'-' is not standard output"):
        atomic_write(Path("-"), lambda fh: fh.write(b"x"), overwrite=False)
    assert not (tmp_path / "-").exists()


@pytest.mark.skipif(not os.path.exists("/proc/self/fd/1"), reason="needs /proc")
def test_link_to_a_stream_is_refused_and_kept(tmp_path):
    # /dev/stdout -> /proc/self/fd/1: with stdout sent to a file it resolves to a regular
    # file, and the save's rename replaced the link (as root: the system's /dev/stdout)
    link = tmp_path / "stdout-link"
    link.symlink_to("/proc/self/fd/1")
    with pytest.raises(OSError, match="link to an open stream"):
        atomic_write(link, lambda fh: fh.write(b"x"), overwrite=True)
    assert os.readlink(link) == "/proc/self/fd/1"
    with pytest.raises(OSError, match="link to an open stream"):
        check_not_special(Path("/proc/self/fd/1"))
    # a plain link to a file is not a stream: replaced as before (the target untouched)
    target = tmp_path / "target.csv"
    target.write_bytes(b"old")
    plain = tmp_path / "plain.csv"
    plain.symlink_to(target)
    atomic_write(plain, lambda fh: fh.write(b"new"), overwrite=True)
    assert plain.read_bytes() == b"new" and target.read_bytes() == b"old"


def test_a_refused_replace_names_the_file_not_the_temporary(tmp_path, monkeypatch):
    out = tmp_path / "r.csv"
    out.write_bytes(b"theirs")

    def refuse(src, dst):
        raise PermissionError(errno.EPERM, "Operation not permitted", str(src), str(dst))

    monkeypatch.setattr(files.os, "replace", refuse)
    with pytest.raises(PermissionError) as info:
        atomic_write(out, lambda fh: fh.write(b"mine"), overwrite=True)
    message = str(info.value)
    assert "cannot replace" in message and str(out) in message and ".tmp" not in message
    assert "[Errno" not in message and info.value.errno == errno.EPERM
    assert out.read_bytes() == b"theirs"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv"]  # no temporary left


def test_ctrl_c_during_shutdown_is_no_traceback(tmp_path):
    # a SIGINT after the command's work, while the interpreter shuts down (an atexit
    # callback here, as Dask's, numba's and tqdm's are): Python printed "Exception
    # ignored in atexit callback ... KeyboardInterrupt" with a traceback
    script = (
        "import atexit, os, signal, sys, time, runpy\n"
        "atexit.register(lambda: (os.kill(os.getpid(), signal.SIGINT), time.sleep(2)))\n"
        "sys.argv = ['closedloop', 'config', '--preset', 'kaos', '--fmt', 'json']\n"
        "runpy.run_module('closedloop', run_name='__main__', alter_sys=True)\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          env=env, cwd=tmp_path, timeout=120)
    assert "Traceback" not in done.stderr and "KeyboardInterrupt" not in done.stderr
    assert done.returncode == 0 and '"name": "kaos"' in done.stdout  # flushed, all of it


def test_task_keys_change_with_the_code(monkeypatch):
    version = keys.package_version()
    assert version.startswith(modalinfo.__version__ + "+src.")
    assert len(version.split("+src.")[1]) == 12
    key = keys.task_key("abc", "summary")
    monkeypatch.setattr(keys, "source_fingerprint", lambda: "f" * 64)  # another checkout
    other = keys.task_key("abc", "summary")
    assert other != key
    import hashlib

    text = '["' + modalinfo.__version__ + '+src.ffffffffffff","abc","summary"]'
    assert other == hashlib.sha256(text.encode()).hexdigest()


def test_source_fingerprint_covers_every_source_file(tmp_path, monkeypatch):
    # a copy of the two packages with one statement added to one module: another
    # fingerprint (a comment alone no longer changes it: test_fingerprint_left15.py)
    import shutil

    for name in ("modalinfo", "closedloop"):
        shutil.copytree(ROOT / name, tmp_path / name,
                        ignore=shutil.ignore_patterns("__pycache__"))
    code = ("import sys; sys.path.insert(0, sys.argv[1]);"
            "from modalinfo.common.tasks.keys import source_fingerprint as f; print(f())")
    first = subprocess.run([sys.executable, "-c", code, str(tmp_path)], capture_output=True,
                           text=True, check=True).stdout
    sweep = tmp_path / "closedloop" / "sweep.py"
    sweep.write_text(sweep.read_text() + "\nANOTHER_BUILD = 1\n")
    second = subprocess.run([sys.executable, "-c", code, str(tmp_path)],
                            capture_output=True, text=True, check=True).stdout
    assert first.strip() and second.strip() and first != second


def test_a_lock_whose_pid_was_reused_is_stale(tmp_path):
    # the lock names pid 1 on this host, written long before pid 1 started (a reused
    # pid): refused before as "in use by modalinfo batch (pid 1 on <host>)"
    import json
    import socket

    from modalinfo.common.folders import OutputLock

    if not os.path.exists("/proc/1/stat"):
        pytest.skip("needs Linux /proc")
    (tmp_path / ".lock").write_text(json.dumps({
        "pid": 1, "host": socket.gethostname(), "started": 1_000_000_000.0,  # 2001
        "command": "modalinfo batch"}))
    with OutputLock(tmp_path) as lock:
        assert lock.held
        assert json.loads((tmp_path / ".lock").read_text())["pid"] == os.getpid()
    # a live holder that started before its lock was written is still in use
    (tmp_path / ".lock").write_text(json.dumps({
        "pid": os.getppid(), "host": socket.gethostname(), "started": time.time(),
        "command": "modalinfo batch"}))
    from modalinfo.common.folders import OutputInUseError

    with pytest.raises(OutputInUseError, match="in use"):
        OutputLock(tmp_path).acquire()
