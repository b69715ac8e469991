"""Round 50 PART b of issue 27: a save ended by a CPU-time limit leaves no temporary file.

docs/ADVERSARIAL.md, "Round 50 PART b, issue 27", rows R20 and R21: ``ulimit -St 5``
(soft CPU-time limit: SIGXCPU) during ``modalinfo convert big.npz old.csv --overwrite``
left a 60 MB hidden ``.old.csv.<pid>-<random>.tmp`` (exit 152); ``ulimit -t 4`` (the hard
limit: SIGKILL, which no handler sees) left 16-100 MB ones, and no later write of
``old.csv`` removed them.

References: POSIX.1-2017 signal.h (SIGXCPU's default action ends the process; a shell
reports a process ended by signal n as 128 + n, 152 for SIGXCPU, 24 on Linux); the old
file's SHA-256 by ``hashlib``; a dead pid is that of a child this test started and
reaped (``subprocess``), a live one this test's own parent.
"""

from __future__ import annotations

import hashlib
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from modalinfo.common.files import atomic_write

pytestmark = pytest.mark.skipif(not hasattr(signal, "SIGXCPU"), reason="POSIX only")


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_sigxcpu_during_a_save_removes_the_temporary_and_keeps_the_old_file(tmp_path):
    target = tmp_path / "old.csv"
    target.write_bytes(b"old content\n" * 1000)
    before = _sha(target)
    # the child writes half a file, then receives SIGXCPU as a soft CPU limit sends it
    code = textwrap.dedent(f"""
        import os, signal
        from modalinfo.common.files import atomic_write
        def write(fh):
            fh.write(b"new" * 100000)
            fh.flush()
            os.kill(os.getpid(), signal.SIGXCPU)
            fh.write(b"more" * 100000)
        atomic_write({str(target)!r}, write, overwrite=True)
        """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, cwd=tmp_path)
    assert proc.returncode == 128 + signal.SIGXCPU, proc.stderr
    assert "Traceback" not in proc.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old.csv"]
    assert _sha(target) == before


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def test_a_killed_writers_temporary_is_removed_by_the_next_write(tmp_path, capsys):
    dead = _dead_pid()
    stale = tmp_path / f".old.csv.{dead}-ab_c12xy.tmp"  # as a SIGKILLed writer leaves it
    stale.write_bytes(b"half a file")
    live = tmp_path / f".old.csv.{os.getppid()}-zz9z9zz9.tmp"  # a writer still running
    live.write_bytes(b"in progress")
    mine = tmp_path / ".old.csv.notes.tmp"  # a user's file: no pid, not ours
    mine.write_bytes(b"notes")
    other = tmp_path / f".other.csv.{dead}-ab_c12xy.tmp"  # another target's: not this write's
    other.write_bytes(b"x")
    atomic_write(tmp_path / "old.csv", lambda fh: fh.write(b"new\n"), overwrite=False)
    assert (tmp_path / "old.csv").read_bytes() == b"new\n"
    assert not stale.exists()
    assert live.exists() and mine.exists() and other.exists()
    err = capsys.readouterr().err
    assert stale.name in err and mine.name not in err


def test_a_task_row_names_the_file_size_limit(tmp_path):
    # R41: `ulimit -f 30; closedloop sweep` wrote the run's row as "[Errno 27] File too
    # large" alone; the row (error_line, in the worker that inherits the limit) names it
    code = textwrap.dedent(f"""
        import resource
        resource.setrlimit(resource.RLIMIT_FSIZE, (30 * 1024, resource.RLIM_INFINITY))
        from modalinfo.common.files import error_line
        try:
            with open({str(tmp_path / "big.bin")!r}, "wb") as fh:
                fh.write(b"x" * (64 * 1024))
                fh.flush()
        except OSError as exc:
            print(error_line(exc))
        """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    line = proc.stdout.strip()
    assert line.startswith("[Errno 27]"), line
    assert "ulimit -f, RLIMIT_FSIZE) is 30.00 KiB" in line.replace("kiB", "KiB")


def test_a_failed_cache_write_leaves_the_kernel_running(tmp_path):
    # R48: `ulimit -f 1; NUMBA_CACHE_DIR=<new> closedloop run --preset kaos` ended with
    # "[Errno 27] File too large ... write a smaller output": numba's cache write, not an
    # output. Reference: the sums 0 + 1 + ... + 99 = 4950 and 0 + ... + 9 = 45.
    (tmp_path / "kern_round50.py").write_text(textwrap.dedent("""
        from modalinfo.common.jit import jit

        @jit
        def total(n):
            s = 0
            for i in range(n):
                s += i
            return s
        """), encoding="utf-8")
    code = textwrap.dedent("""
        import resource, warnings
        warnings.simplefilter("always")
        resource.setrlimit(resource.RLIMIT_FSIZE, (0, resource.RLIM_INFINITY))
        import kern_round50
        print(kern_round50.total(100), kern_round50.total(10))
        """)
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache"),
           "PYTHONPATH": os.pathsep.join([str(tmp_path), *sys.path])}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=300, cwd=tmp_path, env=env)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["4950", "45"]
    assert proc.stderr.count("could not write its cache") == 1, proc.stderr


def test_a_library_not_mapped_for_lack_of_memory_is_one_line(capsys):
    # `ulimit -v 400000; modalinfo synth ...`: SciPy's extension module raised
    # "ImportError: .../_lbfgsb...so: failed to map segment from shared object" (the
    # dynamic loader's words for mmap's ENOMEM), a 40-line traceback
    from modalinfo.common.startup import import_refusal

    exc = ImportError("/x/scipy/optimize/_lbfgsb.cpython-311-x86_64-linux-gnu.so: failed "
                      "to map segment from shared object")
    assert import_refusal("modalinfo", exc) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("modalinfo: error: out of memory")
    with pytest.raises(ImportError, match="No module named"):  # a broken installation
        import_refusal("modalinfo", ImportError("No module named 'scipy'"))


def test_a_lock_that_cannot_be_written_leaves_nothing(tmp_path):
    # R90: `ulimit -f 0; python -m paper_figures --out r90` said "'r90' is as it was"
    # and left r90/ holding an empty `.lock.<pid>.<ns>.tmp`. Reference: the listing.
    out = tmp_path / "out"
    out.mkdir()
    code = textwrap.dedent(f"""
        import resource
        resource.setrlimit(resource.RLIMIT_FSIZE, (0, resource.RLIM_INFINITY))
        from modalinfo.common.folders import OutputLock
        try:
            OutputLock({str(out)!r}).acquire()
        except OSError as exc:
            print(exc.errno)
        """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "27"  # EFBIG
    assert list(out.iterdir()) == []
