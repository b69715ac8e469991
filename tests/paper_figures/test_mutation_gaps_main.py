"""``python -m paper_figures --help``: the options the report's help did not pin yet.

Gap found by mutation testing (docs/MUTATION.md, "paper_figures/__main__.py": the help
texts of ``--overwrite``, ``--quick`` and ``--duration`` were free to change). Reference:
the module docstring's contract for each option (``--overwrite`` replaces files already
there; ``--quick`` is a smoke run on reduced settings, numbers not the paper's: Figures
2-4, 6 and 8 on reduced closed-loop settings, Figure 5 on its first 5 modes;
``--duration`` is the simulated time of the Figures 2-4 runs in seconds, 0.5 s by
default and 0.2 s with ``--quick``) and the default ``closedloop_runs.DEFAULT_DURATION``
/ ``QUICK_DURATION``, written out here word for word. No figure is made: < 1 s.
"""

from __future__ import annotations

import pytest

from paper_figures import closedloop_runs
from paper_figures.__main__ import main


def test_help_of_overwrite_quick_and_duration(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "400")  # one line per option: no hyphen split by wrapping
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert (closedloop_runs.DEFAULT_DURATION, closedloop_runs.QUICK_DURATION) == (0.5, 0.2)
    for option in (
            "--overwrite replace figures and report already in the output directory",
            "--quick a smoke run, numbers not the paper's: reduced closed-loop settings for "
            "Figures 2-4, 6 and 8, Figure 5's evaluation on the first 5 modes",
            "--duration DURATION simulated time of the Figures 2-4 runs [s] (default 0.5, "
            "quick 0.2)"):
        assert option in text
