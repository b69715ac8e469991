"""Permission refusals without root's capabilities: one line naming the path and the remedy.

Reference: POSIX permission rules as the kernel applies them -- a folder created under
``umask 777`` has mode 000 (``0o777 & ~umask``), in which its owner without
``CAP_DAC_OVERRIDE`` can create no file; a folder of mode 000 cannot be listed by it.
The commands run in a subprocess under ``setpriv --bounding-set=-all --inh-caps=-all``
(root with every capability dropped, so the modes bind; the venv lives under /root, so
another uid could not run it). Adversarial round 18 PART b, rows H14 (forecast --out:
a bare "[Errno 13]" on a temporary name, the empty mode-000 folder left), H15 (batch
--out: the same on the lock's temporary name) and U06 (a batch input folder with an
unreadable subfolder refused whole with a bare "[Errno 13]").

Skipped, with the reason, where the process is not root or ``setpriv`` cannot drop the
capabilities (the check is a real read of a mode-000 file under it).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from .conftest import write_small_log

SETPRIV = shutil.which("setpriv")
NOCAP = [SETPRIV or "setpriv", "--bounding-set=-all", "--inh-caps=-all"]


def _caps_drop_binds(tmp: Path) -> str:
    """Return why the test cannot run here, or '' when a mode-000 file is refused."""
    if not hasattr(os, "geteuid") or os.geteuid() != 0:
        return "needs root, to drop its capabilities with setpriv"
    if SETPRIV is None:
        return "setpriv (util-linux) is not installed"
    probe = tmp / "probe"
    probe.write_text("x")
    probe.chmod(0)
    run = subprocess.run([*NOCAP, "cat", str(probe)], capture_output=True, timeout=30)
    probe.chmod(0o600)
    if run.returncode == 0:
        return "setpriv did not drop CAP_DAC_OVERRIDE here (a mode-000 file was read)"
    if b"ermission denied" not in run.stderr:
        return f"setpriv cannot drop capabilities here: {run.stderr.decode().strip()}"
    return ""


@pytest.fixture(scope="module")
def nocap(tmp_path_factory):
    why = _caps_drop_binds(tmp_path_factory.mktemp("probe"))
    if why:
        pytest.skip(why)
    return NOCAP


def _cli(prefix, argv, cwd, umask=None):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    pre = (lambda: os.umask(umask)) if umask is not None else None
    return subprocess.run([*prefix, sys.executable, "-m", "modalinfo", *argv], cwd=cwd,
                          env=env, capture_output=True, text=True, timeout=300,
                          preexec_fn=pre)


def _one_line(run) -> str:
    lines = [ln for ln in run.stderr.strip().splitlines() if ln.startswith("modalinfo ")]
    assert len(run.stderr.strip().splitlines()) == 1, run.stderr
    return lines[0]


def test_forecast_out_under_umask_777(nocap, tmp_path):
    write_small_log(tmp_path / "log.npz", 400)
    argv = ["forecast", "log.npz", "--horizon", "2", "--predictors", "linear", "--quiet"]
    # the same run with the usual umask works (and compiles what it needs into the
    # package's caches, which a umask-777 run could not write)
    assert _cli([], [*argv, "--out", "ok"], tmp_path).returncode == 0
    for out in ("H14", "new/deep/H14"):
        run = _cli(nocap, [*argv, "--out", out], tmp_path, umask=0o777)
        assert run.returncode == 2
        line = _one_line(run)
        assert "Errno" not in line and "umask 777" in line and "set umask 022" in line
        assert f"into '{out.split('/')[0]}'" in line  # the outermost folder it made
        assert not (tmp_path / out.split("/")[0]).exists()  # nothing left behind


def test_batch_out_under_umask_777(nocap, tmp_path):
    write_small_log(tmp_path / "log.npz", 200)
    run = _cli(nocap, ["batch", "log.npz", "--out", "H15", "--quiet"], tmp_path, umask=0o777)
    assert run.returncode == 2
    line = _one_line(run)
    assert "Errno" not in line and "'H15'" in line and "set umask 022" in line
    assert not (tmp_path / "H15").exists()


def test_batch_names_an_unreadable_subfolder(nocap, tmp_path):
    (tmp_path / "in" / "closed").mkdir(parents=True)
    write_small_log(tmp_path / "in" / "a.npz", 200)
    write_small_log(tmp_path / "in" / "closed" / "b.npz", 300)
    (tmp_path / "in" / "closed").chmod(0)
    try:
        run = _cli(nocap, ["batch", "in", "--out", "out", "--analyses", "summary",
                           "--no-plots"], tmp_path)
    finally:
        (tmp_path / "in" / "closed").chmod(0o755)
    assert run.returncode == 0, run.stderr
    assert "Errno" not in run.stderr
    assert "1 subfolder(s) of the input folders cannot be read" in run.stderr
    assert os.path.join("in", "closed") in run.stderr
    table = (tmp_path / "out" / "batch.csv").read_text()
    assert "a.npz" in table and "b.npz" not in table
