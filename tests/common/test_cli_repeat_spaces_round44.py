"""An option given twice with values that differ in white space only: the message shows it.

Round 44 PART b, a07: ``synth --frames '300 ' --frames=300`` was refused "given twice
(--frames 300  and --frames 300)": two values printed alike, the trailing space invisible.
Reference: Python's ``repr`` of the two strings as typed (``'300 '`` and ``'300'``);
values that differ otherwise keep the plain spelling of round 23's message.
"""

import pytest

from modalinfo.common.cli import Parser


def _parser():
    parser = Parser(prog="prog", exit_on_error=False)
    parser.add_argument("--frames", type=int)
    return parser


@pytest.mark.parametrize("argv", [["--frames", "300 ", "--frames=300"],
                                  ["--frames", "\t300", "--fr", "300"]])
def test_white_space_difference_is_shown(capsys, argv):
    with pytest.raises(SystemExit) as exc:
        _parser().parse_args(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    first, second = argv[1], argv[-1].partition("=")[2] or argv[-1]
    assert f"{first!r} and --frames {second!r}, which differ in white space" in err


def test_other_difference_keeps_plain_values(capsys):
    with pytest.raises(SystemExit):
        _parser().parse_args(["--frames", "300", "--frames", "400"])
    assert "given twice (--frames 300 and --frames 400); give it once" in \
        capsys.readouterr().err


def test_same_value_still_allowed():
    assert _parser().parse_args(["--frames", "300", "--frames=300"]).frames == 300
