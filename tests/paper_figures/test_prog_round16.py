"""Round 16 PART b (issue 27), I24: the console script's usage names the console script.

Reference from outside the code: pyproject.toml's ``[project.scripts]`` (the command a
user types is ``paper-figures``) and argparse's documented ``prog`` (the name its usage
and error lines start with).
"""

from __future__ import annotations

import sys

import pytest

from paper_figures.__main__ import main


@pytest.mark.parametrize(("argv0", "name"), [("/venv/bin/paper-figures", "paper-figures"),
                                              ("/x/paper_figures/__main__.py",
                                               "python -m paper_figures")])
def test_usage_names_the_command_typed(monkeypatch, capsys, argv0, name):
    monkeypatch.setattr(sys, "argv", [argv0, "--no-such-option"])
    with pytest.raises(SystemExit) as stop:
        main(["--no-such-option"])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith(f"{name}: error: ")
