r"""Every control character's shown form, and the shell word's quotes (review32, round 32).

Planted-bug review of fix49-c (``files.shown_name`` control characters,
``files.shell_quoted``): fix49-c's tests named one name of a newline, a tab, ESC and
U+009B, so DEL (0x7F) left raw (R32-F1), a carriage return shown ``\n`` (R32-F2) and
``\x1`` for 0x01 without its zero (R32-F3) passed them. Reference, the docstrings'
promises: ``codecs.escape_decode`` of the shown form gives back the name's UTF-8 bytes,
and the shown form is one printable line; ``shell_quoted`` is "always in single quotes"
for a printable UTF-8 name, and ``shlex.split`` of it gives the name back (R32-F5).
"""

from __future__ import annotations

import codecs
import shlex

import pytest

from modalinfo.common.files import shell_quoted, shown_name

#: every character the docstring calls a control: C0, DEL, C1, U+2028 / U+2029
CONTROLS = [chr(c) for c in (*range(0x20), *range(0x7F, 0xA0), 0x2028, 0x2029)]


@pytest.mark.parametrize("char", CONTROLS, ids=lambda c: f"U+{ord(c):04X}")
def test_each_control_is_shown_printable_and_one_to_one(char):
    name = f"a{char}b.npz"
    shown = shown_name(name)
    assert shown.isprintable() and len(shown.splitlines()) == 1, repr(shown)
    assert codecs.escape_decode(shown.encode("utf-8"))[0] == name.encode("utf-8")


@pytest.mark.parametrize("name", ["plain.h5", "k", "a-b_c.npz", "it's.h5", "a b.h5"])
def test_a_printable_name_is_a_single_quoted_word(name):
    word = shell_quoted(name)
    assert word.startswith("'") and word.endswith("'"), word
    assert shlex.split(word) == [name]
