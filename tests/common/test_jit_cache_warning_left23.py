"""The numba no-cache warning: one line from a command, the caller's line from Python.

Reference: POSIX permission rules as the kernel applies them (as
tests/common/test_jit_cache_left19.py): a fresh copy of the package, run as root without
capabilities (``setpriv --bounding-set=-all --inh-caps=-all``) under ``umask 777`` with a
fresh ``HOME``, leaves numba no writable cache folder, so ``modalinfo.common.jit`` warns
while the package loads; and the warnings module's documented forms: a command line
shows its warnings as ``PROG: warning: MESSAGE`` (``modalinfo.common.cli.dispatch``),
Python's default ``formatwarning`` as ``FILE:LINE: CATEGORY: MESSAGE`` followed by that
line of the file. Leftovers 23-misc (issue 27): before, ``modalinfo info --help`` printed
two lines, ``.../modalinfo/bases/_dm_kl_kernels.py:18: RuntimeWarning: ...`` and
``  @jit``, and a script's ``import modalinfo.forecast`` was shown at an ``@jit`` line
of the package rather than at the script's import; under ``PYTHONWARNINGS=error`` the
command ended in a traceback. Skipped, with the reason, where the capabilities cannot
be dropped.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import modalinfo

from ..cli.test_permissions_left18 import nocap  # noqa: F401  (the fixture)


@pytest.fixture(scope="module")
def fresh(tmp_path_factory):
    """A copy of the package without any numba cache, in a folder all may use."""
    root = tmp_path_factory.mktemp("fresh")
    shutil.copytree(Path(modalinfo.__file__).parent, root / "modalinfo",
                    ignore=shutil.ignore_patterns("__pycache__"))
    (root / "script.py").write_text("import numpy\nimport modalinfo.forecast\n",
                                    encoding="utf-8")
    return root


def _run(prefix, root: Path, argv: list[str], home: Path, extra_env=None):
    home.mkdir()
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(root), *sys.path]),
           "HOME": str(home), "XDG_CACHE_HOME": str(home / ".cache")}
    for name in ("NUMBA_CACHE_DIR", "PYTHONWARNINGS"):
        env.pop(name, None)
    env.update(extra_env or {})
    return subprocess.run([*prefix, sys.executable, *argv], cwd=root, env=env,
                          capture_output=True, text=True, timeout=300,
                          preexec_fn=lambda: os.umask(0o777))


def test_command_says_it_in_one_line(nocap, fresh, tmp_path):  # noqa: F811
    run = _run(nocap, fresh, ["-m", "modalinfo", "info", "--help"], tmp_path / "h1")
    assert run.returncode == 0, run.stderr
    lines = run.stderr.splitlines()
    assert len(lines) == 1, run.stderr
    assert lines[0].startswith("modalinfo: warning: numba finds no writable folder")
    assert "NUMBA_CACHE_DIR" in lines[0] and "@jit" not in run.stderr


def test_command_refuses_in_one_line_under_warnings_as_errors(nocap, fresh, tmp_path):  # noqa: F811
    run = _run(nocap, fresh, ["-m", "modalinfo", "info", "--help"], tmp_path / "h2",
               {"PYTHONWARNINGS": "error"})
    assert run.returncode == 2, run.stderr
    assert "Traceback" not in run.stderr
    lines = run.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        "modalinfo: error: RuntimeWarning raised as an error"), run.stderr


def test_python_shows_the_callers_line(nocap, fresh, tmp_path):  # noqa: F811
    run = _run(nocap, fresh, [str(fresh / "script.py")], tmp_path / "h3")
    assert run.returncode == 0, run.stderr
    lines = run.stderr.splitlines()
    # Python's form: the script's line 2 (its import), then that line of the script
    assert len(lines) == 2, run.stderr
    assert lines[0].startswith(f"{fresh / 'script.py'}:2: RuntimeWarning: numba finds no")
    assert lines[1].strip() == "import modalinfo.forecast"
