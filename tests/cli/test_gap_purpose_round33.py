"""A gap refusal names what needs equally spaced frames, with its verb (round 33 PART b).

Reference: English agreement and the options given. ``reorder`` said "the block
bootstrap and --stability windows needs" whatever ran (a bootstrap, windows or both);
``paper_figures`` said "Figures 1 and 5 needs" with ``--only 1`` (its test is in
``tests/paper_figures/test_main_report_text.py``).
"""

import numpy as np

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def test_reorder_gap_refusal_grammar(tmp_path, capsys):
    t = np.arange(200) / 1000.0
    t[100:] += 0.05
    x = np.random.default_rng(3).standard_normal((200, 3))
    path = tmp_path / "gap.npz"
    save(ModalLog(x, timestamps=t, modes=[2, 3, 4]), path)
    base = ["reorder", str(path), "--pupil-pixels", "16", "--budget", "5000", "--quiet"]
    assert main(base + ["--resamples", "40"]) == 2
    err = capsys.readouterr().err
    assert "; the block bootstrap of the gains (--resamples) needs equally spaced" in err
    assert main(base + ["--resamples", "0", "--stability", "50"]) == 2
    assert "; the --stability windows need equally spaced" in capsys.readouterr().err
    assert main(base + ["--resamples", "40", "--stability", "50"]) == 2
    assert ("; the block bootstrap of the gains (--resamples) and the --stability windows "
            "need equally spaced") in capsys.readouterr().err
