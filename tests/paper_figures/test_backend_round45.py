"""A figure's ``plot()`` leaves the caller's matplotlib backend alone (round 45 PART a, G15).

Reference: ``matplotlib.get_backend()`` before and after, and pyplot's own figure list
(``plt.get_fignums()``). Every ``paper_figures`` ``plot()`` called
``matplotlib.use("Agg")``: a caller on the ``pdf`` backend (or a notebook's) was left on
Agg for the session, the bug audit 10-state fixed in ``modalinfo.batch.report``. The
figures are drawn on ``matplotlib.figure.Figure`` objects of their own; the PNG and PDF
are still written (read back: the PNG and PDF magic bytes).
"""

from __future__ import annotations

import inspect

import matplotlib
import matplotlib.pyplot as plt
import pytest

from paper_figures import (
    fig1_fitting_error,
    fig2_sr_peak,
    fig3_sr_spectrum,
    fig4_sr_maps,
    fig5_forecast,
    fig6_compression,
    fig7_solar,
    fig_information_flow,
)

from .test_mutation_gaps_fig2_sr_peak import _runs

MODULES = (fig1_fitting_error, fig2_sr_peak, fig3_sr_spectrum, fig4_sr_maps, fig5_forecast,
           fig6_compression, fig7_solar, fig_information_flow)


@pytest.mark.parametrize("module", [fig2_sr_peak, fig3_sr_spectrum, fig4_sr_maps])
def test_plot_keeps_the_callers_backend(module, tmp_path, pdf_backend):
    figures = plt.get_fignums()
    paths = module.plot(module.compute(_runs(quick=True)), tmp_path)
    assert matplotlib.get_backend() == "pdf"
    assert plt.get_fignums() == figures  # no pyplot figure made or left
    png = [p for p in paths if p.suffix == ".png"]
    pdf = [p for p in paths if p.suffix == ".pdf"]
    assert len(png) == len(pdf) == 1
    assert png[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert pdf[0].read_bytes()[:5] == b"%PDF-"


@pytest.mark.parametrize("module", MODULES, ids=lambda m: m.__name__.rpartition(".")[2])
def test_no_plot_sets_the_backend(module):
    # the 5 other figures need closed-loop runs or a forecast evaluation to draw; their
    # plot() source shows the same (no matplotlib.use, no pyplot)
    source = inspect.getsource(module.plot)
    assert "matplotlib.use" not in source and "pyplot" not in source
