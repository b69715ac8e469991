"""Planted-bug review 26 (stop 50): a missing non-ASCII name beside OTHER files only.

Round 40 PART b F24 names a file of the folder whose name equals the missing one under
:func:`unicodedata.normalize` ("NFC"); a folder holding other files (none equal under
NFC) keeps the plain "no such file" message. Reference: ``unicodedata.normalize`` (the
names differ under NFC). Plant R26-F3 (``e.name != name or ...``: any other file named as
the twin) escaped tests/common/test_unicode_form_missing_file_round40.py, whose folders
held the twin alone or an ASCII name.
"""

import unicodedata

import numpy as np

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def test_a_missing_accented_name_beside_other_files_keeps_the_plain_message(tmp_path,
                                                                             capsys):
    held, typed = "\u00e9t\u00e9.npz", "\u00e9t\u00e8.npz"  # été / étè: other letters
    assert unicodedata.normalize("NFC", held) != unicodedata.normalize("NFC", typed)
    save(ModalLog(np.random.default_rng(40).standard_normal((50, 3)), rate=100.0),
         tmp_path / held)
    (tmp_path / "notes.txt").write_text("x")
    assert main(["info", str(tmp_path / typed), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert err.rstrip().endswith(f"no such file: '{tmp_path / typed}'"), err
