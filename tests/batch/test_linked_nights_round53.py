"""A night linked into an archive from another disk is walked (round 53 PART b, M04).

Reference: the files on disk (``os.walk`` of the link's target, written by the test);
every log of the archive, reached by any path, is listed once under its real path.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

from modalinfo.batch.manifest import collect_logs


def _log(path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    np.save(path, np.zeros((20, 3)))


@pytest.fixture
def archive(tmp_path):
    root = tmp_path / "arch"
    _log(root / "2026-11-01" / "a.npy")
    _log(tmp_path / "disk2" / "night" / "b.npy")
    os.symlink(tmp_path / "disk2" / "night", root / "2026-11-02")
    return root, tmp_path


def test_linked_night_is_walked(archive):
    root, tmp = archive
    paths = sorted(e.path for e in collect_logs(root))
    # the linked night's log was missing: ['.../2026-11-01/a.npy'] only
    assert paths == sorted([str((root / "2026-11-01" / "a.npy").resolve()),
                            str((tmp / "disk2" / "night" / "b.npy").resolve())])


def test_loops_and_second_links_list_each_log_once(archive):
    root, tmp = archive
    os.symlink(root, root / "2026-11-01" / "up")          # a loop to the archive's top
    os.symlink(tmp / "disk2" / "night", root / "latest")  # a second link to one night
    paths = [e.path for e in collect_logs(root)]
    assert sorted(paths) == sorted(set(paths))
    assert len(paths) == 2
