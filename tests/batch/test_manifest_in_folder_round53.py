"""A manifest kept in an archive's folder is not read as a log (round 53 PART b, M16).

Reference: the files the test writes (two ``numpy.save`` logs and a manifest CSV with a
``path`` column, the layout of ``modalinfo.batch.manifest``'s docstring): the walk lists
the two logs, and the manifest apart.
"""

from __future__ import annotations

import numpy as np

from modalinfo.batch.manifest import collect_logs


def test_manifest_in_walked_folder_listed_apart(tmp_path):
    for night in ("2026-11-01", "2026-11-02"):
        (tmp_path / night).mkdir()
        np.save(tmp_path / night / "a.npy", np.zeros((20, 3)))
    (tmp_path / "manifest.csv").write_text("path,rate\n2026-11-01/a.npy,1000\n")
    (tmp_path / "log.csv").write_text("Z2,Z3\n0.1,0.2\n0.3,0.4\n")  # a CSV log stays a log
    found: list[str] = []
    paths = sorted(e.path for e in collect_logs(tmp_path, manifests=found))
    # manifest.csv was a log, its row "corrupt CSV file ... could not convert string
    # '2026-11-01/a.npy' to float64"
    assert paths == sorted(str((tmp_path / p).resolve()) for p in
                           ("2026-11-01/a.npy", "2026-11-02/a.npy", "log.csv"))
    assert found == [str(tmp_path / "manifest.csv")]
