"""Round 18 PART b: files a batch directory search leaves out are named, not dropped.

Reference: the folder's own listing (``os.listdir``): every non-hidden file is either a
log entry or a skipped path, so the two lists partition it. Before the fix an AOT file
named ``.aot`` (which ``modalinfo info`` reads) and a ``.csv.gz`` vanished from the
batch table with no word (M01 / M03). A glob whose folder part holds brackets gets a
hint that, followed literally, works (M10; reference: ``glob.escape``).
"""

import glob
import os

import numpy as np
import pytest

from modalinfo.batch.manifest import collect_logs


def test_directory_search_names_every_skipped_file(tmp_path):
    np.save(tmp_path / "a.npy", np.zeros((10, 2)))
    for name in ("b.aot", "c.csv.gz", "README.md", ".hidden.npz"):
        (tmp_path / name).write_bytes(b"x")
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "d.png").write_bytes(b"x")
    skipped: list[str] = []
    entries = collect_logs(tmp_path, skipped=skipped)
    assert [os.path.basename(e.path) for e in entries] == ["a.npy"]
    assert sorted(os.path.basename(p) for p in skipped) == ["README.md", "b.aot", "c.csv.gz",
                                                           "d.png"]
    listed = {n for n in os.listdir(tmp_path) if not n.startswith(".")} - {"sub"}
    assert listed == {"a.npy"} | {os.path.basename(p) for p in skipped} - {"d.png"}


def test_skipped_is_optional(tmp_path):
    np.save(tmp_path / "a.npy", np.zeros((10, 2)))
    (tmp_path / "b.aot").write_bytes(b"x")
    assert len(collect_logs(tmp_path)) == 1


def test_glob_with_a_bracketed_folder_gets_a_hint_that_works(tmp_path):
    """M10: 'night [1]/*.npy' matched nothing with no word on why; the hint, followed
    literally, finds the log (reference: ``glob.escape``, Python's own remedy)."""
    folder = tmp_path / "night [1]"
    folder.mkdir()
    np.save(folder / "a.npy", np.zeros((10, 2)))
    pattern = str(folder / "*.npy")
    with pytest.raises(ValueError, match="matches no file") as err:
        collect_logs(pattern)
    fixed = str(err.value).rsplit("write ", 1)[-1].strip("'")
    assert fixed == glob.escape(str(folder)) + "/*.npy"
    assert [os.path.basename(e.path) for e in collect_logs(fixed)] == ["a.npy"]
