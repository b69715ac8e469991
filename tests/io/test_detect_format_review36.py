"""Mutation round 36 (review36): a ``.csv`` name does not stop the content checks.

fix53-c's ``detect_format`` returns the extension's format for binary files before
decoding them, all but ``csv``'s; the plant dropping ``and by_ext != "csv"`` escaped
stop 60's tests. Reference: Python's codecs (the file is written as UTF-16 with its
BOM); the words of round 9 PART b, N44 ("it is UTF-16 text; a CSV must be UTF-8").
"""

from __future__ import annotations

import pytest

from modalinfo.io import load
from modalinfo.io.files import LogFormatError


def test_a_utf16_csv_is_named_as_such(tmp_path):
    path = tmp_path / "u16.csv"
    path.write_bytes("Z2,Z3\n0.1,0.2\n0.3,0.4\n".encode("utf-16"))
    with pytest.raises(LogFormatError, match="it is UTF-16 text; a CSV must be UTF-8"):
        load(path, rate=1000.0)
