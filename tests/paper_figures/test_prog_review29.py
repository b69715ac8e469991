"""The figure scripts' "exists" refusals name the program as argparse does (review29).

Round 29 (stop 53's fixes 45-c, c08): planted with a fixed program name ("fig6", "fig7",
"fig"), these refusals passed every test, which ran only ``python -m paper_figures``:
P2 ``write_figure`` from ``figure_main`` without ``output_names`` (paper_figures/
_common.py:452; the documented default, while fig1 and fig5 both pass it), P3 / P5
``write_figure`` of fig6_compression / fig_information_flow, P4 fig7_solar's own check.
Reference, outside our code: argparse's own error line for the same parser (``prog`` +
": error: "), read from its stderr, and the existing file's bytes re-read (untouched).
"""

from __future__ import annotations

import importlib

import pytest

from paper_figures._common import figure_main

PROG = "python -m paper_figures.figX_review29"


def _main(argv):
    return figure_main(argv, prog=PROG, description="a test figure", figure_name="x.png",
                       make=lambda stage, log: pytest.fail("drawn despite the refusal"))


def test_existing_figure_refused_under_the_program_name_argparse_uses(tmp_path, capsys):
    with pytest.raises(SystemExit):
        _main(["--bogus"])
    argparse_prog = capsys.readouterr().err.strip().splitlines()[-1].split(": error: ")[0]
    assert argparse_prog == PROG
    (tmp_path / "x.png").write_bytes(b"kept")
    assert _main(["--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.split(": error: ")[0] == argparse_prog
    assert f"'{tmp_path / 'x.png'}' exists; pass --overwrite" in err
    assert (tmp_path / "x.png").read_bytes() == b"kept"


def _argparse_prog(main, capsys) -> str:
    with pytest.raises(SystemExit):
        main(["--bogus"])
    return capsys.readouterr().err.strip().splitlines()[-1].split(": error: ")[0]


@pytest.mark.parametrize("name", ["fig6_compression", "fig7_solar", "fig_information_flow"])
def test_script_refuses_an_existing_figure_under_its_argparse_name(tmp_path, capsys, name):
    module = importlib.import_module(f"paper_figures.{name}")
    prog = _argparse_prog(module.main, capsys)
    assert prog == f"python -m paper_figures.{name}"
    (tmp_path / module.FIGURE_NAME).write_bytes(b"kept")
    assert module.main(["--out", str(tmp_path)]) == 2  # refused before any computation
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.split(": error: ")[0] == prog
    assert f"'{tmp_path / module.FIGURE_NAME}' exists; pass --overwrite" in err
    assert (tmp_path / module.FIGURE_NAME).read_bytes() == b"kept"
