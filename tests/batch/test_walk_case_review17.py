"""A directory search takes a log whose extension is in upper case (review17, M1).

Reference: the folder's own listing (``os.listdir``) and the extension rule the directory
search had before this session (``Path(name).suffix.lower()`` against the readers'
extensions): ``A.NPY`` written by a Windows tool is the same ``.npy`` log as ``a.npy``,
so it is an entry, not a skipped file. Planted bug M1 (review17: the ``.lower()`` dropped)
listed it as skipped and the batch left it out.
"""

import os

import numpy as np

from modalinfo.batch.manifest import collect_logs


def test_upper_case_extension_is_a_log_not_skipped(tmp_path):
    np.save(tmp_path / "a.npy", np.zeros((10, 2)))
    np.save(tmp_path / "tmp.npy", np.ones((10, 2)))
    os.replace(tmp_path / "tmp.npy", tmp_path / "B.NPY")
    (tmp_path / "notes.PNG").write_bytes(b"x")
    skipped: list[str] = []
    entries = collect_logs(tmp_path, skipped=skipped)
    assert sorted(os.path.basename(e.path) for e in entries) == ["B.NPY", "a.npy"]
    assert [os.path.basename(p) for p in skipped] == ["notes.PNG"]
    assert set(os.listdir(tmp_path)) == {"a.npy", "B.NPY", "notes.PNG"}
