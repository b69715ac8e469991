"""Round 18 PART b: files a batch directory search leaves out are named, not dropped.

Reference: the folder's own listing (``os.listdir``): every non-hidden file is either a
log entry or a skipped path, so the two lists partition it. Before the fix an AOT file
named ``.aot`` (which ``modalinfo info`` reads) and a ``.csv.gz`` vanished from the
batch table with no word (M01 / M03).
"""

import os

import numpy as np

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
