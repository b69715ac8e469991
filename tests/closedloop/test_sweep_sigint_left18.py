"""Leftovers 18-sigint (issue 27): a Ctrl-C inside a ``gc`` callback ends a sweep.

``closedloop sweep`` shares ``modalinfo batch``'s Dask client and its Ctrl-C handler
(Leftovers 17-sigint), which records the signal and lets the runner's poll raise it; a
Ctrl-C that lands inside a ``gc`` callback (distributed registers one) was dropped
("Exception ignored in ...") before it. The sweep case was checked by hand only.

Reference from outside the code: the signal as POSIX raises it, ``signal.raise_signal``
(``raise(3)``), called from inside a ``gc.callbacks`` entry during a forced
``gc.collect()`` when the runner starts waiting; the exit status by the shell's
convention (128 + SIGINT = 130); resume checked by running the same command again (exit
0, one ok row, read with :mod:`csv`). No timing: the signal is raised at a fixed point.
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from closedloop.config import save_config  # noqa: E402

from .conftest import small  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]

posix = pytest.mark.skipif(os.name != "posix", reason="POSIX signals")

#: ``closedloop sweep`` with a SIGINT raised inside a gc callback when the runner
#: starts waiting on its tasks (as ``tests/batch/test_sigint_gc_left17.py`` for batch).
GC_DRIVER = '''
import gc, signal, sys
import distributed

armed = []

def callback(phase, info):
    if armed:  # once: the SIGINT handler runs here, inside the gc callback
        armed.clear()
        signal.raise_signal(signal.SIGINT)

gc.callbacks.append(callback)
_as_completed = distributed.as_completed

class as_completed(_as_completed):
    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        armed.append(1)
        gc.collect()

distributed.as_completed = as_completed
if __name__ == "__main__":
    from closedloop.cli import main
    sys.exit(main(sys.argv[1:]))
'''


def _env() -> dict:
    return {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1"}


def _table_rows(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@posix
def test_ctrl_c_inside_a_gc_callback_ends_a_sweep(tmp_path):
    save_config(small(), tmp_path / "small.toml")
    (tmp_path / "grid.toml").write_text('config = "small.toml"\nduration = 0.05\n'
                                        'seeds = [0]\npredictors = ["none"]\n'
                                        '[[overrides]]\nname = "base"\n')
    (tmp_path / "drv.py").write_text(GC_DRIVER)
    args = ["sweep", str(tmp_path / "grid.toml"), "--out", str(tmp_path / "out"),
            "--workers", "1", "--quiet"]
    proc = subprocess.run([sys.executable, str(tmp_path / "drv.py"), *args], cwd=tmp_path,
                          env=_env(), capture_output=True, text=True, timeout=240)
    assert "Exception ignored" not in proc.stderr, proc.stderr
    assert (proc.returncode, proc.stderr) == (130, "closedloop: interrupted\n"), proc.stderr
    assert not (tmp_path / "out" / "sweep.csv").exists()
    again = subprocess.run([sys.executable, "-m", "closedloop", *args], cwd=tmp_path,
                           env=_env(), capture_output=True, text=True, timeout=240)
    assert again.returncode == 0, again.stderr
    rows = _table_rows(tmp_path / "out" / "sweep.csv")
    assert len(rows) == 1 and rows[0]["status"] == "ok"
