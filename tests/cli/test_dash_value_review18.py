"""Planted-bug review 18 (issue 27): no hint before an option spelled ``--opt=value``.

Round 19 PART b (N29) explains argparse's "expected one argument" when the value was
there but starts with '-'. A following token ``--rate=5`` is not such a value: it is the
option ``--rate`` with its value, and the hint must not tell the user to write
``--memory-limit=--rate=5``. Reference: Python's plain ``argparse.ArgumentParser``, which
reads ``--rate=5`` as the option ``--rate`` and gives the same error for the line.
"""

import argparse

import pytest

from modalinfo.common.cli import Parser


def test_an_option_with_equals_after_a_valueless_option_gets_no_hint(capsys):
    plain, ours = argparse.ArgumentParser(), Parser(prog="prog")
    for p in (plain, ours):
        p.add_argument("--memory-limit")
        p.add_argument("--rate", type=float)
    assert plain.parse_args(["--rate=5"]).rate == 5.0
    with pytest.raises(SystemExit):
        plain.parse_args(["--memory-limit", "--rate=5"])
    plain_err = capsys.readouterr().err.strip().splitlines()[-1]
    assert plain_err.endswith("argument --memory-limit: expected one argument")
    with pytest.raises(SystemExit) as exc:
        ours.parse_args(["--memory-limit", "--rate=5"])
    assert exc.value.code == 2
    assert capsys.readouterr().err == ("prog: error: argument --memory-limit: expected one "
                                       "argument\n")
