"""Round 19 PART b, N29: a value starting with '-' is named, with the spelling that passes it.

Reference: Python's argparse documentation ("Arguments containing -"): a token that
starts with '-' and does not look like a negative number is an option, and
``--option=-value`` passes it. Checked here with a plain ``argparse.ArgumentParser``.
Before the fix ``closedloop run --memory-limit -0GB`` said only "argument
--memory-limit: expected one argument" of an option that was given one.
"""

import argparse

import pytest

from modalinfo.common.cli import Parser


def _parsers():
    plain, ours = argparse.ArgumentParser(), Parser(prog="prog")
    for p in (plain, ours):
        p.add_argument("--memory-limit")
        p.add_argument("--rate", type=float)
    return plain, ours


def test_dash_value_is_named_with_the_equals_spelling(capsys):
    plain, ours = _parsers()
    assert plain.parse_args(["--memory-limit=-0GB"]).memory_limit == "-0GB"
    with pytest.raises(SystemExit) as exc:
        ours.parse_args(["--memory-limit", "-0GB"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "'-0GB'" in err and "--memory-limit=-0GB" in err
    assert ours.parse_args(["--memory-limit=-0GB"]).memory_limit == "-0GB"


def test_missing_value_keeps_argparse_words(capsys):
    _, ours = _parsers()
    with pytest.raises(SystemExit):
        ours.parse_args(["--rate"])
    assert capsys.readouterr().err == "prog: error: argument --rate: expected one argument\n"
    with pytest.raises(SystemExit):
        ours.parse_args(["--memory-limit", "--rate", "5"])  # a real option follows
    assert "write" not in capsys.readouterr().err
