"""Round 8 of issue 27's adversarial inputs (command lines): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 8, issue 27".

Reference: the dispatcher contract (one line on stderr, exit 2, no traceback, also for
an environment that numba refuses at import) and the
AOT format: a loop whose coefficients carry labels but no ``modes`` data (the mode
images) holds no modal basis, which the message must say without contradicting
``modalinfo info`` (which lists the labels).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("aotpy")

from .conftest import exit_code  # noqa: E402
from .test_cli_aot import naomi_file  # noqa: E402, F401  (the shared AOT fixture)

ROOT = Path(__file__).resolve().parents[2]


def test_reorder_basis_file_of_a_loop_without_mode_images_says_so(naomi_file, capsys):  # noqa: F811
    # e122: an exported DM-K-L run (coefficients DMKL1..40, no mode images) was refused
    # with "loop 'dm0.pol' has no modes" while `modalinfo info` listed its 40 modes
    code = exit_code(["reorder", naomi_file, "--loop", "Other", "--basis", "file"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert "has no mode images" in err and "no modal basis can be read" in err


@pytest.mark.parametrize("command", [["modalinfo", "info", "x.npz"],
                                     ["closedloop", "info", "x.h5"],
                                     ["paper_figures", "--only", "1"]])
def test_numba_refusing_its_environment_is_one_line_exit_2(command, tmp_path):
    # e105: NUMBA_NUM_THREADS=0 made numba's import raise: a 48-line traceback, exit 1
    env = dict(os.environ, NUMBA_NUM_THREADS="0",
               PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    p = subprocess.run([sys.executable, "-m", *command], cwd=tmp_path, env=env,
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 2, p.stderr
    assert p.stderr.count("\n") == 1 and "Traceback" not in p.stderr
    assert "NUMBA_NUM_THREADS must be >= 1" in p.stderr
