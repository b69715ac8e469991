"""``python -m paper_figures --quick``: every figure, both logs, and the comparison table.

References: the paper's headline numbers (Stangalini et al.: modes to reach 0.4 waves^2
20 / 15 / 7; ARMA(2,3); forecasts accurate for 2-3 ms; SR 0.4 -> > 0.6 with ARMA best;
SR oscillations damped at ~50 Hz and above 70 Hz; corrected-FoV diameters 0.9' / 1.25' /
1.5' / 1.6'), each of which must have a row; and the run's own files: the Figure 5 rows
are recomputed from the evaluation the run wrote (``fig5_forecast*.json``), the Figure 1
counts from the shipped logs with ``modalinfo.ordering`` in the test, so the numbers are
shown to come from the run and not from typed text. Every cell of Figure 5's predictor
tables (both logs, the paper's NN among the rows) and the gains its text quotes are
recomputed from those JSON files; the logs comparison's lines on Figures 1 and 5 from the
JSON files and from the comparison rows; the Figure 1 comparison rows from the section's
panel (a) table, column by column. ``--quick`` is a smoke run: Figure 5 evaluates the
first ``QUICK_MODES`` modes of each log, whose labels the test reads from the shipped
logs (the full ``compute`` against its quick one: ``tests/forecast/test_fig5.py``).
"""

import json
import re
from pathlib import Path

import numpy as np
import pytest

from paper_figures import FIGURES

STEMS = ("fig1_fitting_error", "fig2_sr_peak", "fig3_sr_spectrum", "fig4_sr_maps",
         "fig5_forecast", "fig6_compression")


@pytest.fixture(scope="module")
def out(quick_run):
    # the session's one quick run (tests/paper_figures/conftest.py)
    return quick_run.out


@pytest.fixture(scope="module")
def table(out):
    """Rows of the comparison table: list of (figure, quantity, paper, ours, why)."""
    text = (out / "report.md").read_text()
    rows = []
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and cells[0].startswith("Figure"):
            rows.append(tuple(cells))
    return rows


def test_every_figure_file_and_the_report(out):
    for stem in STEMS:
        assert (out / f"{stem}.png").stat().st_size > 10_000
        assert (out / f"{stem}.pdf").stat().st_size > 1_000
    for stem in ("fig1_fitting_error", "fig5_forecast"):  # the simulated log too
        assert (out / f"{stem}_closedloop.png").stat().st_size > 10_000
    report = (out / "report.md").read_text()
    for _, label, _ in FIGURES:
        assert f"## {label}" in report
    assert "## The spectral and the simulated KAOS-like logs" in report
    html = (out / "report.html").read_text()
    assert html.count("data:image/png;base64,") >= len(STEMS) + 2


def _find(table, figure_prefix, quantity_part):
    found = [r for r in table if r[0].startswith(figure_prefix) and quantity_part in r[1]]
    assert found, f"no row {figure_prefix!r} / {quantity_part!r}"
    return found


def test_a_row_for_every_paper_number(table):
    for part, paper in (("Zernike, standard order", "20"), ("K-L (theory), MI order", "15"),
                        ("Zernike, MI order", "7")):
        rows = _find(table, "Figure 1", f"modes to reach 0.4 waves^2, {part}")
        assert len(rows) == 2 and all(r[2] == paper for r in rows)  # both shipped logs
    assert _find(table, "Figure 5", "best ARMA order")[0][2] == "(2,3)"
    assert _find(table, "Figure 5", "forecast horizon")[0][2] == "2-3 ms"
    assert _find(table, "Figure 2", "SR peak, no prediction")[0][2] == "0.4"
    assert all(r[2] == "> 0.6" for r in _find(table, "Figure 2", "SR peak, ARMA(2,3)"))
    assert _find(table, "Figure 2", "best of linear / ARMA / NN")[0][2] == "ARMA"
    assert _find(table, "Figure 3", "~50 Hz / none, ARMA(2,3)")[0][2] == "damped"
    assert _find(table, "Figure 3", "> 70 Hz / none, ARMA(2,3)")[0][2] == "reduced"
    for label, d in (("no prediction", "0.9'"), ("linear (a=2, b=-1)", "1.25'"),
                     ("NN (paper, 10 patterns)", "1.5'"), ("ARMA(2,3)", "1.6'")):
        assert _find(table, "Figure 4", f"diameter (SR > 0.3), {label}")[0][2] == d
    assert len(_find(table, "Figure 6", "")) >= 2
    # every row explains itself
    assert all(len(r[4]) > 10 for r in table)


def test_figure5_rows_come_from_the_run(out, table):
    for suffix, tag in (("", "spectral"), ("_closedloop", "simulated")):
        ev = json.loads((out / f"fig5_forecast{suffix}.json").read_text())
        i = ev["names"].index("ARMA(2,3)")
        gain = np.asarray(ev["gain_wavefront"])[i, 0]
        row = [r for r in _find(table, "Figure 5", "best ARMA order") if tag in r[0]][0]
        assert f"ARMA(2,3) gains x{gain:.2f}" in row[4]
        good = np.asarray(ev["gain_wavefront"])[i] > 1.0
        n = int(np.argmin(good)) if not good.all() else good.size
        h = ev["horizons"][n - 1] if n else 0
        row = [r for r in _find(table, "Figure 5", "forecast horizon") if tag in r[0]][0]
        assert f"ARMA(2,3): {'>= ' if n == good.size else ''}{h / 2:g} ms ({h} frames)" \
            in row[3]


def test_figure1_totals_come_from_the_logs(table):
    # the typical frame is the frame of median total variance; its total in waves^2
    from modalinfo.io import load

    data = Path(__file__).resolve().parents[2] / "data"
    for name, tag in (("kaos_like_closed_loop.npz", "spectral"),
                      ("kaos_closedloop.npz", "simulated")):
        log = load(data / name).to_units("waves")
        total = np.sum(np.asarray(log.coeffs) ** 2, axis=1)
        typical = float(np.sort(total)[total.size // 2])
        row = [r for r in _find(table, "Figure 1", "Zernike, standard order") if tag in r[0]][0]
        quoted = float(re.search(r"totals ([0-9.e-]+) waves\^2", row[4]).group(1))
        # the fitting-error curve integrates over the sampled pupil: equal to the
        # Parseval sum of the unit-RMS coefficients to the pupil's sampling error
        assert quoted == pytest.approx(typical, rel=0.1)


def _sections(out):
    """Report sections by heading line (the text up to the next ``## `` heading)."""
    text = (out / "report.md").read_text()
    parts = re.split(r"^(## .*)$", text, flags=re.M)
    return {parts[i]: parts[i + 1] for i in range(1, len(parts) - 1, 2)}


def _section(out, start, tag):
    found = [body for head, body in _sections(out).items()
             if head.startswith(start) and tag in head]
    assert len(found) == 1, (start, tag)
    return found[0]


def _evaluations(out):
    """The run's own Figure 5 evaluations: log tag -> JSON dict."""
    return {tag: json.loads((out / f"fig5_forecast{suffix}.json").read_text())
            for suffix, tag in (("", "spectral"), ("_closedloop", "simulated"))}


def _gain(ev, name, horizon=1):
    j = ev["horizons"].index(horizon)
    return float(np.asarray(ev["gain_wavefront"])[ev["names"].index(name), j])


def test_figure5_predictor_tables_and_gains_come_from_the_run(out):
    # every cell of each log's table (RMSE and gain of every predictor at every shown
    # horizon), and the gains the text quotes -- the paper's NN among them -- from the
    # evaluation the run wrote
    from paper_figures.fig5_forecast import REPORT_HORIZONS

    for tag, ev in _evaluations(out).items():
        body = _section(out, "## Figure 5", tag)
        rmse, gain = np.asarray(ev["rmse_wavefront"]), np.asarray(ev["gain_wavefront"])
        header = "| predictor | " + " | ".join(f"h={h}" for h in REPORT_HORIZONS) + " |"
        assert header in body
        for i, name in enumerate(ev["names"]):
            cells = [f"{rmse[i, ev['horizons'].index(h)]:.4f} "
                     f"(x{gain[i, ev['horizons'].index(h)]:.2f})" for h in REPORT_HORIZONS]
            assert f"| {name} | {' | '.join(cells)} |" in body, (tag, name)
        flat = " ".join(body.split())
        assert (f"paper's configuration (10 patterns for 121 weights) gains "
                f"x{_gain(ev, 'NN paper (10 patterns)'):.2f} on the wavefront") in flat
        assert (f"(2000 patterns) gains x{_gain(ev, 'NN 10-10-1, 2000 patterns'):.2f}"
                in flat)
        assert f"ARMA(2,3), as in the paper, gains x{_gain(ev, 'ARMA(2,3)'):.2f}" in flat
        assert f"gives x{_gain(ev, 'ARMA (AIC)'):.2f}" in flat
        assert (f"gain x{_gain(ev, 'multivariate VAR(4)'):.2f} (batch VAR(4)" in flat
                and f"x{_gain(ev, 'multivariate RLS'):.2f} (RLS" in flat)
        best = ev["names"][int(np.argmax(gain[:, 0]))]
        assert f"Best at h = 1: **{best}**" in flat


def test_logs_compared_section_quotes_figures_1_and_5_of_each_log(out, table):
    body = " ".join(_section(out, "## The spectral and the simulated", "").split())
    evs = _evaluations(out)
    a, b = evs["spectral"], evs["simulated"]

    def best(ev):
        return ev["names"][int(np.argmax(np.asarray(ev["gain_wavefront"])[:, 0]))]

    assert (f"ARMA(2,3) x{_gain(a, 'ARMA(2,3)'):.2f} (spectral) vs "
            f"x{_gain(b, 'ARMA(2,3)'):.2f} (simulated); best predictor {best(a)} vs "
            f"{best(b)}") in body
    # Figure 1: the calibrated-target counts of each log's comparison rows, in the
    # order standard Zernike / MI K-L / MI Zernike
    counts = {}
    for tag in ("spectral", "simulated"):
        counts[tag] = []
        for part in ("Zernike, standard order", "K-L (theory), MI order", "Zernike, MI order"):
            row = [r for r in _find(table, "Figure 1", part) if tag in r[0]][0]
            counts[tag].append(re.search(r"\((\d+) at the calibrated target\)", row[3]).group(1))
    assert (f"spectral {' / '.join(counts['spectral'])}, simulated "
            f"{' / '.join(counts['simulated'])}.") in body


def test_figure1_comparison_rows_are_the_typical_frame_panel(out, table):
    # the comparison table's "n at 0.4 (m at the calibrated target)" of each log are the
    # two count columns of the section's panel (a), in that order
    for tag in ("spectral", "simulated"):
        body = _section(out, "## Figure 1", tag)
        panel = body.split("**(a) typical frame")[1].split("**(b)")[0]
        for part in ("Zernike, standard order", "K-L (theory), MI order", "Zernike, MI order"):
            line = [ln for ln in panel.splitlines() if ln.startswith(f"| {part} |")]
            assert len(line) == 1, (tag, part)
            _, paper, at_04, at_cal = [c.strip() for c in line[0].strip().strip("|").split("|")]
            row = [r for r in _find(table, "Figure 1", part) if tag in r[0]][0]
            assert (row[2], row[3]) == (paper, f"{at_04} ({at_cal} at the calibrated target)")


def test_figure5_quick_evaluates_the_first_modes_of_each_log(out):
    # the smoke run's evaluation: the first QUICK_MODES modes of each shipped log, as the
    # report says (labels read from the logs here)
    from modalinfo.io import load
    from paper_figures.fig5_forecast import QUICK_MODES, QUICK_PAPER_SEEDS

    data = Path(__file__).resolve().parents[2] / "data"
    evs = _evaluations(out)
    for name, tag in (("kaos_like_closed_loop.npz", "spectral"),
                      ("kaos_closedloop.npz", "simulated")):
        labels = list(load(data / name).labels)
        assert evs[tag]["labels"] == labels[:QUICK_MODES]
        flat = " ".join(_section(out, "## Figure 5", tag).split())
        assert (f"the evaluation and the AIC orders on the first {QUICK_MODES} of the "
                f"{len(labels)} modes, the paper's NN over {len(QUICK_PAPER_SEEDS)} "
                f"seeds.") in flat
