"""A warning raised as an error ends a command in one line (adversarial round 9 PART b, N49).

Reference: Python's warnings semantics (``simplefilter("error")``, what
``PYTHONWARNINGS=error`` sets, raises the warning as an exception) and the project's
command-line contract (one line on stderr, exit status 2). Before the fix the exception
left ``dispatch`` as a 58-line traceback (a DM-space K-L cache that could not be written,
under PYTHONWARNINGS=error).
"""

from __future__ import annotations

import warnings

from modalinfo.common.cli import EXIT_USAGE, Parser, dispatch


def _parser() -> Parser:
    parser = Parser(prog="tool")
    sub = parser.add_subparsers(dest="command")
    cmd = sub.add_parser("run")

    def run(args) -> int:
        warnings.warn("the cache could not be written", RuntimeWarning, stacklevel=1)
        return 0

    cmd.set_defaults(_run=run)
    return parser


def test_a_warning_raised_as_an_error_is_one_line(capsys):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert dispatch(_parser(), ["run"], "tool") == EXIT_USAGE
    err = capsys.readouterr().err
    assert err == ("tool run: error: RuntimeWarning raised as an error (PYTHONWARNINGS / "
                   "-W error): the cache could not be written\n")

