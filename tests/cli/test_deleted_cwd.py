"""The three command lines started in a deleted current folder: one line, exit 2.

Reference: POSIX getcwd(3), which fails with ENOENT once the folder is unlinked, and the
project's rule for a command line (one line on stderr, exit 2, never a traceback). Audit
10-env: numba's import of coverage called ``os.getcwd()`` and every command ended in a
traceback, exit 1. Each case is a subprocess (about a second: the check runs before the
heavy imports).
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("module", ["modalinfo", "closedloop", "paper_figures"])
def test_deleted_current_folder_is_one_line_exit_2(tmp_path, module):
    gone = tmp_path / "gone"
    gone.mkdir()
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    script = (f"import os, subprocess, sys; os.chdir({str(gone)!r}); os.rmdir({str(gone)!r}); "
              f"r = subprocess.run([sys.executable, '-m', {module!r}, '--help'], "
              "capture_output=True, text=True); "
              "sys.stdout.write(str(r.returncode) + '\\n' + r.stderr)")
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                         text=True, timeout=600).stdout
    code, _, err = out.partition("\n")
    assert code == "2", err
    assert "Traceback" not in err and err.count("\n") == 1
    assert "current folder no longer exists" in err
