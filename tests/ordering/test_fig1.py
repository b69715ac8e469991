"""Figure 1 script (paper_figures.fig1_fitting_error) end to end on a short log.

References: the paper's numbers (0.4 waves^2 with 20 standard Zernikes, 15 MI K-L,
7 MI Zernikes; Stangalini et al., Section 2.1) must be printed beside ours, and the
calibrated target is by definition the standard order's error at 20 modes.
"""

import re

from modalinfo.io import save
from modalinfo.telemetry.synthetic import kaos_like
from paper_figures import fig1_fitting_error as fig1


def test_make_on_a_short_log(tmp_path):
    log_path = tmp_path / "short.npz"
    save(kaos_like(n_frames=400, seed=1), log_path)
    text = fig1.make(tmp_path, log_path)
    png = tmp_path / fig1.FIGURE_NAME
    assert png.is_file() and png.stat().st_size > 10_000
    assert text.startswith("## Figure 1")
    # paper's counts beside ours; the standard order needs exactly 20 at the calibrated target
    assert "| Zernike, standard order | 20 | 0 | 20 |" in text
    assert re.search(r"\| K-L \(theory\), MI order \| 15 \| \d+ \| \d+ \|", text)
    assert re.search(r"\| Zernike, MI order \| 7 \| \d+ \| \d+ \|", text)
    assert "Stability of the MI-greedy Zernike order" in text


def test_main_refuses_to_overwrite(tmp_path, capsys):
    (tmp_path / fig1.FIGURE_NAME).write_bytes(b"x")
    assert fig1.main(["--out", str(tmp_path)]) == 2
    assert "pass --overwrite" in capsys.readouterr().err
