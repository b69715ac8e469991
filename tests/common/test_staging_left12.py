"""Staging left by runs killed outright: removed when its process is provably gone, else named.

Issue 27, leftovers 12-cli item 1. References, outside the code: POSIX and the process
table (a child that has exited and been reaped has no pid: ``os.kill(pid, 0)`` raises;
pytest's parent is alive); ``tempfile``'s naming (``prefix + random + suffix``, the
random part of letters, digits and ``_``); and the names earlier versions staged under,
from ``git log -p`` (``.<out>.partial-<random>`` of ``paper_figures/_common.py`` before
6e88df8, ``.forecast.<random>.tmp`` of ``modalinfo forecast``, ``.<name>.<random>.tmp``
of ``atomic_write``): none records a pid, and some of those runs took no lock, so a live
one may still write there: they are named with the command that removes them, never
removed.
"""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest

from modalinfo.cli.cmd_forecast import write_outputs
from modalinfo.common.files import atomic_write
from modalinfo.common.folders import clean_staging, pid_alive
from modalinfo.common.tasks.rows import clean_run_staging
from modalinfo.forecast import LinearPredictor, evaluate


@pytest.fixture(scope="module")
def dead_pid():
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()  # exited and reaped: the pid names no process (unless reused at once)
    if pid_alive(child.pid):
        pytest.skip("the pid was reused at once")
    return child.pid


def _lines(capsys) -> list[str]:
    return capsys.readouterr().err.splitlines()


def test_a_dead_pid_is_removed_a_live_one_and_a_pidless_one_are_kept(tmp_path, capsys,
                                                                     dead_pid):
    dead = tmp_path / f".out.partial-{dead_pid}-k3j_x9ab"
    live = tmp_path / f".out.partial-{os.getppid()}-a1b2c3d4"
    own = tmp_path / f".out.partial-{os.getpid()}-zz"
    old = tmp_path / ".out.partial-q8w_e7rt"  # written before pids were recorded
    for folder in (dead, live, own, old):
        folder.mkdir()
    (dead / "fig2.png").write_bytes(b"half")
    (tmp_path / "notes.txt").write_text("mine")
    (tmp_path / f".out.partial-{dead_pid}-link").symlink_to(tmp_path / "notes.txt")
    assert clean_staging(tmp_path, ".out.partial-", command="paper_figures") == [dead.name]
    assert not dead.exists() and live.is_dir() and own.is_dir() and old.is_dir()
    assert (tmp_path / "notes.txt").read_text() == "mine"
    said = _lines(capsys)
    assert said[0] == (f"paper_figures: removed 1 staging item(s) of runs that ended without "
                       f"cleaning up (killed) in '{tmp_path}': {dead.name}")
    assert said[1].startswith(f"paper_figures: note: 1 staging item(s) in '{tmp_path}'")
    assert said[1].endswith(f"remove them: rm -r '{old}'") and len(said) == 2


def test_atomic_writes_name_their_process(tmp_path):
    seen = []

    def write(fh):
        seen.extend(p.name for p in tmp_path.iterdir())
        fh.write(b"x")

    atomic_write(tmp_path / "batch.csv", write, overwrite=False)
    (name,) = seen
    assert name.startswith(f".batch.csv.{os.getpid()}-") and name.endswith(".tmp")


def test_batch_and_sweep_temporaries(tmp_path, capsys, dead_pid):
    rows, runs = tmp_path / "rows", tmp_path / "runs"
    rows.mkdir()
    runs.mkdir()
    gone = [rows / f".k1.json.{dead_pid}-ab_12.tmp", tmp_path / f".sweep.csv.{dead_pid}-x.tmp"]
    kept = [rows / ".k1.json.ab_12cd.tmp",  # an earlier version's: no pid
            runs / f".k2.h5.{dead_pid}-cd.tmp",  # a worker's: maybe on another host
            tmp_path / f".lock.{dead_pid}.123.tmp",  # the lock's own: not staging
            rows / "k1.json"]
    for path in gone + kept:
        path.write_text("{}")
    clean_run_staging(tmp_path, "sweep", "closedloop sweep", worker_folders=("runs",))
    assert not any(p.exists() for p in gone) and all(p.exists() for p in kept)
    said = _lines(capsys)
    assert sum("removed 1 staging item(s)" in line for line in said) == 2
    notes = [line for line in said if ": note: " in line]
    assert [n.rsplit("rm -r ", 1)[1] for n in notes] == [f"'{kept[0]}'", f"'{kept[1]}'"]


def test_forecast_removes_a_killed_runs_staging(tmp_path, capsys, dead_pid):
    # write_outputs is where `modalinfo forecast --out` stages its four files
    rng = np.random.default_rng(12)
    ev = evaluate({"linear": LinearPredictor()}, np.cumsum(rng.standard_normal((400, 3)), 0),
                  train=200, horizons=[1, 2])
    out = tmp_path / "fc"
    out.mkdir()
    dead = out / f".forecast.{dead_pid}-u7y6t5r4.tmp"
    old = out / ".forecast.u7y6t5r4.tmp"
    for folder in (dead, old):
        folder.mkdir()
        (folder / "forecast.json").write_text("{}")
    write_outputs(ev, out, overwrite=False)
    assert not dead.exists() and old.is_dir() and (out / "forecast.json").is_file()
    said = [line for line in _lines(capsys) if "staging" in line]
    assert said[0].startswith("modalinfo forecast: removed 1 staging item(s)")
    assert said[1].endswith(f"rm -r '{old}'") and len(said) == 2
    assert [p.name for p in out.iterdir() if p.name.startswith(".")] == [old.name]
