"""Figure 6: the report's and table's numbers are the study's; the plot; the crossing.

References: the :class:`closedloop.studies.compression.CompressionStudy` the figure is built
from (the report's cells are recomputed from it here), and a power law for
``Figure6.crossing`` (log-log interpolation is exact on a power law).
"""

import numpy as np
import pytest

from closedloop import LoopModel, presets
from closedloop.studies.compression import compression_study
from paper_figures import fig6_compression as fig6


@pytest.fixture(scope="module")
def figure():
    cfg = presets.get("kaos")
    study = compression_study(cfg, n_values=[4, 10, 27], duration=0.1, model=LoopModel(cfg),
                              orderings=("zernike", "kl", "kl-mi", "pca"),
                              predictor="linear-ls")
    n = np.array([27, 54, 108])
    scaling = {"none": 1e-6 * n, "linear-ls": 1e-8 * n ** 2.0, "multivariate": 5e-8 * n ** 2}
    screen = {"none": 0.5, "oracle": 0.52, "linear-ls": 0.51}
    return fig6.Figure6(study=study, screen=screen, scaling_n=n, scaling_time=scaling,
                        slow_rtc=None, quick=True, elapsed=1.0)


def test_report_cells_are_the_study(figure):
    s = figure.study
    text = fig6.report(figure)
    for o in s.orderings:
        none = s.strehl_peak[(False, o, "none")]
        pred = s.strehl_peak[(False, o, "linear-ls")]
        cells = " | ".join(f"{a:.3f} / {b:.3f}" for a, b in zip(none, pred, strict=True))
        assert cells in text


def test_table_rows_are_the_study(figure):
    s = figure.study
    rows = fig6.table_rows(figure)
    syn = fig6.synergy(figure, 10)
    i = 1  # n = 10
    assert syn["baseline"] == s.strehl_peak[(False, "zernike", "none")][i]
    assert syn["prediction"] == s.strehl_peak[(False, "zernike", "linear-ls")][i]
    assert syn["mi"] == max(s.strehl_peak[(False, "kl-mi", "none")][i], -1)
    assert rows[0][0].endswith("n = 10 modes (SR peak)")
    assert f"{syn['both']:.3f}" in rows[0][2] and f"{syn['baseline']:.3f}" in rows[0][2]
    n_opt, sr_opt = s.optimum(max(s.orderings, key=lambda o: s.optimum(
        o, "linear-ls", latency=True)[1]), "linear-ls", latency=True)
    assert f"n = {n_opt}" in rows[1][2] and f"{sr_opt:.3f}" in rows[1][2]
    # t = 5e-8 n^2 reaches a 0.5 ms frame at n = 100
    assert "at about 100 modes" in rows[1][3]


def test_report_names_the_screen(figure):
    text = fig6.report(figure)
    assert "linear-ls 0.5100" in text and "oracle 0.5200" in text


def test_crossing_on_a_power_law(figure):
    # t = 1e-8 n^2: reaches 25 us at n = 50 exactly
    assert figure.crossing("linear-ls", 25e-6) == pytest.approx(50.0)
    assert figure.crossing("none", 1.0) is None
    assert figure.crossing("none", 1e-9) == 27.0


def test_plot_writes_png_and_pdf(figure, tmp_path):
    paths = fig6.plot(figure, tmp_path)
    assert [p.name for p in paths] == [fig6.FIGURE_NAME, fig6.PDF_NAME]
    assert all(p.stat().st_size > 5_000 for p in paths)


def test_main_refuses_to_overwrite(tmp_path, capsys):
    (tmp_path / fig6.PDF_NAME).write_text("mine")
    assert fig6.main(["--out", str(tmp_path)]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert (tmp_path / fig6.PDF_NAME).read_text() == "mine"


def test_extrapolated_crossing_follows_the_power_law(figure):
    # beyond the measured sizes: the last two points' law, t = 5e-8 n^2 (2 ms at 200)
    assert figure.extrapolated_crossing("multivariate", 2e-3) == pytest.approx(200.0)
    assert figure.extrapolated_crossing("multivariate", 5e-4) == pytest.approx(100.0)


def test_slow_rtc_section_quotes_its_study(figure, tmp_path):
    import dataclasses

    s = figure.study
    with_slow = dataclasses.replace(figure, slow_rtc=s)
    text = fig6.report(with_slow)
    o = s.orderings[0]
    i = len(s.n_values) - 1
    assert (f"n={s.n_values[i]} {s.strehl_peak[(False, o, 'linear-ls')][i]:.3f} -> "
            f"{s.strehl_peak[(True, o, 'linear-ls')][i]:.3f}") in text
    assert fig6.plot(with_slow, tmp_path)[0].stat().st_size > 5_000
