"""Adversarial round 15, PART b: the batch hash cache sees a replaced log.

Reference, outside the code under test: ``hashlib.sha256`` of the two files' bytes
(they differ) and ``os.stat``; a log replaced by another of the same size with its
modification time set back (``cp`` then ``touch -r``) must not keep the cache entry of
the old bytes. Row F13 of docs/ADVERSARIAL.md "Round 15 PART b"; fails on d06a533.
"""

from __future__ import annotations

import hashlib
import os
import shutil

from modalinfo.batch import archive


def test_same_size_replacement_with_mtime_set_back_is_seen(tmp_path):
    a, b = tmp_path / "a.npz", tmp_path / "b.npz"
    a.write_bytes(b"\x01" * 4096)
    b.write_bytes(b"\x02" * 4096)
    assert hashlib.sha256(a.read_bytes()).digest() != hashlib.sha256(b.read_bytes()).digest()
    before = archive._stat(str(a))
    st = os.stat(a)
    shutil.copyfile(b, a)  # same size, new bytes, same inode
    os.utime(a, ns=(st.st_atime_ns, st.st_mtime_ns))  # touch -r: the mtime set back
    assert os.stat(a).st_size == st.st_size and os.stat(a).st_mtime_ns == st.st_mtime_ns
    assert archive._stat(str(a)) != before
    moved = tmp_path / "c.npz"
    shutil.copy2(b, moved)
    os.replace(moved, a)  # mv of a copy: another inode
    assert archive._stat(str(a)) != before
