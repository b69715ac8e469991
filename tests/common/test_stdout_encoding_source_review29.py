"""The stdout encoding refusal names where the encoding came from (review29).

Round 29 E6 (modalinfo/common/cli.py:92, ``StdoutEncodingError``): the encoding is named
"from PYTHONIOENCODING" only when that variable sets one; Python's documentation of
PYTHONIOENCODING ("encodingname:errorhandler", both parts optional): ``:strict`` sets the
error handler alone, and the encoding still comes from the locale. Planted as "the
variable is set", it passed every test (all set ``ascii``). Reference: that rule of the
Python documentation, and the round 45 test's stand-in stdout (ascii, strict).
"""

import argparse
import io
import sys

import pytest

from modalinfo.common.cli import dispatch


def _parser(run):
    parser = argparse.ArgumentParser(prog="prog")
    parser.add_subparsers(dest="command").add_parser("go").set_defaults(_run=run)
    return parser


def _run(monkeypatch, capsys) -> str:
    monkeypatch.setattr(sys, "stdout", io.TextIOWrapper(io.BytesIO(), encoding="ascii",
                                                        errors="strict", write_through=True))

    def run(args):
        sys.stdout.write("mode Tip_\u00e9\n")
        return 0

    assert dispatch(_parser(run), ["go"], "prog") == 1
    return capsys.readouterr().err


@pytest.mark.parametrize(("value", "source"), [
    (":strict", "the locale, LC_ALL / LC_CTYPE / LANG"),  # the handler alone
    ("ascii:strict", "PYTHONIOENCODING"),
    ("ascii", "PYTHONIOENCODING"),
])
def test_the_encoding_named_from_where_it_came(monkeypatch, capsys, value, source):
    monkeypatch.setenv("PYTHONIOENCODING", value)
    err = _run(monkeypatch, capsys)
    assert f"its encoding ascii (from {source}) cannot encode '\u00e9' (U+00E9)" in err


def test_without_the_variable_the_locale_is_named(monkeypatch, capsys):
    monkeypatch.delenv("PYTHONIOENCODING", raising=False)
    assert "(from the locale, LC_ALL / LC_CTYPE / LANG)" in _run(monkeypatch, capsys)
