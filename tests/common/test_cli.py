"""Tests of modalinfo.common.cli.Parser: contradictory flags of one setting are refused.

Reference: argparse's documented behaviour (the last of two actions on one ``dest``
wins, silently); the rule here is the one the Parser applies to options given twice
(adversarial rounds 2 and 5): one line on stderr naming both, exit status 2.
"""

import argparse

import pytest

from modalinfo.common.cli import EXIT_USAGE, Parser


def _parser() -> Parser:
    parser = Parser(prog="prog")
    parser.add_argument("--transpose", action=argparse.BooleanOptionalAction, default=None)
    parser.add_argument("--closed-loop", dest="closed", action="store_true", default=True)
    parser.add_argument("--open-loop", dest="closed", action="store_false")
    parser.add_argument("--quiet", action="store_true")
    return parser


@pytest.mark.parametrize("argv, first, second", [
    (["--transpose", "--no-transpose"], "--transpose", "--no-transpose"),
    (["--no-transpose", "--transpose"], "--no-transpose", "--transpose"),
    (["--closed-loop", "--open-loop"], "--closed-loop", "--open-loop"),
])
def test_two_flags_setting_one_value_differently_are_refused(capsys, argv, first, second):
    with pytest.raises(SystemExit) as exc:
        _parser().parse_args(argv)
    assert exc.value.code == EXIT_USAGE
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert f"argument {second}: contradicts {first}" in err


@pytest.mark.parametrize("argv, transpose, closed", [
    (["--no-transpose", "--no-transpose"], False, True),
    (["--quiet", "--quiet", "--open-loop", "--open-loop"], None, False),
    (["--transpose"], True, True),
])
def test_a_flag_repeated_with_the_same_meaning_still_parses(argv, transpose, closed):
    args = _parser().parse_args(argv)
    assert args.transpose is transpose and args.closed is closed


def test_an_old_spelling_and_the_new_one_with_different_values_are_refused(capsys):
    # round 5, row i46: `--in-modes 2-28 --modes 3-29` analysed Z3..Z29 without a word
    class Alias(argparse.Action):
        stores_value = True

        def __call__(self, parser, namespace, values, option_string=None):
            setattr(namespace, self.dest, values)

    parser = Parser(prog="prog")
    parser.add_argument("--in-modes", dest="in_modes")
    parser.add_argument("--modes", dest="in_modes", action=Alias)
    with pytest.raises(SystemExit):
        parser.parse_args(["--in-modes", "2-28", "--modes", "3-29"])
    assert "argument --modes: given twice (--in-modes 2-28 and --modes 3-29)" in (
        capsys.readouterr().err)
    assert parser.parse_args(["--in-modes", "2-28", "--modes", "2-28"]).in_modes == "2-28"


# ---------------------------------------------------------------------------------------
# Audit 10-env: streams that refuse the output. Reference: /dev/full's contract (every
# write fails with ENOSPC) and POSIX's exit-status rule (an output not written is a
# failure, never 0; a refusal stays 2 even when its one line cannot be written).
class _Full:
    """A stream like /dev/full."""

    def write(self, text):
        raise OSError(28, "No space left on device")

    def flush(self):
        raise OSError(28, "No space left on device")


def test_help_to_a_full_disk_is_a_failure_not_exit_0(monkeypatch):
    monkeypatch.setattr("sys.stdout", _Full())
    with pytest.raises(SystemExit) as info:
        _parser().parse_args(["--help"])  # argparse itself swallows the OSError: exit 0
    assert info.value.code == 1


def test_a_refusal_whose_line_cannot_be_written_still_exits_2(monkeypatch):
    from modalinfo.common.cli import CommandError, dispatch

    parser = Parser(prog="prog")
    sub = parser.add_subparsers(dest="command")
    cmd = sub.add_parser("do")

    def run(args):
        raise CommandError("bad input")

    cmd.set_defaults(_run=run)
    monkeypatch.setattr("sys.stderr", _Full())
    assert dispatch(parser, ["do"], "prog") == EXIT_USAGE
    with pytest.raises(SystemExit) as info:
        parser.parse_args(["do", "--bogus"])
    assert info.value.code == EXIT_USAGE


def test_a_low_open_file_limit_is_refused_before_a_local_cluster(monkeypatch):
    # audit 10-env: `ulimit -n 30; modalinfo batch ...` printed Dask's and psutil's
    # "Too many open files" tracebacks; 64 ran clean. Reference: getrlimit(2)'s soft
    # limit, the one the kernel enforces on open(2).
    import resource

    from modalinfo.common.cli import CommandError, check_cluster_args

    args = argparse.Namespace(command="batch", workers=1, threads_per_worker=None,
                              worker_wait=None, memory_limit=None, scheduler=None)
    monkeypatch.setattr(resource, "getrlimit", lambda which: (30, 4096))
    with pytest.raises(CommandError, match=r"ulimit -n\) is 30; .* at least 64"):
        check_cluster_args(args)
    args.scheduler = "tcp://elsewhere:8786"  # a remote cluster's limits are its own
    check_cluster_args(args)
    monkeypatch.setattr(resource, "getrlimit", lambda which: (64, 4096))
    args.scheduler = None
    check_cluster_args(args)
