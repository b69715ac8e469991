"""A sweep folder moved or copied, then resumed (adversarial round 20 PART b, issue 27).

Reference from outside the code: the file system. Every ``result_file`` of the table
must name a file that exists inside the folder the table is in (``os.path`` on the
moved and the copied folder; the original removed, or kept beside the copy). Before
the fix the table kept the absolute path of the first run: a file gone after a move,
the original's file after a copy.
"""

from __future__ import annotations

import csv
import shutil
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from closedloop.config import save_config  # noqa: E402
from closedloop.sweep import load_grid, sweep  # noqa: E402

from .conftest import small  # noqa: E402

GRID = """
config = "small.toml"
duration = 0.05
seeds = [0]
predictors = ["none"]
"""


def _files(folder: Path) -> list[Path]:
    with open(folder / "sweep.csv", encoding="utf-8", newline="") as fh:
        return [Path(r["result_file"]) for r in csv.DictReader(fh)]


def test_result_files_follow_a_moved_and_a_copied_sweep_folder(tmp_path, monkeypatch):
    save_config(small(), tmp_path / "small.toml")
    (tmp_path / "grid.toml").write_text(GRID)
    grid = load_grid(tmp_path / "grid.toml")
    rows, _ = sweep(grid, tmp_path / "first", n_workers=1, threads_per_worker=1,
                    progress=False)
    assert [r["status"] for r in rows] == ["ok"]
    moved = tmp_path / "moved"
    shutil.move(tmp_path / "first", moved)
    rows, report = sweep(grid, moved, progress=False)  # resumed: nothing runs
    assert report.n_specs == 1 and report.n_skipped == 1
    for files in ([Path(r["result_file"]) for r in rows], _files(moved)):
        assert files and all(f.is_file() and f.parent == moved.resolve() / "runs"
                             for f in files)
    copy = tmp_path / "copy"
    shutil.copytree(moved, copy)
    sweep(grid, copy, progress=False)
    assert all(f.is_file() and f.parent == copy.resolve() / "runs" for f in _files(copy))
    # resumed through a relative --out (review19, planted bug SW1): the table still
    # names absolute files, found from any working directory
    monkeypatch.chdir(tmp_path)
    rows, _ = sweep(grid, Path("copy"), progress=False)
    monkeypatch.chdir(moved)
    for files in ([Path(r["result_file"]) for r in rows], _files(copy)):
        assert files and all(f.is_absolute() and f.is_file()
                             and f.parent == copy.resolve() / "runs" for f in files)
