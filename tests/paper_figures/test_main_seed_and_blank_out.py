"""``python -m paper_figures``: ``--seed`` reaches every simulated figure, and an --out name
of blanks is refused like an empty one.

References (outside the code): the documented rules of ``python -m paper_figures``:
``--seed`` "sets the simulated figures (2, 3, 4, 6, 7, 8)" (Figure 6 simulates the
compression runs, Figure 8 its own series: they read the seed without being closed-loop
runs of ``--duration``), so with any of them chosen the seed is no refusal and the next
rule speaks (here: an ``--out`` that is an existing file, "exists and is not a
directory"); an ``--out`` that names no folder (empty, or only blanks as an unset,
quoted ``"$OUT $X"`` gives) is refused in one line, exit 2, before any other rule, and
nothing is written in the current folder.

Planted bugs R8-48 and R8-49 (docs/MUTATION.md, round 8): ``--out " "`` accepted (the
blank test ``not text`` for ``not text.strip()``: a folder named " " in the current
folder), and ``--seed`` refused with Figure 6 or 8 alone (the kinds that read it written
``{"runs"}`` for ``{"runs", "own"}``); the tests before gave ``--out ""`` and ``--seed``
with Figures 1 and 5 only.
"""
from __future__ import annotations

import pytest

from paper_figures.__main__ import main


@pytest.mark.parametrize("only", ["6", "8", "2", "1,6"])
def test_seed_with_a_simulated_figure_is_no_refusal(tmp_path, capsys, only):
    a_file = tmp_path / "results.txt"
    a_file.write_text("mine")
    assert main(["--only", only, "--seed", "3", "--out", str(a_file)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "exists and is not a directory" in err, err
    assert a_file.read_text() == "mine"


@pytest.mark.parametrize("blank", [" ", "   ", "\t"])
def test_an_out_name_of_blanks_is_refused(tmp_path, capsys, monkeypatch, blank):
    monkeypatch.chdir(tmp_path)
    # --log with Figure 3 is refused too, later: the blank name must be the one reported
    with pytest.raises(SystemExit) as exc:
        main(["--only", "3", "--log", str(tmp_path / "none.npz"), "--out", blank])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--out: must name a folder" in err, err
    assert list(tmp_path.iterdir()) == []
