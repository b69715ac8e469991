"""The theoretical K-L's assumed outer scale is said by batch and paper_figures too.

Issue 27, left24-status item 3. Round 24 PART b (F31-F35) made ``reorder --basis
kl-theory`` and ``fitting-error`` say on stderr that a log without metadata gets an
infinite outer scale (Kolmogorov) and a 1 m pupil; ``batch``'s ``ordering`` and
``fitting_error`` analyses and ``paper_figures --log`` (Figure 1 orders ``kl-theory``)
made the same assumption without a word. References, outside the code: Kolmogorov vs
von Karman turbulence (Conan 2000: the K-L depends on the outer scale, which a bare
array saved with numpy does not carry), and the CLI's own note of round 24 PART b (the
one text every route must print, tests/cli/test_cli_round24.py); a log that records
its outer scale and diameter gets no note. Fast: the batch task run in this process
(as a worker runs it), no cluster; paper_figures with its figures stubbed.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.cli.cmd_batch import kl_assumption_note
from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog
from paper_figures.__main__ import main as figures_main

from ..paper_figures.test_main_report_text import figs  # noqa: F401 - a fixture

KOLMOGOROV = ("no outer scale: the theoretical K-L assumes Kolmogorov turbulence "
              "(infinite outer scale)")


def _log(path, **metadata):
    coeffs = np.random.default_rng(24).standard_normal((600, 5)) * 0.01
    save(ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4, 5, 6], units="rad", wavelength=5e-7,
                  metadata=metadata), path)
    return path


def _row(path, analysis, **params):
    return run_log_task({"path": str(path), "fmt": None, "hints": {}, "analysis": analysis,
                         "params": resolve_params(analysis, params)})


@pytest.mark.parametrize("analysis, params", [
    ("fitting_error", {"orderings": "zernike:standard,kl-theory:variance"}),
    ("ordering", {"basis": "kl-theory", "method": "variance", "windows": 0}),
])
def test_a_batch_row_says_the_assumed_outer_scale(tmp_path, analysis, params):
    bare = _log(tmp_path / "bare.npz")
    row = _row(bare, analysis, **params)
    assert row["kl_assumed"] == KOLMOGOROV
    # a log that records its geometry: nothing assumed, no column
    rec = _log(tmp_path / "rec.npz", outer_scale=20.0, diameter=0.7)
    assert "kl_assumed" not in _row(rec, analysis, **params)


def test_no_theoretical_kl_no_column(tmp_path):
    bare = _log(tmp_path / "bare.npz")
    assert "kl_assumed" not in _row(bare, "fitting_error", orderings="zernike:standard")


def test_batch_says_it_once_per_assumption(tmp_path, capsys):
    bare = _log(tmp_path / "bare.npz")
    rows = [dict(_row(bare, a, **p), path=str(bare), status="ok") for a, p in [
        ("fitting_error", {"orderings": "kl-theory:variance"}),
        ("ordering", {"basis": "kl-theory", "method": "variance", "windows": 0})]]
    rows.append({"path": "other.npz", "status": "ok", "kl_assumed": float("nan")})
    kl_assumption_note(rows)
    assert capsys.readouterr().err == (f"modalinfo batch: note: 1 log(s) record {KOLMOGOROV}; "
                                       f"column kl_assumed: {bare}\n")


def test_paper_figures_log_says_it_for_figure_1(figs, tmp_path, capsys):  # noqa: F811
    figs.mods["fig1_fitting_error"].SPECS = [("zernike", "standard"), ("kl-theory", "mi_greedy")]
    bare = _log(tmp_path / "bare.npz")
    assert figures_main(["--only", "1", "--log", str(bare), "--out", str(tmp_path / "o")]) == 0
    assert capsys.readouterr().err == (f"python -m paper_figures: note: 'bare.npz' records "
                                       f"{KOLMOGOROV}: Figure 1\n")
    rec = _log(tmp_path / "rec.npz", outer_scale=20.0, diameter=0.7)
    assert figures_main(["--only", "1", "--log", str(rec), "--out", str(tmp_path / "p")]) == 0
    assert capsys.readouterr().err == ""
