"""Figures 2-4: the shared closed-loop runs, the figures and the report's numbers.

References: the report's numbers are recomputed here from the ``SimulationResult`` of
each run (``exp(-residual_variance)`` maximised over the field for the SR peak,
``scipy.signal.welch`` and a trapezoid integral for the band powers,
``SimulationResult.corrected_fov_diameter`` for d), not read back from the report;
the paper's column is checked against its constants; the oracle bound (a loop told the
true future POL does not do worse than the same loop without prediction beyond the
frame-to-frame scatter of their difference).
Small configuration (``small()`` of tests/closedloop/conftest.py): 32 px, 3x3 field, 35 + 20
modes, 0.2 s (ARMA with AIC orders needs up to 160 training frames after 15 ms).
"""

import re

import numpy as np
import pytest
from scipy import signal

from paper_figures import closedloop_runs, fig2_sr_peak, fig3_sr_spectrum, fig4_sr_maps
from paper_figures.__main__ import main

from ..closedloop.conftest import small  # the small MCAO of the closedloop tests

NAMES = ("none", "linear", "arma", "oracle", "arma-aic")
DURATION = 0.2


PROGRESS: list[str] = []  # run_all's progress lines (round 43 PART b, R21)


@pytest.fixture(scope="module")
def results():
    PROGRESS.clear()
    res, timings = closedloop_runs.run_all(small(), DURATION, seed=3, names=NAMES,
                                           budget_every=4, log=PROGRESS.append)
    return res, timings


def test_progress_lines_give_the_report_window(results):
    """Round 43 PART b, R21: stdout gave each run's own-window SR peak (ARMA first), the
    report the no-prediction run's window (linear first). Reference: numpy's mean of each
    run's SR peak from the no-prediction run's ``averaging_start``."""
    res, _ = results
    start = res["none"].averaging_start
    for name in NAMES:
        line = next(x for x in PROGRESS if x.startswith(f"[paper_figures]   {name}: "))
        want = f"SR peak {np.mean(res[name].strehl_peak[start:]):.3f} (mean from " \
               f"{res['none'].times[start] * 1e3:.0f} ms, the no-prediction run's closure)"
        assert want in line, line


@pytest.fixture(scope="module")
def runs(results):
    res, timings = results
    return closedloop_runs.summarize(res, duration=DURATION, timings=timings)


def _row(text, quantity):
    """The ``ours`` cell of the report row whose quantity is ``quantity``."""
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) in (3, 4) and cells[0] == quantity:
            return cells[1], cells[2]
    raise AssertionError(f"no row {quantity!r} in the report")


def test_every_predictor_ran_on_one_atmosphere(results, runs):
    res, _ = results
    assert list(runs.runs) == list(NAMES)
    assert {r.seed for r in res.values()} == {3}
    assert runs.budget and runs.budget["temporal"].shape == (9,)
    # the oracle is the upper bound of the loop
    # the oracle is not worse than no prediction beyond the scatter of their difference
    # (with a gain-0.5 integrator an exact forecast is not an exact correction)
    start = runs.runs["none"].closure_index
    diff = runs.runs["oracle"].strehl_peak[start:] - runs.runs["none"].strehl_peak[start:]
    assert diff.mean() >= -0.5 * diff.std()


def test_figure2_numbers_come_from_the_runs(results, runs, tmp_path):
    res, _ = results
    text = fig2_sr_peak.make(tmp_path, runs)
    start = res["none"].closure_index  # one window for every run
    assert (tmp_path / fig2_sr_peak.FIGURE_NAME).stat().st_size > 10_000
    assert (tmp_path / fig2_sr_peak.PDF_NAME).stat().st_size > 1_000
    for name in NAMES:
        r = res[name]
        peak = np.exp(-r.residual_variance).max(axis=1)[start:].mean()
        quantity = ("SR peak, no prediction" if name == "none" else
                    f"SR peak, {closedloop_runs.LABELS[name]}"
                    + (" (not in the paper)" if name in ("oracle", "arma-aic") else ""))
        paper, ours = _row(text, quantity)
        assert ours == f"{peak:.3f}"
        if name == "none":
            assert paper == f"{fig2_sr_peak.PAPER_SR_NONE:g}"
    best = max(("linear", "arma"), key=lambda n: np.exp(-res[n].residual_variance)
               .max(axis=1)[start:].mean())
    assert _row(text, "best of linear / ARMA / NN") == ("ARMA", closedloop_runs.LABELS[best])
    # the explanation quotes the run's own budget
    b = res["none"].budget
    k = int(np.argmax(res["none"].strehl_map().ravel()))
    assert f"temporal {b.temporal[k]:.3f}" in text
    assert f"fitting {b.fitting[k]:.3f}" in text


def test_figure3_band_powers_come_from_the_runs(results, runs, tmp_path):
    res, _ = results
    text = fig3_sr_spectrum.make(tmp_path, runs)
    assert (tmp_path / fig3_sr_spectrum.FIGURE_NAME).stat().st_size > 10_000
    assert (tmp_path / fig3_sr_spectrum.PDF_NAME).is_file()

    def power(r, low, high):
        x = np.exp(-r.residual_variance).max(axis=1)[r.closure_index:]
        f, p = signal.welch(x - x.mean(), fs=1e3, nperseg=min(x.size, 256))
        sel = (f >= low) & (f <= (f[-1] if high is None else high))
        return np.trapezoid(p[sel], f[sel])

    for name in NAMES[1:]:
        label = closedloop_runs.LABELS[name]
        for quantity, low, high in ((f"SR oscillation power at ~50 Hz / none, {label}", 40, 60),
                                    (f"SR oscillation power > 70 Hz / none, {label}", 70, None)):
            _, ours = _row(text, quantity)
            ratio = power(res[name], low, high) / power(res["none"], low, high)
            assert ours.split()[0] == f"{ratio:.2f}"


def test_figure4_diameters_come_from_the_runs(results, runs, tmp_path):
    res, _ = results
    text = fig4_sr_maps.make(tmp_path, runs)
    assert (tmp_path / fig4_sr_maps.FIGURE_NAME).stat().st_size > 10_000
    assert (tmp_path / fig4_sr_maps.PDF_NAME).is_file()
    for name in NAMES:
        paper, ours = _row(text, "corrected-FoV diameter (SR > 0.3), "
                           + closedloop_runs.LABELS[name])
        assert ours == f"{res[name].corrected_fov_diameter(0.3):.2f}'"
        expected = fig4_sr_maps.PAPER_DIAMETER.get(name)
        assert paper == ("-" if expected is None else f"{expected:g}'")
    # the time-averaged map is the mean of exp(-variance) after closure
    r = res["arma"]
    np.testing.assert_allclose(runs.runs["arma"].strehl_map.ravel(),
                               np.exp(-r.residual_variance[r.closure_index:]).mean(axis=0))
    assert re.search(r"one cell = 30\.0\"", text)


def test_main_rejects_bad_only(tmp_path, capsys):
    assert main(["--out", str(tmp_path), "--only", "2,9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--only" in err
    assert not (tmp_path / "report.md").exists()


def test_main_refuses_existing_figure3_pdf(tmp_path, capsys):
    (tmp_path / "fig3_sr_spectrum.pdf").write_text("mine")
    assert main(["--out", str(tmp_path), "--only", "3"]) == 2
    assert "--overwrite" in capsys.readouterr().err
    assert (tmp_path / "fig3_sr_spectrum.pdf").read_text() == "mine"


@pytest.mark.slow
def test_quick_main_makes_figures_2_to_4(tmp_path):
    assert main(["--out", str(tmp_path), "--only", "2,3,4", "--quick"]) == 0
    report = (tmp_path / "report.md").read_text()
    for label in ("Figure 2", "Figure 3", "Figure 4"):
        assert f"## {label}" in report
    assert "not yet regenerated" not in report
    for stem in ("fig2_sr_peak", "fig3_sr_spectrum", "fig4_sr_maps"):
        assert (tmp_path / f"{stem}.png").stat().st_size > 10_000
        assert (tmp_path / f"{stem}.pdf").is_file()
