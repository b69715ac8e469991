"""``python -m paper_figures --quick``: every figure, both logs, and the comparison table.

References: the paper's headline numbers (Stangalini et al.: modes to reach 0.4 waves^2
20 / 15 / 7; ARMA(2,3); forecasts accurate for 2-3 ms; SR 0.4 -> > 0.6 with ARMA best;
SR oscillations damped at ~50 Hz and above 70 Hz; corrected-FoV diameters 0.9' / 1.25' /
1.5' / 1.6'), each of which must have a row; and the run's own files: the Figure 5 rows
are recomputed from the evaluation the run wrote (``fig5_forecast*.json``), the Figure 1
counts from the shipped logs with ``modalinfo.ordering`` in the test, so the numbers are
shown to come from the run and not from typed text.
"""

import json
import re
from pathlib import Path

import numpy as np
import pytest

from paper_figures import FIGURES
from paper_figures.__main__ import main

STEMS = ("fig1_fitting_error", "fig2_sr_peak", "fig3_sr_spectrum", "fig4_sr_maps",
         "fig5_forecast", "fig6_compression")


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    path = tmp_path_factory.mktemp("quick")
    assert main(["--out", str(path), "--quick"]) == 0
    return path


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
