r"""``error_line`` and the dispatcher's error lines (review 31, round 31 mutation).

Planted slips that passed every test: ``error_line`` dropping an ``OSError``'s second
file name (``filename2``, Python's ``'a' -> 'b'`` form), taking the last line instead of
the first, ``dispatch`` losing the type name of a blank message, and ``_file_too_large``
testing the raw name (which a shown message never holds when the name has a backslash or
an undecodable byte) and so naming the file twice. ``RowStore.write``'s refusal when the
output folder went away named its ``rows`` folder raw. References, outside the package:
a real ``os.link`` onto an existing name (Python formats its ``OSError``), the files'
bytes (``os.fsencode``), ``codecs.escape_decode`` of each quoted name (``ls -b``'s
escapes back to bytes) and the docstrings' promises ("the first line", "the text for an
error whose message is blank", "say which file").
"""

from __future__ import annotations

import codecs
import errno
import os
import re
import shutil

import pytest

from modalinfo.common.files import error_line

SLASH = b"a\\xe9"  # a literal backslash, then x, e, 9
BYTE = b"b\xe9"  # the byte 0xE9: not UTF-8
STEMS = pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])


def _quoted_bytes(message: str) -> list[bytes]:
    message.encode("utf-8")  # printable: no lone surrogate
    return [codecs.escape_decode(q.encode("utf-8"))[0] for q in re.findall(r"'([^']*)'", message)]


@STEMS
def test_both_names_of_a_two_file_oserror_are_shown(tmp_path, stem):
    src = os.path.join(os.fsencode(tmp_path), stem + b".src")
    dst = os.path.join(os.fsencode(tmp_path), stem + b".dst")
    for name in (src, dst):
        open(name, "wb").close()
    with pytest.raises(FileExistsError) as caught:
        os.link(os.fsdecode(src), os.fsdecode(dst))
    assert caught.value.filename2 is not None  # Python's own 'a' -> 'b' form
    assert _quoted_bytes(error_line(caught.value)) == [src, dst], ascii(error_line(caught.value))


def test_the_first_line_is_kept():
    assert error_line(ValueError("first line\nsecond line\n")) == "first line"
    assert error_line(ValueError("  \n"), "ValueError") == "ValueError"


def _dispatch(exc, capsys) -> tuple[int, str]:
    from modalinfo.common.cli import Parser, dispatch

    parser = Parser(prog="prog")
    cmd = parser.add_subparsers(dest="command").add_parser("do")

    def run(args):
        raise exc

    cmd.set_defaults(_run=run)
    code = dispatch(parser, ["do"], "prog")
    return code, capsys.readouterr().err


def test_a_blank_message_is_named_by_its_type(capsys):
    code, err = _dispatch(ValueError(""), capsys)
    assert code == 2 and err == "prog do: error: ValueError\n", err


@STEMS
def test_a_file_too_large_is_named_once(tmp_path, stem, capsys):
    path = os.path.join(os.fsencode(tmp_path), stem + b".out")
    code, err = _dispatch(OSError(errno.EFBIG, "File too large", os.fsdecode(path)), capsys)
    assert err.count("\n") == 1 and "ulimit -f" in err
    assert _quoted_bytes(err) == [path], ascii(err)


@STEMS
def test_a_row_store_whose_folder_went_names_both_shown(tmp_path, stem):
    from modalinfo.common.files import OutputGoneError
    from modalinfo.common.tasks.rows import RowStore

    out = os.path.join(os.fsencode(tmp_path), stem)
    store = RowStore(os.fsdecode(out))
    shutil.rmtree(out)
    with pytest.raises(OutputGoneError) as caught:
        store.write("k", {"status": "ok"})
    assert _quoted_bytes(caught.value.strerror) == [out, os.path.join(out, b"rows")], \
        ascii(caught.value.strerror)
