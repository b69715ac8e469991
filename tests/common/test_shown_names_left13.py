r"""A file name with bytes that are not UTF-8 is shown one way everywhere: ``\xNN``.

Issue 27, left13-cli item 4: the batch table wrote ``bad\xff.npz`` (round 13 PART b) while
its duplicate-file note printed ``bad\udcff.npz`` (stderr's ``backslashreplace`` of the
PEP 383 surrogate) and its stdout report the raw byte. Reference, outside the code: GNU
``ls -b``'s escape of a byte, ``\xff`` (Python's ``bytes.decode("utf-8",
"backslashreplace")`` gives the same), written here as literals; the command lines are run
as subprocesses, with the interpreter's own stdout and stderr.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from modalinfo.common.files import shown_name

ROOT = Path(__file__).resolve().parents[2]
BAD = os.fsdecode(b"bad\xff.npz")


def test_shown_name_escapes_only_bad_bytes():
    assert shown_name(BAD) == "bad\\xff.npz"
    assert shown_name(f"cannot read '{BAD}'") == "cannot read 'bad\\xff.npz'"
    assert shown_name(Path("caf\u00e9/x.npz")) == "caf\u00e9/x.npz"  # valid UTF-8 kept
    assert shown_name(b"a\xfeb") == "a\\xfeb"
    assert shown_name("\ud800") == "\\ud800"  # a surrogate no byte gave: its code point


def _run(*argv: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1",
           "LC_ALL": "C.UTF-8"}
    return subprocess.run([sys.executable, "-m", "modalinfo", *argv], cwd=cwd, env=env,
                          capture_output=True, timeout=300, check=False)


def test_error_line_shows_the_byte_as_the_table_does(tmp_path):
    proc = _run("info", BAD, cwd=tmp_path)
    assert proc.returncode == 2
    err = proc.stderr.decode("utf-8")
    assert "bad\\xff.npz" in err and "udcff" not in err and len(err.splitlines()) == 1


@pytest.mark.slow
def test_batch_note_report_and_table_agree(tmp_path):
    from modalinfo.io import save
    from modalinfo.telemetry.log import ModalLog

    folder = tmp_path / "in"
    folder.mkdir()
    log = ModalLog(np.random.default_rng(0).standard_normal((300, 4)), rate=100.0,
                   units="rad")
    save(log, folder / "a.npz")
    shutil.copy(folder / "a.npz", folder / BAD)  # byte-identical: the note lists both
    (folder / os.fsdecode(b"broken\xfe.npz")).write_bytes(b"not a zip")  # an error row
    proc = _run("batch", "in", "--analyses", "summary", "--out", "out", "--workers", "1",
                "--no-plots", cwd=tmp_path)
    assert proc.returncode == 1
    err, out = proc.stderr.decode("utf-8"), proc.stdout.decode("utf-8")
    note = next(line for line in err.splitlines() if "byte-identical" in line)
    assert "bad\\xff.npz" in note and "udcff" not in err
    assert "broken\\xfe.npz [summary]" in out
    table = (tmp_path / "out" / "batch.csv").read_text(encoding="utf-8")
    assert "bad\\xff.npz" in table and "broken\\xfe.npz" in table
