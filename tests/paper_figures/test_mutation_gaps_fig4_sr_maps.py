"""Figure 4 (time-averaged SR maps) on hand-made runs: numbers, rows, report, panels.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all
outside the module:

- the runs are written in this file: 3 x 3 SR maps of dyadic values (so every field
  mean is exact or worked out by hand), corrected-FoV diameters chosen by hand, and a
  flat no-prediction budget (fitting 0.3 + aliasing 0.1 = 0.4 rad^2, temporal 0.05
  rad^2 in every direction), so the field means the rows quote are known;
- the paper (Stangalini et al., Sect. 3.4, Fig. 4): the SR = 0.3 threshold, the
  diameters 0.9' / 1.25' / 1.5' / 1.6', the 2 x 2 layout (no prediction upper left,
  linear upper right, ARMA lower left, NN lower right); the module docstring: our third
  column (oracle, ARMA with AIC orders), isocontours every 0.1 with the 0.3 one in
  white, axes in arcsec over the science field, the grid cell = field / (n - 1);
- the figure read back from the ``Figure`` handed to ``savefig`` (panel positions,
  extents in arcsec, colour limits 0-1, contour levels, labels, the colour bar's
  wavelength in nm).
No closed loop runs: ~3 s.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib.image
import numpy as np
import pytest
from matplotlib.figure import Figure

from paper_figures import fig4_sr_maps as fig4
from paper_figures.closedloop_runs import ClosedLoopRuns, PredictorRun

MAPS = {  # SR maps [row = y, column = x]; field means in the comments
    "none": [[0.125, 0.25, 0.375], [0.5, 0.625, 0.75], [0.875, 0.5, 0.5]],      # 0.5
    "multivariate": [[0.625]],                                                  # 0.625
    "linear": [[0.375, 0.5, 0.625], [0.5, 0.5, 0.5], [0.625, 0.75, 0.625]],     # 5 / 9
    "arma": [[0.125, 0.25, 0.375], [0.5, 0.625, 0.75], [0.875, 0.5, 0.5]],      # 0.5
    "nn-paper": [[0.125] * 3, [0.25] * 3, [0.25] * 3],                          # 0.2083
    "oracle": [[0.125, 0.25, 0.375]] * 3,                                       # 0.25
    "arma-aic": [[0.25, 0.5, 0.75]] * 3,                                        # 0.5
    "nn": [[0.375]],                                                            # 0.375
}
DIAMETER = {"none": 0.9, "multivariate": 0.75, "linear": 1.0, "arma": 1.5, "nn-paper": 0.25,
            "oracle": 1.25, "arma-aic": 0.5, "nn": 0.875}
LABEL = {"none": "no prediction", "linear": "linear (a=2, b=-1)", "arma": "ARMA(2,3)",
         "nn-paper": "NN (paper, 10 patterns)", "oracle": "oracle (true future)",
         "arma-aic": "ARMA (AIC order)", "multivariate": "multivariate VAR(4)",
         "nn": "NN 10-10-1, 2000 patterns"}


def _run(name, smap=None, d=None):
    return PredictorRun(
        name=name, summary={"strehl_peak_mean": 0.0, "steps_per_second": 1.0},
        times=np.arange(1, 7) * 1e-3, strehl_peak=np.zeros(6), closure_index=2,
        spectrum_freqs=np.zeros(1), spectrum_psd=np.zeros(1),
        strehl_map=np.array(MAPS[name] if smap is None else smap, dtype=float),
        fov_diameter=DIAMETER[name] if d is None else d)


def _budget():
    dirs = np.array([(x, y) for y in (-30.0, 0.0, 30.0) for x in (-30.0, 0.0, 30.0)])
    return {"directions": dirs, "fitting": np.full(9, 0.3), "aliasing": np.full(9, 0.1),
            "temporal": np.full(9, 0.05), "noise": np.full(9, 0.01),
            "measured": np.full(9, 0.5)}


def _runs(names=tuple(MAPS), quick=False, budget=True, **over):
    runs = {n: over.get(n) or _run(n) for n in names}
    return ClosedLoopRuns(config_name="table1", seed=7, duration=0.006, field_size=60.0,
                          wavelength=500e-9, runs=runs, budget=_budget() if budget else {},
                          quick=quick)


@pytest.fixture(scope="module")
def result():
    return fig4.compute(_runs())


def test_the_paper_constants():
    assert fig4.THRESHOLD == 0.3
    assert fig4.PAPER_DIAMETER == {"none": 0.9, "linear": 1.25, "nn-paper": 1.5, "arma": 1.6}
    assert fig4.LAYOUT == {"none": (0, 0), "linear": (0, 1), "arma": (1, 0),
                           "nn-paper": (1, 1), "oracle": (0, 2), "arma-aic": (1, 2)}
    assert (fig4.FIGURE_NAME, fig4.PDF_NAME) == ("fig4_sr_maps.png", "fig4_sr_maps.pdf")
    assert fig4.NEEDS_RUNS is True


def test_compute(result):
    assert result.diameter == DIAMETER
    assert result.field_mean == pytest.approx(
        {"none": 0.5, "multivariate": 0.625, "linear": 5 / 9, "arma": 0.5,
         "nn-paper": 1.875 / 9, "oracle": 0.25, "arma-aic": 0.5, "nn": 0.375}, rel=1e-15)
    assert result.map_max == {"none": 0.875, "multivariate": 0.625, "linear": 0.75,
                              "arma": 0.875, "nn-paper": 0.25, "oracle": 0.375,
                              "arma-aic": 0.75, "nn": 0.375}
    assert all(type(v) is float for v in [*result.field_mean.values(),
                                          *result.map_max.values()])


WHY_NONE = ("off axis our residual is fitting + aliasing 0.400 rad^2 (field mean), which "
            "sets d; the paper's system and budget are not published")
WHY_PRED = "a predictor acts only on the temporal term, 0.050 rad^2 field mean here"


def test_table_rows_word_for_word(result):
    q = "corrected-FoV diameter (SR > 0.3), "
    assert fig4.table_rows(result) == [
        (q + "no prediction", "0.9'", "0.90'", WHY_NONE),
        (q + "multivariate VAR(4)", "-", "0.75'", "not in the paper"),
        (q + "linear (a=2, b=-1)", "1.25'", "1.00'", WHY_PRED),
        (q + "ARMA(2,3)", "1.6'", "1.50'", WHY_PRED),
        (q + "NN (paper, 10 patterns)", "1.5'",
         "0.25'", "the loop was lost (field-mean SR 0.208 against 0.500 without prediction)"),
        (q + "oracle (true future)", "-", "1.25'", "not in the paper"),
        (q + "ARMA (AIC order)", "-", "0.50'", "not in the paper"),
        (q + "NN 10-10-1, 2000 patterns", "-", "0.88'", "not in the paper"),
    ]


def test_loss_is_below_half_strictly():
    # linear's field mean exactly half of no prediction's (0.25 of 0.5): kept
    half = _run("linear", MAPS["oracle"])
    rows = fig4.table_rows(fig4.compute(_runs(("none", "linear"), linear=half)))
    assert rows[1][3] == WHY_PRED
    low = _run("linear", [[0.125, 0.25, 0.375]] * 2 + [[0.125, 0.25, 0.3749]])
    rows = fig4.table_rows(fig4.compute(_runs(("none", "linear"), linear=low)))
    assert rows[1][3].startswith("the loop was lost (field-mean SR 0.250 against 0.500")


def test_rows_without_a_budget():
    rows = fig4.table_rows(fig4.compute(_runs(("none", "linear"), budget=False)))
    assert rows[0][3] == ("off axis our residual is fitting + aliasing nan rad^2 (field "
                          "mean), which sets d; the paper's system and budget are not "
                          "published")
    assert rows[1][3] == "a predictor acts only on the temporal term, nan rad^2 field mean here"


def _report(n, cell, moves, means, verdict, fit="0.400", temporal="0.050"):
    return f"""## Figure 4: time-averaged SR maps and the corrected field of view

![Figure 4](fig4_sr_maps.png)

SR averaged after each run's own detected closure
(`SimulationResult.strehl_map`; the closure times are listed under Figure 2, so the
windows differ between runs) on the {n}x{n} science grid over
60" (one cell = {cell}"); the diameter d = 2 sqrt(A / pi) of the
area with SR > 0.3 is measured on the grid refined 16 times by bilinear
interpolation, so it is known to about a cell ({{cell_arcmin}}'); a region that reaches
the grid's edge is clipped (d is then a lower bound). The paper's formula
4 sqrt(A) / pi is a typo: a disc of diameter d must give d back.

{{table}}

Change of d against no prediction: {moves}. Field-mean SR: {means}.
{verdict} Off axis the residual is anisoplanatism and the upper layer beyond its
DM's sensed disc (fitting + aliasing, field mean {fit}
rad^2 without prediction) while the temporal term, all a predictor can remove, is
{temporal} rad^2 (field mean of the same budget,
Figure 2). The paper's growth from 0.9' to 1.6'
needs a temporal error that dominates off axis.
"""


def _table(rows):
    return "\n".join(["| quantity | paper | ours | why they differ |", "|---|---|---|---|"]
                     + [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows])


def test_report_word_for_word(result):
    moves = ("multivariate VAR(4) -0.15', linear (a=2, b=-1) +0.10', ARMA(2,3) +0.60', "
             "NN (paper, 10 patterns) -0.65', oracle (true future) +0.35', ARMA (AIC order) "
             "-0.40', NN 10-10-1, 2000 patterns -0.03'")
    means = ("no prediction 0.500, multivariate VAR(4) 0.625, linear (a=2, b=-1) 0.556, "
             "ARMA(2,3) 0.500, NN (paper, 10 patterns) 0.208, oracle (true future) 0.250, "
             "ARMA (AIC order) 0.500, NN 10-10-1, 2000 patterns 0.375")
    # one cell = 60" / (3 - 1) = 30" = 0.5'; ARMA's +0.60' is more than a cell
    verdict = ("Prediction enlarges d by up to +0.60' (ARMA(2,3)), from 0.90' without "
               "prediction.")
    expected = _report(3, "30.0", moves, means, verdict).format(
        cell_arcmin="0.50", table=_table(fig4.table_rows(result)))
    assert fig4.report(result) == expected


@pytest.mark.parametrize(("d_linear", "verdict"), [
    # a gain below one cell (0.5'): "at most"; exactly one cell: "enlarges"
    (0.875, "Prediction moves d by at most +0.38' (linear (a=2, b=-1)), less than a grid "
            "cell, from 0.50' without prediction."),
    (1.0, "Prediction enlarges d by up to +0.50' (linear (a=2, b=-1)), from 0.50' without "
          "prediction."),
    # 127/256' = 0.496': below one cell (0.5'), if only just
    (0.5 + 127 / 256, "Prediction moves d by at most +0.50' (linear (a=2, b=-1)), less than "
                      "a grid cell, from 0.50' without prediction."),
    # every predictor below no prediction: the best of them, not no prediction itself
    (0.25, "Prediction moves d by at most -0.25' (linear (a=2, b=-1)), less than a grid "
           "cell, from 0.50' without prediction."),
])
def test_report_verdict_at_one_cell(d_linear, verdict):
    runs = _runs(("none", "linear"), budget=False, none=_run("none", d=0.5),
                 linear=_run("linear", d=d_linear))
    text = fig4.report(fig4.compute(runs))
    assert f"\n{verdict} Off axis" in text
    assert "(fitting + aliasing, field mean nan\nrad^2" in text
    assert "temporal term, all a predictor can remove, is\nnan rad^2" in text


def test_report_one_point_grid_and_no_predictor():
    # a 1 x 1 grid: one cell = the whole field (60" / max(0, 1)); no predictor: "none"
    runs = _runs(("none",), none=_run("none", [[0.5]]))
    text = fig4.report(fig4.compute(runs))
    assert 'on the 1x1 science grid over\n60" (one cell = 60.0")' in text
    assert "so it is known to about a cell (1.00')" in text
    assert "Change of d against no prediction: . Field-mean SR: no prediction 0.500." in text
    assert ("Prediction moves d by at most +0.00' (no prediction), less than a grid cell, "
            "from 0.90' without prediction.") in text


@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig4")
    saved = []
    savefig = Figure.savefig

    def recording(self, fname, *args, **kwargs):
        saved.append((Path(str(fname)).name, self))
        return savefig(self, fname, *args, **kwargs)

    mp = pytest.MonkeyPatch()
    mp.setattr(Figure, "savefig", recording)
    try:
        text = fig4.make(out, _runs(quick=True))
        # the paper's four alone: a 2 x 2 figure
        paper = out / "paper"
        paper.mkdir()
        paths = fig4.plot(fig4.compute(_runs(("none", "linear", "arma", "nn-paper"))), paper)
        # no prediction and the oracle alone: the oracle's column makes it 3 columns
        two = out / "two"
        two.mkdir()
        fig4.plot(fig4.compute(_runs(("none", "oracle"))), two)
    finally:
        mp.undo()
    figures, small = dict(saved[:2]), dict(saved[2:4])
    return out, text, figures, paths, small, saved[4][1]


def _contours(ax):
    from matplotlib.contour import ContourSet

    return [c for c in ax.collections if isinstance(c, ContourSet)]


def test_plot_read_back(drawn):
    # one test reads everything back: mutmut runs a plot mutant only with the tests that
    # called plot (the fixture's first user), see docs/MUTATION.md
    out, text, figures, paths, small, two = drawn
    assert text == fig4.report(fig4.compute(_runs(quick=True)))
    assert paths == [out / "paper" / "fig4_sr_maps.png", out / "paper" / "fig4_sr_maps.pdf"]
    assert (out / "fig4_sr_maps.pdf").read_bytes()[:5] == b"%PDF-"
    fig = figures["fig4_sr_maps.png"]
    assert figures["fig4_sr_maps.pdf"] is fig
    # 8 runs: 3 columns (the extra one and the runs outside the layout), 3 rows
    assert tuple(fig.get_size_inches()) == pytest.approx((12.6, 11.4))
    assert matplotlib.image.imread(out / "fig4_sr_maps.png").shape[:2] == (1254, 1386)
    assert fig._suptitle.get_text() == "Figure 4: time-averaged SR maps, table1, seed 7 (quick)"
    grid = fig.axes[:9]
    cbar = fig.axes[9]
    assert len(fig.axes) == 10
    assert cbar.get_ylabel() == "SR after closure (500 nm)"
    # panel positions: row-major axes; titles name the runs, the paper's 2x2 + our column;
    # the runs outside the layout fill the free cells in order
    titles = [ax.get_title() for ax in grid]
    assert titles == ["no prediction", "linear (a=2, b=-1)", "oracle (true future)",
                      "ARMA(2,3)", "NN (paper, 10 patterns)", "ARMA (AIC order)",
                      "multivariate VAR(4)", "NN 10-10-1, 2000 patterns", ""]
    assert [ax.axison for ax in grid] == [True] * 8 + [False]
    assert {ax.title.get_fontsize() for ax in grid[:8]} == {9}
    assert [ax.get_xlabel() for ax in grid[:8]] == ["x [arcsec]"] * 8
    assert [ax.get_ylabel() for ax in grid[:8]] == ["y [arcsec]", "", "", "y [arcsec]", "", "",
                                                    "y [arcsec]", ""]
    names = ["none", "linear", "oracle", "arma", "nn-paper", "arma-aic", "multivariate", "nn"]
    for ax, name in zip(grid, names, strict=False):
        (im,) = ax.images
        np.testing.assert_array_equal(np.asarray(im.get_array()), MAPS[name])
        assert im.get_extent() == [-30.0, 30.0, -30.0, 30.0]      # arcsec, the 60" field
        assert im.origin == "lower" and im.get_clim() == (0.0, 1.0)
        assert im.get_cmap().name == "viridis" and im.get_interpolation() == "bilinear"
        d_text = [t for t in ax.texts if t.get_text().startswith("d = ")]
        (t,) = d_text
        assert t.get_text() == f"d = {DIAMETER[name]:.2f}' (SR > 0.3)"
        assert t.get_position() == (0.03, 0.04) and t.get_transform() == ax.transAxes
        assert (t.get_color(), t.get_fontsize()) == ("w", 8)
        box = t.get_bbox_patch()
        assert matplotlib.colors.to_rgb(box.get_facecolor()) == (0.0, 0.0, 0.0)
        assert box.get_alpha() == 0.5
    # contours: every 0.1 in black on the 3x3 maps, 0.3 in white where the map crosses it
    white = {"none": True, "linear": False, "oracle": True, "arma": True, "nn-paper": False,
             "arma-aic": True, "multivariate": None, "nn": None}
    for ax, name in zip(grid, names, strict=False):
        cs = _contours(ax)
        if white[name] is None:                   # a 1x1 map: no contour
            assert cs == []
            continue
        assert len(cs) == (2 if white[name] else 1), name
        np.testing.assert_allclose(cs[0].levels, np.arange(1, 10) / 10, atol=1e-12)
        assert matplotlib.colors.to_rgb(cs[0].get_edgecolor()[0]) == (0.0, 0.0, 0.0)
        assert cs[0].get_linewidth()[0] == 0.5
        xs = np.concatenate([p.vertices[:, 0] for p in cs[0].get_paths() if len(p.vertices)])
        assert xs.min() >= -30.0 and xs.max() <= 30.0 and xs.max() - xs.min() > 20.0
        labels = [t for t in ax.texts if not t.get_text().startswith("d = ")]
        assert labels and all(t.get_fontsize() == 6 for t in labels)
        assert all(len(t.get_text()) == 3 and t.get_text()[1] == "." for t in labels)
        if white[name]:
            np.testing.assert_array_equal(cs[1].levels, [0.3])
            assert matplotlib.colors.to_rgb(cs[1].get_edgecolor()[0]) == (1.0, 1.0, 1.0)
            assert cs[1].get_linewidth()[0] == 1.6
    # the colour bar shrunk to 0.8 of the panels' height
    top = max(ax.get_position().y1 for ax in grid)
    bottom = min(ax.get_position().y0 for ax in grid)
    assert cbar.get_position().height == pytest.approx(0.8 * (top - bottom), rel=0.02)
    assert cbar.get_position().x0 > max(ax.get_position().x1 for ax in grid)
    # the paper's four alone: 2 x 2, no "(quick)", the layout of the paper
    fig = small["fig4_sr_maps.png"]
    assert tuple(fig.get_size_inches()) == pytest.approx((8.4, 7.6))
    assert fig._suptitle.get_text() == "Figure 4: time-averaged SR maps, table1, seed 7"
    assert [ax.get_title() for ax in fig.axes[:4]] == [
        "no prediction", "linear (a=2, b=-1)", "ARMA(2,3)", "NN (paper, 10 patterns)"]
    assert len(fig.axes) == 5
    # no prediction and the oracle: 2 x 3, no prediction upper left, the oracle upper right
    assert tuple(two.get_size_inches()) == pytest.approx((12.6, 7.6))
    assert [ax.get_title() for ax in two.axes[:6]] == ["no prediction", "", "oracle (true "
                                                       "future)", "", "", ""]
    assert [ax.axison for ax in two.axes[:6]] == [True, False, True, False, False, False]


def test_a_run_outside_the_layout_among_few_runs(tmp_path):
    # the docstring: a third column for the extra runs; closedloop_runs.compute takes any
    # predictor names. No prediction, linear and the VAR(4): 3 columns, the VAR(4) in a
    # free cell (it raised StopIteration: the 2 x 3 grid was all reserved by LAYOUT)
    import matplotlib.pyplot as plt

    try:
        fig4.plot(fig4.compute(_runs(("none", "linear", "multivariate"))), tmp_path)
    finally:
        plt.close("all")


def test_a_two_by_two_map_gets_its_contours(tmp_path, monkeypatch):
    # the docstring's contours every 0.1 and the white SR 0.3 on any map of more than one
    # point (a 2 x 2 grid is a field of 4 directions, as a 1 x 1 is the axis alone)
    import matplotlib.colors as mcolors
    import matplotlib.pyplot as plt

    saved = []
    monkeypatch.setattr(fig4, "save_png_pdf", lambda f, out, png, pdf: saved.append(f)
                        or [out / png, out / pdf])
    smap = [[0.25, 0.5], [0.75, 1.0]]
    fig4.plot(fig4.compute(_runs(("none", "linear"), none=_run("none", smap))), tmp_path)
    (f,) = saved
    ax = f.axes[0]
    plt.close(f)
    assert ax.get_title() == "no prediction"
    sets = _contours(ax)
    assert len(sets) == 2
    np.testing.assert_allclose(sets[0].levels, np.arange(0.1, 1.0, 0.1))
    assert list(sets[1].levels) == [0.3]
    assert mcolors.to_hex(sets[1].get_edgecolor()[0]) == "#ffffff"
