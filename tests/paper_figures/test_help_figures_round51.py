"""``--help`` names every figure ``--duration`` and ``--quick`` change (round 51 PART b, O08).

``--help`` said ``--duration`` is the "simulated time of the Figures 2-4 runs" and
``--quick`` reduces "Figures 2-4, 6 and 8"; Figure 7 (``fig7_solar``, ``NEEDS_RUNS``) runs
``table1-solar`` with the table1 runs' duration and quick settings (its ``compute`` reads
``runs.duration`` and ``runs.quick``), and the refusal of ``--only 1 --duration`` says
"Figures 2, 3, 4, 7". Reference: each figure module's own flags, read here (``NEEDS_RUNS``
for the closed-loop runs; a ``quick`` parameter of ``compute`` or the runs for ``--quick``),
not the help's text.
"""

from __future__ import annotations

import importlib
import inspect
import re

import pytest

from paper_figures import FIGURES
from paper_figures.__main__ import main


def _numbers(words: str) -> set[int]:
    """'Figures 2-4, 6, 7 and 8' -> {2, 3, 4, 6, 7, 8}."""
    out: set[int] = set()
    for a, b in re.findall(r"(\d+)(?:-(\d+))?", words):
        out.update(range(int(a), int(b or a) + 1))
    return out


def _help(capsys, monkeypatch) -> str:
    monkeypatch.setenv("COLUMNS", "400")
    with pytest.raises(SystemExit):
        main(["--help"])
    return " ".join(capsys.readouterr().out.split())


def test_duration_and_quick_help_name_the_figures_they_change(capsys, monkeypatch):
    runs, quick = set(), set()
    for name, label, _ in FIGURES:
        module = importlib.import_module(f"paper_figures.{name}")
        number = int(label.split()[-1])
        if getattr(module, "NEEDS_RUNS", False):
            runs.add(number)
            quick.add(number)
        elif "quick" in inspect.signature(module.compute).parameters:
            quick.add(number)
    assert runs == {2, 3, 4, 7}  # the modules' own flags, as the refusal names them
    text = _help(capsys, monkeypatch)
    duration = re.search(r"--duration DURATION simulated time of the closed-loop runs of "
                         r"(Figures [\d\-, and]+) \[s\]", text)
    assert duration is not None, text
    assert _numbers(duration.group(1)) == runs
    reduced = re.search(r"reduced closed-loop settings for (Figures [\d\-, and]+), Figure 5's",
                        text)
    assert reduced is not None, text
    assert _numbers(reduced.group(1)) | {5} == quick
