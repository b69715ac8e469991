"""A log named in another Unicode form than the file's: the refusal names the file's twin.

Round 40 PART b F24: ``info f24/é.npz`` typed in NFD (``e`` + U+0301) beside a file
``é.npz`` saved in NFC (U+00E9) said only "no such file: 'f24/é.npz'" - both names look
the same on a terminal. Reference: :func:`unicodedata.normalize` (the two names are equal
under NFC) and the file system itself (Linux keeps the bytes: a name typed in the other
form opens nothing). An ASCII name that is missing keeps the plain message.
"""

import unicodedata

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog

NFC = "\u00e9t\u00e9.npz"
NFD = unicodedata.normalize("NFD", NFC)


@pytest.mark.parametrize("held, typed", [(NFC, NFD), (NFD, NFC)])
def test_missing_name_in_another_unicode_form_names_the_file(tmp_path, capsys, held, typed):
    save(ModalLog(np.random.default_rng(40).standard_normal((50, 3)), rate=100.0),
         tmp_path / held)
    if (tmp_path / typed).exists():
        pytest.skip("this file system normalises names (both forms open the file)")
    assert unicodedata.normalize("NFC", typed) == unicodedata.normalize("NFC", held)
    code = main(["info", str(tmp_path / typed), "--quiet"])
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "no such file" in err, err
    form = "NFC" if held == NFC else "NFD"
    assert f"holds '{held}', the same name in Unicode form {form}" in err, err


def test_a_missing_ascii_name_keeps_the_plain_message(tmp_path, capsys):
    save(ModalLog(np.zeros((50, 3)) + 1.0, rate=100.0), tmp_path / "a.npz")
    assert main(["info", str(tmp_path / "b.npz"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.rstrip().endswith(f"no such file: '{tmp_path / 'b.npz'}'"), err
