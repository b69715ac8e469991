r"""Every command's one-line refusals name a user's path in the shown form (fixes 47-b).

Fixes 45-b made ``shown_name`` one-to-one (a literal backslash written ``\\``, an
undecodable byte ``\xNN``, as ``ls -b`` writes them) but only batch applied it to whole
paths: ``modalinfo info 'a\xe9.npz'`` (backslash, x, e, 9) and ``modalinfo info
a<0xE9>.npz`` both said "no such file: 'a\xe9.npz'". Now every message quotes a path
through ``modalinfo.common.files.quoted``. Reference: ``codecs.escape_decode`` of the
quoted text gives back the name's bytes (``os.fsencode``), and the two names read apart.
"""

from __future__ import annotations

import codecs
import os
import re

import numpy as np

from .conftest import exit_code

LITERAL = "a\\xe9.npz"  # backslash, x, e, 9
BYTE = os.fsdecode(b"a\xe9.npz")  # one undecodable byte


def _quoted_names(line: str) -> list[bytes]:
    return [codecs.escape_decode(m.encode("utf-8"))[0] for m in re.findall(r"'([^']*)'", line)]


def test_info_names_a_backslash_and_a_byte_apart(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    lines = []
    for name in (LITERAL, BYTE):
        assert exit_code(["info", name]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "no such file" in err, err
        lines.append(err)
        assert os.fsencode(name) in _quoted_names(err), err
    assert lines[0] != lines[1]
    assert "'a\\\\xe9.npz'" in lines[0]


def test_convert_onto_itself_names_the_backslash_path(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    name = "x\\y.npz"
    np.savez(name, coefficients=np.zeros((10, 3)) + np.arange(3))
    assert exit_code(["convert", name, name]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is the input file IN" in err, err
    assert "'x\\\\y.npz'" in err and "'x\\y.npz'" not in err
    assert _quoted_names(err)[:2] == [os.fsencode(name)] * 2
