"""One program name in every refusal of ``python -m paper_figures`` (fixes 45-c).

Round 44 PART b c08: argparse's refusals said "python -m paper_figures: error:" (its
``prog``, the name typed: round 16 PART b, I24) while the command's own said
"paper_figures: error:". Reference: argparse's own line for the same parser
(``prog`` + ": error: "), read from its output, not from our code.
"""

from __future__ import annotations

import pytest

from paper_figures.__main__ import main


def _first_word(err: str) -> str:
    return err.split(": error: ", 1)[0]


def test_argparse_and_own_refusals_share_the_program_name(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--onl", "2", "--on", "5"])  # argparse's: given twice through prefixes
    assert exc.value.code == 2
    argparse_line = capsys.readouterr().err
    assert main(["--only", "9", "--out", str(tmp_path / "o")]) == 2  # the command's own
    own_line = capsys.readouterr().err
    assert own_line.count("\n") == 1
    assert _first_word(own_line) == _first_word(argparse_line.strip().splitlines()[-1])
    assert own_line.startswith("python -m paper_figures: error: --only")
