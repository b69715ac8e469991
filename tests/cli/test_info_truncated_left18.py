"""Leftovers 18-sigint (issue 27), L07: a small log truncated while ``modalinfo info`` reads it.

A memory-mapped log that another process shortens while it is read kills the command
with SIGBUS (exit 135 in a shell, no message; Python cannot catch the fault). A log
below ``modalinfo.io.MAP_ABOVE`` (and 1/8 of the usable memory) is now read, not
mapped: shortened before its data are read it is refused in one line naming the
truncation (exit 2); shortened after they were read, the command completes on the bytes
it read.

Reference from outside the code: the file as the operating system shows it
(``os.truncate`` to half its size, at a fixed point: a wrapper of the reader's numpy
calls ``fromfile`` / ``memmap``, before or after the call - no race), the process's exit
status (``subprocess``: a negative status is the signal that ended it, SIGBUS), and the
frame count and per-mode means numpy computes from the array the test wrote.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]

posix = pytest.mark.skipif(os.name != "posix", reason="SIGBUS and os.truncate are POSIX")

#: ``modalinfo info`` with the NPY reader's ``fromfile`` / ``memmap`` wrapped: the log
#: is cut to half its size just before the call (CUT_WHEN=before) or just after it.
DRIVER = '''
import os, sys
import numpy as np
import modalinfo.io.npz as npz

def _cut():
    path = os.environ["CUT"]
    os.truncate(path, os.path.getsize(path) // 2)

class _Numpy:
    def __getattr__(self, name):
        value = getattr(np, name)
        if name not in ("fromfile", "memmap"):
            return value

        def wrapped(*args, **kwargs):
            if os.environ["CUT_WHEN"] == "before":
                _cut()
            out = value(*args, **kwargs)
            if os.environ["CUT_WHEN"] == "after":
                _cut()
            return out
        return wrapped

npz.np = _Numpy()
if __name__ == "__main__":
    from modalinfo.cli import main
    sys.exit(main(sys.argv[1:]))
'''

N_FRAMES, N_MODES = 4000, 10


def _info(tmp_path: Path, when: str) -> tuple[subprocess.CompletedProcess, np.ndarray]:
    x = np.random.default_rng(18).standard_normal((N_FRAMES, N_MODES))
    log = tmp_path / "log.npy"
    np.save(log, x)
    (tmp_path / "drv.py").write_text(DRIVER)
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1",
           "CUT": str(log), "CUT_WHEN": when}
    proc = subprocess.run([sys.executable, str(tmp_path / "drv.py"), "info", str(log),
                           "--rate", "1000"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=120)
    assert os.path.getsize(log) < x.nbytes  # the hook did cut the file
    return proc, x


@posix
def test_cut_before_the_read_is_a_one_line_truncated_refusal(tmp_path):
    proc, _ = _info(tmp_path, "before")
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert "truncated" in proc.stderr and "log.npy" in proc.stderr, proc.stderr


@posix
def test_cut_after_the_read_is_no_sigbus_the_bytes_read_are_summarised(tmp_path):
    proc, x = _info(tmp_path, "after")
    assert proc.returncode == 0, (proc.returncode, proc.stderr)  # was -7: SIGBUS
    assert f"{N_FRAMES} frames x {N_MODES} modes" in proc.stdout, proc.stdout
    rows = [ln.split() for ln in proc.stdout.splitlines() if ln.startswith("Z")]
    means = np.array([float(r[1]) for r in rows])
    np.testing.assert_allclose(means, x.mean(axis=0), rtol=1e-4, atol=1e-7)  # 5 digits


def test_the_mapping_threshold_is_the_documented_rule(tmp_path, monkeypatch):
    """Mapped when larger than min(MAP_ABOVE, usable memory / 8), else read; a missing
    path is not mapped (the reader names the problem)."""
    import modalinfo.io as mio

    log = tmp_path / "log.npy"
    np.save(log, np.zeros((100, 3)))
    size = os.path.getsize(log)
    monkeypatch.setattr(mio, "usable_memory_bytes", lambda: float("inf"))
    assert not mio.mapping_pays(log)  # the default threshold, 128 MiB
    monkeypatch.setattr(mio, "MAP_ABOVE", size)
    assert not mio.mapping_pays(log)
    monkeypatch.setattr(mio, "MAP_ABOVE", size - 1)
    assert mio.mapping_pays(log)
    monkeypatch.setattr(mio, "MAP_ABOVE", 2**40)
    monkeypatch.setattr(mio, "usable_memory_bytes", lambda: 8.0 * size)
    assert not mio.mapping_pays(log)
    monkeypatch.setattr(mio, "usable_memory_bytes", lambda: 8.0 * (size - 1))
    assert mio.mapping_pays(log)
    assert not mio.mapping_pays(tmp_path / "missing.npy")
