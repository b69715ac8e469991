r"""A non-UTF-8 file name on **stdout** reads ``\xNN`` too (review13, planted bug R13-L5).

The default tier checked the error line (stderr) only; the batch test that reads stdout
is ``slow``. Reference, outside the code: GNU ``ls -b``'s escape of a byte, ``\xff``,
written here as a literal; the command line run as a subprocess with the interpreter's
own stdout (``LC_ALL=C.UTF-8``), whose bytes are read as they are.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
BAD = os.fsdecode(b"bad\xff.npz")


def test_info_report_on_stdout_shows_the_byte_as_ls_b(tmp_path):
    from modalinfo.io import save
    from modalinfo.telemetry.log import ModalLog

    save(ModalLog(np.random.default_rng(0).standard_normal((300, 4)), rate=100.0,
                  units="rad"), tmp_path / BAD)
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1",
           "LC_ALL": "C.UTF-8"}
    proc = subprocess.run([sys.executable, "-m", "modalinfo", "info", BAD], cwd=tmp_path,
                          env=env, capture_output=True, timeout=300, check=False)
    assert proc.returncode == 0, proc.stderr
    assert b"bad\\xff.npz" in proc.stdout and b"\xff" not in proc.stdout
    assert b"udcff" not in proc.stdout
