"""``python -m paper_figures --quick`` with only figures that have no quick setting is refused.

Round 49 PART b, P28: ``--only 1 --quick`` was accepted; Figure 1 has no quick setting
(``fig1_fitting_error.compute`` takes no ``quick``: the module's documented rule, "--quick
reaches the log figures that have a quick setting (Figure 5)"), so the run made Figure 1 on
the paper's settings while the report said "with `--quick` (a smoke run on reduced
settings: numbers not the paper's)". Reference: the module docstring's list of what
``--quick`` reduces (Figures 2-4, 5's first 5 modes, 6, 7, 8) and the refusals of the
other options no chosen figure reads (``--duration``, ``--seed``).
"""

from __future__ import annotations

import numpy as np

from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog
from paper_figures.__main__ import main


def _short_log(path, n_modes):
    x = np.random.default_rng(0).normal(size=(300, n_modes)) * 0.1
    save(ModalLog(x, modes=list(range(2, 2 + n_modes)), units="rad", rate=1000.0), path)
    return str(path)


def test_quick_with_figure_1_alone_is_refused(tmp_path, capsys):
    # a 3-mode log: without the rule the run goes on to Figure 1's own refusal (21 modes)
    log = _short_log(tmp_path / "three.npz", 3)
    assert main(["--only", "1", "--quick", "--log", log, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "--quick" in err and "--only 1 has no quick setting" in err, err
    assert not (tmp_path / "o").exists()


def test_quick_with_figure_5_is_not_refused_by_the_rule(tmp_path, capsys):
    # Figure 5 has a quick setting: the refusal is Figure 5's own (too few frames)
    log = _short_log(tmp_path / "three.npz", 3)
    assert main(["--only", "1,5", "--quick", "--log", log, "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "no quick setting" not in err, err
