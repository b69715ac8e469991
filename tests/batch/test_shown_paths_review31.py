r"""batch's manifest and memory refusals quote the file shown (review 31, round 31 mutation).

A raw ``'{path}'`` planted back in ``read_manifest``'s per-row refusals or in the quality
pass's memory refusal (``batch/analyses._check_quality_memory``) passed every test.
References, outside the package: the file's bytes (``os.fsencode``) and
``codecs.escape_decode`` of the quoted name (``ls -b``'s escapes back to bytes).
"""

from __future__ import annotations

import os

import numpy as np
import pytest

from tests.io.test_shown_paths_fix48a import BYTE, SLASH, _names_file

STEMS = pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])


@STEMS
def test_a_manifest_rows_refusal(tmp_path, stem):
    from modalinfo.batch.manifest import read_manifest

    path = os.path.join(os.fsencode(tmp_path), stem + b".csv")
    with open(path, "wb") as fh:
        fh.write(b"path,rate\n,100\n")  # row 2: an empty path
    with pytest.raises(ValueError) as caught:
        read_manifest(os.fsdecode(path))
    message = str(caught.value)
    assert "row 2: empty path" in message and _names_file(message, path), ascii(message)


@STEMS
def test_the_quality_pass_memory_refusal(tmp_path, stem, monkeypatch):
    from modalinfo.batch.analyses import _check_quality_memory
    from modalinfo.common import memory
    from modalinfo.telemetry import ModalLog

    monkeypatch.setattr(memory, "usable_memory_bytes", lambda: 0)
    path = os.path.join(os.fsencode(tmp_path), stem + b".npz")
    log = ModalLog(np.zeros((10, 3)), rate=10.0)
    with pytest.raises(MemoryError) as caught:
        _check_quality_memory(os.fsdecode(path), log, "warn")
    assert _names_file(str(caught.value), os.path.basename(path)), ascii(str(caught.value))
