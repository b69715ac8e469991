"""Round 30 PART b (issue 27): ``data/`` reached through a link is still the shipped data.

docs/ADVERSARIAL.md, "Round 30 PART b, issue 27", D01 / D02: with ``data/`` a symbolic
link (the logs kept on another disk), ``shipped_edit_note`` compared the resolved log
path with an unresolved ``data/`` and never matched: an edited shipped log was reported
without its EDITED note, and Figure 1's table called an untouched shipped log "the log
`...`" while the report's head called it the shipped one.

References: ``hashlib.sha256`` of the committed file against ``SHIPPED_SHA256`` (the
copy is byte-identical, checked here); an edit made with ``numpy.savez`` (values x 2),
whose SHA-256 differs.
"""

from __future__ import annotations

import hashlib
import os
import shutil

import numpy as np
import pytest

from paper_figures import _common
from paper_figures.fig1_fitting_error import _described

NAME = "kaos_closedloop.npz"


@pytest.fixture
def linked_data(tmp_path, monkeypatch):
    if not hasattr(os, "symlink"):
        pytest.skip("no symbolic links here")
    real = tmp_path / "disk" / "logs"
    real.mkdir(parents=True)
    shutil.copyfile(_common._DATA / NAME, real / NAME)
    link = tmp_path / "repo" / "data"
    link.parent.mkdir()
    try:
        link.symlink_to(real, target_is_directory=True)
    except OSError:
        pytest.skip("symbolic links not permitted")
    monkeypatch.setattr(_common, "_DATA", link)
    return link / NAME


def test_a_shipped_log_behind_a_linked_data_folder_is_the_shipped_log(linked_data):
    digest = hashlib.sha256(linked_data.read_bytes()).hexdigest()
    assert digest == _common.SHIPPED_SHA256[NAME]
    assert _common.shipped_edit_note(linked_data) == ""
    assert _common.shipped_log(f"`{linked_data}`") == "simulated"
    assert _described(f"`{linked_data}`") == "our closed-loop residual"


def test_an_edited_log_behind_a_linked_data_folder_is_named_edited(linked_data):
    with np.load(linked_data) as z:
        arrays = {k: z[k] for k in z.files}
    key = next(k for k, v in arrays.items() if v.ndim == 2 and v.dtype.kind == "f")
    arrays[key] = arrays[key] * 2
    np.savez(linked_data, **arrays)
    assert hashlib.sha256(linked_data.read_bytes()).hexdigest() != \
        _common.SHIPPED_SHA256[NAME]
    note = _common.shipped_edit_note(linked_data)
    assert note.startswith("EDITED: not the shipped file")
    assert _common.SHIPPED_SHA256[NAME] in note
