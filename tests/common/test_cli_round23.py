"""Round 23 PART b: option spellings at the command line (abbreviations given twice, '-').

Reference: argparse's documented behaviour - a unique prefix of a long option stands for
it (``allow_abbrev``) and of two values for one option the last wins silently - against
the project's rule for options given twice (one line naming both, exit status 2), and the
Unix convention that '-' names standard input / output, which these commands do not read
or write (so it must be refused, not taken as a missing file or made into a folder).
"""

import argparse
from pathlib import Path

import pytest

from modalinfo.common.cli import EXIT_USAGE, Parser, path_problem


def _parser() -> Parser:
    parser = Parser(prog="prog")
    parser.add_argument("--horizon", type=int)
    parser.add_argument("--outliers")
    parser.add_argument("--out", type=Path)
    parser.add_argument("--transpose", action=argparse.BooleanOptionalAction, default=None)
    return parser


@pytest.mark.parametrize("argv", [
    ["--hor", "1", "--hor", "2"],
    ["--horizon", "1", "--hor", "2"],
    ["--hor=1", "--horizon=2"],
    ["--outl", "clip", "--outliers", "drop"],
])
def test_an_abbreviated_option_given_twice_is_refused(capsys, argv):
    with pytest.raises(SystemExit) as exc:
        _parser().parse_args(argv)
    assert exc.value.code == EXIT_USAGE
    err = capsys.readouterr().err
    assert "given twice" in err and err.count("\n") == 1


def test_abbreviated_flags_that_contradict_are_refused(capsys):
    with pytest.raises(SystemExit):
        _parser().parse_args(["--no-trans", "--trans"])
    assert "contradicts" in capsys.readouterr().err


def test_an_abbreviation_given_once_or_twice_alike_still_parses():
    args = _parser().parse_args(["--hor", "3", "--horizon", "3", "--outl", "clip"])
    assert (args.horizon, args.outliers) == (3, "clip")


def test_dash_as_a_path_is_refused_naming_standard_streams(capsys):
    assert "standard input / output" in path_problem("-")
    assert path_problem("./-") is None and path_problem("-x.npz") is None
    with pytest.raises(SystemExit) as exc:
        _parser().parse_args(["--out", "-"])
    assert exc.value.code == EXIT_USAGE
    assert "argument --out: '-' means standard input / output" in capsys.readouterr().err
