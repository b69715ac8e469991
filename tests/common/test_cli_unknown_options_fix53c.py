"""Stop 59's small items (fix53-c, issue 27): an option a command does not have is named so.

docs/ADVERSARIAL.md, "Round 52 PART b" (Left): ``modalinfo fitting-error --out X`` was
refused as argparse's "ambiguous option: --out could match --outer-scale, --outliers",
though the command has no ``--out`` (its figure is ``--plot``): the words sent the user
to two options that mean something else. ``closedloop export a b --quiet`` said
"closedloop: error: unrecognized arguments" without naming the subcommand that lacks
the option.

Reference: argparse's documented behaviour (a unique prefix of a long option stands for
it, ``allow_abbrev``; a subcommand's parser reports through its own ``prog``; arguments
no parser takes are "unrecognized"), the commands' own option lists (``--help``), and
the project's rule (one line on stderr naming what is wrong, exit status 2).
"""

from __future__ import annotations

import pytest

from modalinfo.common.cli import EXIT_USAGE


def _run(main, argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == EXIT_USAGE
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err  # one line
    return err


def _modalinfo(argv):
    from modalinfo.cli import build_parser

    return build_parser().parse_args(argv)


def _closedloop(argv):
    from closedloop.cli import build_parser

    return build_parser().parse_args(argv)


@pytest.mark.parametrize("argv", [["fitting-error", "--out", "x.png"],
                                  ["fitting-error", "--out=x.png"]])
def test_a_prefix_of_other_options_is_called_no_such_option(capsys, argv):
    err = _run(_modalinfo, argv, capsys)
    assert err.startswith("modalinfo fitting-error: error: ")
    assert "no option --out" in err
    assert "ambiguous" not in err
    assert "--outer-scale" in err and "--outliers" in err  # what it begins, in full


def test_a_unique_prefix_still_stands_for_its_option():
    args = _modalinfo(["fitting-error", "log.npz", "--outer", "30", "--plot", "x.png"])
    assert args.outer_scale == 30.0


@pytest.mark.parametrize("main, argv, prog", [
    (_closedloop, ["export", "a.h5", "b.fits", "--quiet"], "closedloop export"),
    (_modalinfo, ["info", "x.npz", "--bogus"], "modalinfo info"),
])
def test_unrecognized_arguments_name_the_subcommand(capsys, main, argv, prog):
    err = _run(main, argv, capsys)
    assert err.startswith(f"{prog}: error: unrecognized arguments: ")
    assert argv[-1] in err
