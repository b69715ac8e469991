"""Leftovers 17-sigint (issue 27): a Ctrl-C that lands inside a ``gc`` callback.

Python runs its SIGINT handler wherever the main thread is; inside a ``gc`` callback
(distributed registers one) the ``KeyboardInterrupt`` is printed as "Exception ignored
in ..." and dropped, and ``modalinfo batch`` ran on to exit 0 (Leftovers 16-dask, G1).
Now the handler installed while the Dask client lives records the signal and the
runner's poll raises it: one line, exit 130, the folder resumable.

Reference from outside the code: the signal as POSIX raises it, ``signal.raise_signal``
(``raise(3)``), called from inside a ``gc.callbacks`` entry during a forced
``gc.collect()`` (Python's gc documentation: callbacks run at the start and stop of a
collection); the exit status by the shell's convention (128 + SIGINT = 130); resume
checked by running the same command again (exit 0, a table with a row per task).
No timing: the signal is raised at a fixed point, when the runner starts waiting.
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parents[2]

DRIVER = '''
import gc, signal, sys
import distributed

armed = []

def callback(phase, info):
    if armed:  # once: the SIGINT handler runs here, inside the gc callback
        armed.clear()
        signal.raise_signal(signal.SIGINT)

gc.callbacks.append(callback)
_as_completed = distributed.as_completed

class as_completed(_as_completed):  # the runner starts waiting on its tasks
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        armed.append(1)
        gc.collect()

distributed.as_completed = as_completed
if __name__ == "__main__":
    from modalinfo.cli import main
    sys.exit(main(sys.argv[1:]))
'''


def test_ctrl_c_inside_a_gc_callback_is_honoured(tmp_path, helpers):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    (tmp_path / "drv.py").write_text(DRIVER)
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1"}
    args = ["batch", str(tmp_path / "log000.npz"), "--out", str(tmp_path / "out"),
            "--workers", "1", "--quiet"]
    proc = subprocess.run([sys.executable, str(tmp_path / "drv.py"), *args], cwd=tmp_path,
                          env=env, capture_output=True, text=True, timeout=240)
    assert "Exception ignored" not in proc.stderr, proc.stderr
    assert (proc.returncode, proc.stderr) == (130, "modalinfo: interrupted\n"), proc.stderr
    assert not (tmp_path / "out" / "batch.csv").exists()  # stopped before the table
    again = subprocess.run([sys.executable, "-m", "modalinfo", *args], cwd=tmp_path,
                           env=env, capture_output=True, text=True, timeout=240)
    assert again.returncode == 0, again.stderr
    with open(tmp_path / "out" / "batch.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and all(r["status"] == "ok" for r in rows)
