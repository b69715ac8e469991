r"""The readers' refusals quote the file in its shown form (fixes 48-a; round 45 PART b E21).

Fixes 47-e made batch show a message cell as written (``files.shown_message``: its paths
already quoted by ``files.quoted``), but the io readers and closedloop's config / grid /
result readers still wrote ``'{path}'`` raw: a file named ``a\xe9.csv`` (a backslash,
x, e, 9) and one whose name holds the byte 0xE9 read alike again in batch's error lines
(CI 10: tests/cli/test_batch_shown_lines_review29.py), and an ``OSError`` a task raised
named its file by ``repr`` (``'b\udce9'``, no byte). References, outside the package:
the file's bytes (``os.fsencode``), and ``codecs.escape_decode`` of the quoted name in
the message, which gives those bytes back from ``ls -b``'s escapes; a shown message is
printable UTF-8 (``str.encode('utf-8')`` does not fail).
"""

from __future__ import annotations

import codecs
import os
import re
import warnings

import pytest

SLASH = b"a\\xe9"  # a literal backslash, then x, e, 9
BYTE = b"b\xe9"  # the byte 0xE9: not UTF-8

# corrupt or refused contents, one per reader the suffix picks
CONTENTS = {
    "npz": b"PK\x03\x04not a zip",
    "csv": b"1,2\n3\n",  # a cut last row
    "fits": b"SIMPLE  = T" + b" " * 100,
    "h5": b"\x89HDF\r\n\x1a\nnot hdf5",
    "npy": b"\x93NUMPY not npy",
    "json": b"{",
}


def _names_file(message: str, path: bytes) -> bool:
    """Whether a quoted name in ``message`` gives the bytes ``path`` back (ls -b escapes)."""
    message.encode("utf-8")  # printable: no lone surrogate (a raw undecodable byte)
    quoted = re.findall(r"'([^']*)'", message)
    return any(codecs.escape_decode(q.encode("utf-8"))[0] == path for q in quoted)


@pytest.mark.parametrize("suffix", sorted(CONTENTS))
@pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])
def test_a_readers_refusal_names_the_files_bytes(tmp_path, suffix, stem):
    from modalinfo.io import load

    path = os.path.join(os.fsencode(tmp_path), stem + b"." + suffix.encode())
    with open(path, "wb") as fh:
        fh.write(CONTENTS[suffix])
    with warnings.catch_warnings(), pytest.raises(Exception) as caught:  # noqa: B017
        warnings.simplefilter("ignore")
        load(os.fsdecode(path))
    assert _names_file(str(caught.value), path), str(caught.value).encode("utf-8", "replace")


@pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])
def test_closedloops_config_and_grid_refusals_name_the_files_bytes(tmp_path, stem):
    from closedloop.config import load_config
    from closedloop.sweep import load_grid

    config = os.path.join(os.fsencode(tmp_path), stem + b".toml")
    with open(config, "wb") as fh:
        fh.write(b"x = = 1\n")
    with pytest.raises(ValueError) as caught:
        load_config(os.fsdecode(config))
    assert _names_file(str(caught.value), config)
    with pytest.raises(ValueError) as caught:
        load_grid(os.fsdecode(config))
    assert _names_file(str(caught.value), config)


@pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])
def test_an_oserror_row_names_the_files_bytes(tmp_path, stem):
    """A task's own ``OSError`` (Python's ``repr`` of the name) becomes a row's message."""
    from modalinfo.common.tasks.threads import _limited_call

    missing = os.path.join(os.fsencode(tmp_path), stem)

    def task(payload):
        with open(os.fsdecode(missing), "rb"):
            return {}

    row = _limited_call(task, {}, 1)
    assert row["status"] == "error" and row["error_type"] == "FileNotFoundError"
    assert _names_file(row["error_message"], missing), ascii(row["error_message"])
