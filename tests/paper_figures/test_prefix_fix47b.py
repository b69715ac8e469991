"""paper_figures' notes and warnings start with the program typed, as its errors do.

Fixes 47-b (issue 27; stop 53's leftover of fixes 45-c, round 44 PART b c08): the errors
said "python -m paper_figures: error:" / "python -m paper_figures.figN_...: error:"
(argparse's form for the same parser) while the notes and warnings said
"paper_figures: note:". Reference: argparse's ``prog`` of each command line, the
program typed.
"""

from __future__ import annotations

import sys

from paper_figures import program, run_as
from paper_figures._common import write_figure

STANDALONE = "python -m paper_figures.fig6_compression"


def test_standalone_staging_note_names_the_program_typed(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    old = out / ".out.partial-q8w_e7rt"  # no pid recorded: named, not removed
    old.mkdir()

    def draw(stage):
        (stage / "fig.png").write_bytes(b"png")
        return "section"

    assert write_figure(out, ["fig.png"], False, draw, STANDALONE) == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith(f"{STANDALONE}: note: 1 staging item(s) "), err
    assert old.is_dir() and (out / "fig.png").read_bytes() == b"png"


def test_main_notes_and_warnings_share_the_error_prefix(monkeypatch, tmp_path, capsys):
    from paper_figures import __main__ as pf

    def run(args):  # a note of the run, then Ctrl-C while the figures are made
        pf.tell("note", "a note")
        raise KeyboardInterrupt

    monkeypatch.setattr(pf, "_run", run)
    monkeypatch.setattr(sys, "argv", ["/usr/local/bin/paper-figures"])
    out = tmp_path / "o"
    assert pf.main(["--out", str(out)]) == 130
    assert capsys.readouterr().err == ("paper-figures: note: a note\n"
                                       f"paper-figures: interrupted; '{out}' is as it was\n")
    assert pf._prog() == "paper-figures" == program()
    with run_as(STANDALONE):
        assert program() == STANDALONE
    monkeypatch.setattr(sys, "argv", ["-m"])
    assert program() == "python -m paper_figures"
