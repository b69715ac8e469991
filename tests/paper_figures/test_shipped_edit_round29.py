"""A shipped log edited in ``data/`` is said to be edited (adversarial round 29 PART b).

References: ``hashlib.sha256`` of the committed files (``sha256sum data/*.npz``, the
values :data:`paper_figures._common.SHIPPED_SHA256` records) and a copy edited with
numpy. ``paper_figures`` on a ``data/kaos_like_closed_loop.npz`` scaled by 2 (P09) or
with one value x 1.5 (P10) described it as the "spectral KAOS-like log" / "simulated
kaos closed-loop log" with no word that it was not the shipped file.
"""

from __future__ import annotations

import hashlib
import shutil

import numpy as np

from paper_figures import _common

SHIPPED = _common._DATA  # the repository's data/ (before the test moves _DATA)


def _sha256(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_the_recorded_digests_are_the_committed_files():
    for name, digest in _common.SHIPPED_SHA256.items():
        assert _sha256(_common._DATA / name) == digest, name
        assert _common.shipped_edit_note(_common._DATA / name) == ""


def test_an_edited_shipped_log_is_named_edited(tmp_path, monkeypatch):
    monkeypatch.setattr(_common, "_DATA", tmp_path)
    name = "kaos_closedloop.npz"
    copy = tmp_path / name
    shutil.copyfile(SHIPPED / name, copy)
    assert _common.shipped_edit_note(copy) == ""  # a byte copy is the shipped file
    members = dict(np.load(copy))
    members["coefficients"][100, 3] *= 1.5
    np.savez(copy, **members)
    note = _common.shipped_edit_note(copy)
    assert note.startswith("EDITED: not the shipped file")
    assert _common.SHIPPED_SHA256[name] in note
    # a user's file of the same name elsewhere is not a shipped log: nothing said
    other = tmp_path / "elsewhere"
    other.mkdir()
    shutil.copyfile(copy, other / name)
    assert _common.shipped_edit_note(other / name) == ""
