"""Figure 5 (forecasts) on a hand-made evaluation: derived numbers, table, report, axes.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all outside
the module:
- a ``Figure5`` built here: the evaluation's gains, RMSEs and coverages are arrays
  written in this file (a stand-in with ``ForecastEvaluation``'s documented fields), the
  series and the ARMA interval are hand-made, so the derived numbers follow from the
  docstrings' definitions worked out by hand (the accurate horizon = the longest horizon
  up to which the gain stays > 1; the AIC orders counted, most frequent first; the
  forecast's largest |error| and the values inside the closed 95% interval);
- the table rows and the whole report are written out here word for word (the paper's
  ARMA(2,3) and 2-3 ms, Stangalini et al. Sect. 4);
- the figure is read back from the ``Figure`` handed to ``savefig`` (titles, axis labels
  with the log's units and the time unit, the series drawn in ms) and the PNG's size;
- ``compute``'s refusal of a short log at its documented bound (``MIN_FRAMES``: the ARMA
  windows and panel (c)'s 60 frames after the NN's training);
  ``compute`` with every predictor and the evaluation replaced by recorders: the paper's
  windows (ARMA(2,3) and the linear predictor fitted on frames 0-6999, the NN on patterns
  ending at frame 6980, the 10-step forecast), the frames drawn, and the paper NN's gain
  over persistence worked out by hand (a log whose first mode alternates 0, 1, 0, ...:
  persistence's RMSE is 1, a forecast "truth + e" has RMSE |e|).
No forecast is fitted: ~2 s.
"""

from __future__ import annotations

import types
from pathlib import Path

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog
from paper_figures import _common
from paper_figures import fig5_forecast as fig5

from .conftest import saved_figures

NAMES = ["persistence", "linear (a=2, b=-1)", "linear (LS a, b)", "ARMA(2,3)", "ARMA (AIC)",
         "NN 10-10-1, 2000 patterns", "NN paper (10 patterns)", "multivariate VAR(4)",
         "multivariate RLS"]
GAINS = np.array([
    [1.0] * 10,
    [0.75] * 10,
    [1.1] * 10,
    [1.5, 1.25, 1.1, 1.0, 0.9, 0.9, 0.9, 0.9, 0.9, 0.8],     # > 1 up to h = 3
    [1.75] * 10,
    [1.2] * 10,
    [0.5] * 10,
    [2.5, 2.25, 2.0, 1.75, 1.5, 1.5, 1.25, 1.25, 1.1, 1.2],  # > 1 everywhere: >= 10
    [2.25] * 10,
])
RMSE = 0.03 / GAINS
COVERAGE = np.full((9, 10), 0.5)
COVERAGE[3] = np.linspace(0.95, 0.9, 10)


class FakeEvaluation:
    """``ForecastEvaluation``'s fields and methods that Figure 5 uses, written here."""

    def __init__(self, gains=GAINS, names=NAMES):
        self.names = list(names)
        self.labels = ["Z2", "Z3"]
        self.horizons = np.arange(1, 11)
        self.gain_wavefront = np.array(gains)
        self.rmse_wavefront = 0.03 / self.gain_wavefront
        self.coverage = COVERAGE
        self.origins = np.arange(90)
        self.calls = []

    def index(self, name):
        return self.names.index(name)

    def to_json(self, path, overwrite=False):
        self.calls.append(("to_json", Path(path), overwrite))
        Path(path).write_text("{}")
        return str(path)

    def plot_rmse(self, ax, gain=False):
        self.calls.append(("plot_rmse", gain))
        ax.plot(self.horizons, self.gain_wavefront[0] if gain else self.rmse_wavefront[0],
                label="persistence")


X = np.zeros(7100)
X[7000:7010] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0]
X[6940:7000] = np.linspace(-1.0, 1.0, 60)
X[7010:7041] = 0.25
MEAN = X[7000:7010] + np.array([0.0, 0.01, -0.02, 0.0, 0.05, 0.0, 0.0, -0.125, 0.0, 0.0])
# inside the closed interval: the ends included (frames 7000 and 7001 sit on a bound)
LOWER = X[7000:7010] - np.array([0.0, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, -0.1, 0.1])
UPPER = X[7000:7010] + np.array([0.1, 0.0, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, -0.1])
AIC = np.array([[2, 3], [1, 1], [2, 3], [3, 3], [2, 3], [1, 1]])  # Z2 (2,3), Z3 (1,1)


def _figure(evaluation=None, rate=2000.0, quick=False, aic=AIC, seeds=(0, 1, 2, 3, 4)):
    return fig5.Figure5(
        source="`my.npz`", label="Z2", n_frames=7100, n_modes=6, rate=rate, units="rad",
        frame_ms=1e3 / rate if rate else 1.0, t_unit="ms" if rate else "frames", x=X,
        linear_frames=np.arange(6940, 7020), linear_one_step=np.linspace(0, 1, 80),
        arma_interval_mean=MEAN, arma_interval_lower=LOWER, arma_interval_upper=UPPER,
        nn_frames=np.arange(6981, 7041), nn_one_step=np.linspace(1, 2, 60),
        nn_paper_one_step=np.linspace(2, 3, 60), evaluation=evaluation or FakeEvaluation(),
        paper_nn_gains=(0.5, 0.25, 0.75, 0.625, 0.375)[:len(seeds)],
        increment_correlation=np.array([-0.25, -0.5, 0.0, -0.125, -0.375, -0.25]),
        aic_orders=aic, elapsed=7.31, paper_nn_seeds=seeds, quick=quick)


def test_derived_numbers():
    f = _figure()
    assert f.n_evaluated == 6
    assert f.gain("ARMA(2,3)") == 1.5 and f.gain("ARMA(2,3)", 4) == 1.0
    assert f.gain("multivariate VAR(4)", 10) == 1.2
    assert f.best_one_step == "multivariate VAR(4)"
    assert f.accurate_horizon("ARMA(2,3)") == 3
    assert f.accurate_horizon("multivariate VAR(4)") == 10
    assert f.accurate_horizon("linear (a=2, b=-1)") == 0
    assert f.accurate_horizon("persistence") == 0  # a gain of exactly 1 does not beat it
    assert f.aic_order_counts == [((2, 3), 3), ((1, 1), 2), ((3, 3), 1)]
    assert all(type(v) is int for (pq, c) in f.aic_order_counts for v in (*pq, c))
    # ties keep the (p, q) order
    f2 = _figure(aic=np.array([[3, 1], [1, 2], [3, 1], [1, 2], [0, 4]]))
    assert f2.aic_order_counts == [((1, 2), 2), ((3, 1), 2), ((0, 4), 1)]
    assert f.aic_larger == 1 and f2.aic_larger == 0
    assert _figure(aic=np.array([[3, 3], [2, 4], [5, 0]])).aic_larger == 2
    # |mean - x|: largest 0.125 (frame 7007); inside [lower, upper]: 8 of 10
    assert f.arma_forecast_max_error == pytest.approx(0.125, rel=1e-12)
    assert f.arma_forecast_inside == 8


def test_constants():
    assert (fig5.N_FIT, fig5.NN_END, fig5.H_ARMA) == (7000, 6980, 10)
    assert fig5.PAPER_ARMA_ORDER == (2, 3) and fig5.PAPER_HORIZON_MS == (2.0, 3.0)
    assert fig5.output_names("_s") == ["fig5_forecast_s.png", "fig5_forecast_s.pdf",
                                       "fig5_forecast_s.json"]
    assert fig5.output_names() == ["fig5_forecast.png", "fig5_forecast.pdf",
                                   "fig5_forecast.json"]
    assert list(fig5.HORIZONS) == list(range(1, 11))
    assert fig5.REPORT_HORIZONS == (1, 2, 3, 5, 10)
    assert (fig5.QUICK_MODES, fig5.QUICK_PAPER_SEEDS, fig5.PAPER_SEEDS) == (
        5, (0, 1), (0, 1, 2, 3, 4))


def test_increment_correlation_by_hand():
    # increments of [0, 1, 0, 1, 0]: [1, -1, 1, -1], mean 0: lag-1 sum -3 over 4 -> -0.75;
    # of [0, 1, 3, 6, 10]: [1, 2, 3, 4] - 2.5 = [-1.5, -0.5, 0.5, 1.5]: (0.75 - 0.25 + 0.75)
    # / 5 = 0.25
    x = np.array([[0.0, 0.0], [1.0, 1.0], [0.0, 3.0], [1.0, 6.0], [0.0, 10.0]])
    np.testing.assert_allclose(fig5._increment_correlation(x), [-0.75, 0.25], rtol=1e-12)


def test_short_log_refused_at_the_bound():
    log = ModalLog(np.random.default_rng(0).standard_normal((7040, 2)), rate=2000.0,
                   modes=[2, 3], units="rad")
    with pytest.raises(ValueError) as err:
        fig5.compute(log)
    assert str(err.value) == "`log` must hold at least 7041 frames for Figure 5; got 7040."


H_WHY = ("defined here as the longest horizon up to which the predictor beats persistence "
         "(whole-wavefront gain > 1) at every horizon 1-10 frames of the rolling-origin "
         "evaluation (90 origins after frame 6999); ARMA(2,3) gains x1.50 at h = 1 and x0.80 "
         "at h = 10, multivariate VAR(4) x2.50 and x1.20; the paper judges one mode's "
         "forecast by eye")


def test_table_rows_word_for_word():
    assert fig5.table_rows(_figure()) == [
        ("best ARMA order (p,q)", "(2,3)", "(2,3) (3/6 modes)",
         "AIC over p, q <= 5 on frames 0-6999 picks (2,3) for 3 of 6 modes and (2,3) for 3; "
         "at h = 1 ARMA(2,3) gains x1.50 over persistence on the whole wavefront, ARMA with "
         "AIC orders x1.75"),
        ("forecast horizon that stays accurate", "2-3 ms",
         "ARMA(2,3): 1.5 ms (3 frames); multivariate VAR(4): >= 5 ms (10 frames)", H_WHY),
    ]
    # without a rate: in frames
    rows = fig5.table_rows(_figure(rate=None))
    assert rows[1][2] == "ARMA(2,3): 3 frames; multivariate VAR(4): >= 10 frames"
    # the paper's order counted exactly (another order first)
    rows = fig5.table_rows(_figure(aic=np.array([[1, 1], [1, 1], [2, 3], [3, 2]])))
    assert rows[0][2] == "(1,1) (2/4 modes)"
    assert rows[0][3].startswith("AIC over p, q <= 5 on frames 0-6999 picks (1,1) for 2 of "
                                 "4 modes and (2,3) for 1;")


def _table():
    lines = ["| predictor | h=1 | h=2 | h=3 | h=5 | h=10 |", "|---|---|---|---|---|---|"]
    for i, name in enumerate(NAMES):
        cells = " | ".join(f"{RMSE[i, j]:.4f} (x{GAINS[i, j]:.2f})" for j in (0, 1, 2, 4, 9))
        lines.append(f"| {name} | {cells} |")
    return "\n".join(lines)


def test_report_word_for_word():
    # increments' correlation: mean -0.25, from -0.50 to 0.00; coverage 95.0 % and 90.0 %
    expected = f"""## Figure 5: forecasting a modal coefficient (linear, ARMA, neural net)

![Figure 5](fig5_forecast_s.png)

Input: `my.npz`, 7100 frames x 6 modes at 2000 Hz
(1 frame = 0.5 ms). Panels (a)-(c) show the first logged mode, **`Z2`**
(tip): the paper's caption says "Zernike 1", which in Noll's numbering is piston, a mode
no wavefront sensor measures, so we take the first mode the log contains.

- (a) Linear predictor x[n+1] = 2 x[n] - x[n-1], one-step predictions.
- (b) ARMA(2,3) (Yule-Walker/Hannan-Rissanen + conditional least squares) fitted on frames
  0-6999; 10-step forecast of frames 7000-7009 from the end of
  the window with its 95% interval (psi-weights): 8/10 measured
  values inside, largest error 0.125 rad. AIC over p, q <= 5
  picks (2,3) for `Z2`; over the 6 modes:
  (2,3) x3, (1,1) x2, (3,3) x1.
- (c) Neural net 10-10-1 trained on patterns ending at frame 6980, one-step forecasts
  (triangles) for the working configuration (2000 patterns, L-BFGS, standardised inputs,
  L2 penalty 1) and the paper's (10 patterns, unregularised).

Rolling-origin evaluation without look-ahead (fit on frames 0-6999, forecasts from
every origin of the remaining frames, the same origins for every horizon).
Whole-wavefront RMSE [rad] (sqrt of the mean over origins of the sum over modes of the
squared error; the RMS wavefront error for unit-RMS Zernike modes) and, in brackets, the
gain over persistence:

{_table()}

What this shows, honestly:

- The paper's linear extrapolation (a = 2, b = -1) **loses to persistence** on this \
log (wavefront gain x0.75 at h = 1 and worse at longer horizons):
  extrapolating the last slope beats persistence only when successive increments
  are positively correlated with coefficient > 0.5 (its one-step error is
  Delta x[n+1] - Delta x[n], of variance 2 (1 - rho) Var(Delta x)); here the
  lag-1 correlation of the increments is -0.25 on average over the modes (-0.50 to 0.00):
  your log `my.npz` has rough, anti-correlated increments.
  With least-squares weights the same two-tap predictor gains x1.10.
- ARMA(2,3), as in the paper, gains x1.50 at h = 1; letting AIC choose the order per
  mode gives x1.75 (the paper found (2,3) best on its closed-loop data;
  on this log AIC picks orders larger than (2,3) for 1 of the 6 modes).
  The 95% one-step intervals cover 95.0% of the test values (90.0% at
  h = 10).
- The neural net in a configuration that learns (2000 patterns) gains x1.20; the
  paper's configuration (10 patterns for 121 weights) gains x0.50 on the wavefront
  and, on `Z2` alone over seeds 0-4, between
  x0.25 and x0.75: it is worse than persistence and
  seed-dependent. We report it as published, beside the working one.
- Beyond the paper, the multivariate predictors that use the history of all modes gain
  x2.50 (batch VAR(4), Tikhonov-regularised) and x2.25 (RLS, forgetting
  0.999). Best at h = 1: **multivariate VAR(4)**.
- This is your log `my.npz`; the paper shows the forecasts qualitatively and gives
  no RMSE, so there is no number to compare with.

_(computed in 7.3 s)_
"""
    assert fig5.report(_figure(), suffix="_s") == expected


def test_report_other_branches():
    gains = GAINS.copy()
    gains[1] = 1.25  # the linear extrapolation wins
    text = fig5.report(_figure(FakeEvaluation(gains), rate=None, quick=True, seeds=(0, 1),
                               aic=np.array([[2, 3], [1, 1]])))
    assert ("![Figure 5](fig5_forecast.png)\n\n**Quick settings** (`--quick`): a smoke run, "
            "numbers not the paper's: the evaluation and the AIC orders on the first 2 of the "
            "6 modes, the paper's NN over 2 seeds.\n\nInput: `my.npz`, 7100 frames x 6 modes "
            "at an unknown rate (no --rate)\n(1 frame = 1 frames).") in text
    # the mean -0.25 is not "> 0.5": the report says why the wavefront gain can still
    # exceed 1 (leftovers 33-report)
    assert ("- The paper's linear extrapolation gains x1.25 over persistence at h = 1 (mean "
            "lag-1 increment correlation -0.25, not above 0.5: the wavefront gain weighs each "
            "mode by its increment variance and is measured on the frames after 6999, the mean "
            "weighs the modes equally on frames 0-6999).\n") in text
    assert "on this log AIC picks no order larger than (2,3)).\n" in text
    assert "on `Z2` alone over seeds 0-1, between\n  x0.25 and x0.50:" in text
    # exactly persistence (gain 1): not "loses"
    gains[1] = 1.0
    assert "linear extrapolation gains x1.00" in fig5.report(_figure(FakeEvaluation(gains)))


@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig5") / "new" / "sub"  # made with its parents
    with saved_figures() as figures:
        f = _figure()
        paths = fig5.plot(f, out, suffix="_s")
    return out, f, paths, figures


def test_plot_files(drawn):
    # every read-back in one test: the module fixture draws once, in the first
    # test's setup, and mutmut runs a mutant of `plot` only with the tests that called it
    import matplotlib.colors as mcolors
    import matplotlib.image

    out, f, paths, figures = drawn
    assert paths == [out / "fig5_forecast_s.png", out / "fig5_forecast_s.pdf",
                     out / "fig5_forecast_s.json"]
    assert matplotlib.image.imread(paths[0]).shape[:2] == (935, 1760)  # 16 x 8.5 in, 110 dpi
    assert paths[1].read_bytes()[:5] == b"%PDF-"
    assert f.evaluation.calls == [("to_json", out / "fig5_forecast_s.json", True),
                                  ("plot_rmse", False), ("plot_rmse", True)]
    assert tuple(figures["fig5_forecast_s.png"].get_size_inches()) == (16.0, 8.5)
    a, b, c, r, g = figures["fig5_forecast_s.png"].axes
    assert a.get_title() == "(a) linear predictor, Z2"
    assert b.get_title() == "(b) ARMA(2,3) fitted on frames 0-6999"
    assert c.get_title() == "(c) neural net, training ended at frame 6980"
    assert r.get_title() == "whole-wavefront RMSE vs horizon (6 modes, 90 forecast origins)"
    assert g.get_title() == "gain over persistence"
    assert r.get_yscale() == "log" and g.get_yscale() == "linear"
    for ax in (a, b, c):
        assert ax.get_xlabel() == "time [ms]" and ax.get_ylabel() == "Z2 [rad]"
        assert ax.get_legend().get_texts()[0].get_fontsize() == 7
    # (a): frames 6940-7019 at 0.5 ms
    meas, lin = a.get_lines()
    np.testing.assert_allclose(meas.get_xdata(), np.arange(6940, 7020) * 0.5)
    np.testing.assert_array_equal(meas.get_ydata(), X[6940:7020])
    np.testing.assert_array_equal(lin.get_ydata(), np.linspace(0, 1, 80))
    assert (lin.get_marker(), mcolors.to_hex(lin.get_color())) == (".", "#ff0000")
    assert lin.get_markersize() == 5 and meas.get_linewidth() == 1
    assert [t.get_text() for t in a.get_legend().get_texts()] == [
        "measured", "linear, one step ahead"]
    # (b): 40 frames before the forecast and its 10 frames; the fit's end at 6999.5 frames
    meas, fc, vline = b.get_lines()
    np.testing.assert_allclose(meas.get_xdata(), np.arange(6960, 7010) * 0.5)
    np.testing.assert_array_equal(meas.get_ydata(), X[6960:7010])
    np.testing.assert_allclose(fc.get_xdata(), np.arange(7000, 7010) * 0.5)
    np.testing.assert_array_equal(fc.get_ydata(), MEAN)
    assert fc.get_marker() == "o" and fc.get_markersize() == 4
    np.testing.assert_allclose(vline.get_xdata(), [3499.75, 3499.75])
    assert mcolors.to_hex(vline.get_color()) == mcolors.to_hex("0.6")
    assert vline.get_linewidth() == 0.8
    (band,) = b.collections
    verts = band.get_paths()[0].vertices
    np.testing.assert_allclose(sorted(set(np.round(verts[:, 0], 6))),
                               np.arange(7000, 7010) * 0.5)
    assert verts[:, 1].min() == pytest.approx(LOWER.min())
    assert verts[:, 1].max() == pytest.approx(UPPER.max())
    assert band.get_alpha() == 0.25
    assert [t.get_text() for t in b.get_legend().get_texts()] == [
        "measured", "95% interval", "ARMA(2,3), 10-step forecast"]
    # (c): 60 frames after the NN's training
    meas, nn, nnp = c.get_lines()
    np.testing.assert_allclose(meas.get_xdata(), np.arange(6981, 7041) * 0.5)
    np.testing.assert_array_equal(nn.get_ydata(), np.linspace(1, 2, 60))
    np.testing.assert_array_equal(nnp.get_ydata(), np.linspace(2, 3, 60))
    assert (nn.get_marker(), nnp.get_marker()) == ("^", "v")
    assert mcolors.to_hex(nnp.get_color()) == mcolors.to_hex("orange")
    assert [t.get_text() for t in c.get_legend().get_texts()] == [
        "measured", "NN 10-10-1, 2000 patterns", "NN paper (10 patterns)"]
    # every series at its frames' times (0.5 ms per frame at 2 kHz), the measured ones black
    np.testing.assert_allclose(lin.get_xdata(), np.arange(6940, 7020) * 0.5)
    np.testing.assert_array_equal(meas.get_ydata(), X[6981:7041])
    for ln in (nn, nnp):
        np.testing.assert_allclose(ln.get_xdata(), np.arange(6981, 7041) * 0.5)
        assert ln.get_markersize() == 4 and ln.get_linestyle() == "None"
    assert mcolors.to_hex(nn.get_color()) == mcolors.to_hex("m")
    for ax in (a, b, c):
        m = ax.get_lines()[0]
        assert m.get_label() == "measured" and m.get_linestyle() == "-"
        assert mcolors.to_hex(m.get_color()) == "#000000" and m.get_linewidth() == 1
    assert lin.get_linestyle() == "None"
    assert mcolors.to_hex(fc.get_color()) == mcolors.to_hex("C0") and fc.get_linestyle() == "-"
    assert mcolors.to_hex(band.get_facecolor()[0]) == mcolors.to_hex("C0")


def test_plot_time_axis_without_rate(tmp_path, monkeypatch):
    saved = []
    monkeypatch.setattr(fig5, "save_png_pdf", lambda fig, out, png, pdf: saved.append(fig)
                        or [out / png, out / pdf])
    paths = fig5.plot(_figure(rate=None), tmp_path)
    # the default suffix: the shipped names
    assert [p.name for p in paths] == ["fig5_forecast.png", "fig5_forecast.pdf",
                                       "fig5_forecast.json"]
    # panels (a)-(c) side by side on top, the RMSE and gain panels below, halves
    boxes = [ax.get_position() for ax in saved[0].axes]
    assert boxes[0].y0 == boxes[1].y0 == boxes[2].y0 > boxes[3].y1
    assert boxes[3].y0 == boxes[4].y0
    assert boxes[0].x0 == boxes[3].x0 and boxes[2].x1 == boxes[4].x1
    assert boxes[0].x1 < boxes[1].x0 < boxes[1].x1 < boxes[2].x0
    assert boxes[3].x1 < boxes[4].x0 < boxes[1].x1 and boxes[4].x0 > boxes[1].x0
    # thirds on top, halves below: equal widths in each row
    assert boxes[0].width == pytest.approx(boxes[1].width, rel=1e-9)
    assert boxes[2].width == pytest.approx(boxes[1].width, rel=1e-9)
    assert boxes[3].width == pytest.approx(boxes[4].width, rel=1e-9)
    a = saved[0].axes[0]
    assert a.get_xlabel() == "time [frames]"
    np.testing.assert_array_equal(a.get_lines()[0].get_xdata(), np.arange(6940, 7020))
    import matplotlib.pyplot as plt

    plt.close(saved[0])


def test_make_and_main(tmp_path, monkeypatch):
    calls = []
    # make reads its log through _common.prepared_log (one copy for Figures 1 and 5)
    monkeypatch.setattr(_common, "log_or_kaos_like", lambda p: calls.append(("load", p))
                        or ("LOG", "the source"))
    monkeypatch.setattr(fig5, "compute", lambda log, *, source: calls.append(
        ("compute", log, source)) or "FIG")
    monkeypatch.setattr(fig5, "plot", lambda f, out, *, suffix: calls.append(
        ("plot", f, out, suffix)))
    monkeypatch.setattr(fig5, "report", lambda f, *, suffix: f"report {f} {suffix}")
    assert fig5.make(tmp_path, Path("x.npz"), suffix="_s") == "report FIG _s"
    assert calls == [("load", Path("x.npz")), ("compute", "LOG", "the source"),
                     ("plot", "FIG", tmp_path, "_s")]
    # the default suffix is none: the shipped names
    assert fig5.make(tmp_path, None) == "report FIG "
    assert calls[-1] == ("plot", "FIG", tmp_path, "")
    got = []
    monkeypatch.setattr(fig5, "figure_main", lambda argv, **kw: got.append((argv, kw)) or 3)
    assert fig5.main(["--x"]) == 3
    assert got == [(["--x"], {"prog": "python -m paper_figures.fig5_forecast",
                              "description": "Regenerate Figure 5 (forecasts).",
                              "figure_name": "fig5_forecast.png", "make": fig5.make,
                              "output_names": fig5.output_names,
                              "time_axis": fig5.TIME_AXIS_USE})]


# ---------------------------------------------------------------------------------------
# compute, with every predictor and the evaluation replaced by recorders (no fit runs).
# The log's first mode alternates 0, 1, 0, ...: persistence's one-step error is +-1, RMSE 1;
# a paper NN whose forecast is the truth plus e has RMSE |e|, so its gain is 1 / |e|.

class FakePredictor:
    made: list = []

    def __init__(self, kind, **kw):
        self.kind, self.kw, self.fitted = kind, kw, None
        FakePredictor.made.append(self)

    def fit(self, x):
        self.fitted = np.array(x)
        return self

    def _forecast_path(self, x, horizon):
        assert horizon == 1 and x.shape[1:] == (1,)
        t = np.arange(x.shape[0], dtype=float)
        if "random_state" in self.kw:  # the paper's NN over seeds: truth + e
            e = {0: 0.5, 1: 0.25, 2: 2.0, 3: 4.0, 4: 1.0}[self.kw["random_state"]]
            path = np.append(x[1:, 0], 0.0) + e
        else:  # panels (a) and (c): frame numbers, so the test sees which frame is drawn
            path = {"linear": 1000.0, "nn": 2000.0, "nn-paper": 3000.0}[self.kind] + t
        return path[:, None, None], None

    def predict_interval(self, x):
        self.interval_from = np.array(x)
        return types.SimpleNamespace(mean=[1.0] * 10, lower=[0.5] * 10, upper=[2.0] * 10)

    @property
    def orders_(self):
        return [[len(self.fitted), m] for m in range(self.fitted.shape[1])]


class FakeNN:
    def __new__(cls, **kw):
        return FakePredictor("nn", **kw)

    @staticmethod
    def paper(**kw):
        return FakePredictor("nn-paper", **kw)


def _alternating_log(n_modes=6):
    data = np.zeros((7100, n_modes))
    data[:, 0] = np.arange(7100) % 2
    data[:, 1:] = np.random.default_rng(5).standard_normal((7100, n_modes - 1))
    return ModalLog(data, rate=2000.0, modes=list(range(2, 2 + n_modes)), units="rad")


@pytest.fixture
def forecasters(monkeypatch):
    import modalinfo.forecast

    FakePredictor.made = []
    evaluated = []

    def evaluate(predictors, log, *, train, horizons):
        evaluated.append((predictors, log, train, horizons))
        return types.SimpleNamespace(labels=list(log.labels))

    monkeypatch.setattr(modalinfo.forecast, "LinearPredictor",
                        lambda **kw: FakePredictor("linear", **kw))
    monkeypatch.setattr(modalinfo.forecast, "ARMAPredictor",
                        lambda **kw: FakePredictor("arma", **kw))
    monkeypatch.setattr(modalinfo.forecast, "NeuralNetPredictor", FakeNN)
    monkeypatch.setattr(modalinfo.forecast, "evaluate", evaluate)
    monkeypatch.setattr(fig5, "_predictors", lambda: "PRESETS")
    clock = iter([10.0, 13.5])
    monkeypatch.setattr(fig5, "time", types.SimpleNamespace(perf_counter=lambda: next(clock)))
    return evaluated


def test_compute_fits_the_papers_windows_and_collects_the_numbers(forecasters):
    log = _alternating_log()
    data = np.asarray(log.coeffs)
    f = fig5.compute(log)
    made = {(p.kind, tuple(sorted(p.kw.items()))): p for p in FakePredictor.made}
    lin = made[("linear", (("horizon", 1),))]
    np.testing.assert_array_equal(lin.fitted, data[:7000, 0])
    arma = made[("arma", (("horizon", 10), ("order", (2, 3))))]
    np.testing.assert_array_equal(arma.fitted, data[:7000, 0])
    np.testing.assert_array_equal(arma.interval_from, data[:7000, 0])  # from frame 6999 on
    nn = made[("nn", (("horizon", 1),))]
    nnp = made[("nn-paper", (("horizon", 1),))]
    np.testing.assert_array_equal(nn.fitted, data[:6981, 0])   # patterns end at frame 6980
    np.testing.assert_array_equal(nnp.fitted, data[:6981, 0])
    for seed in range(5):
        p = made[("nn-paper", (("horizon", 1), ("random_state", seed)))]
        np.testing.assert_array_equal(p.fitted, data[:7000, 0])
    aic = made[("arma", (("order", "aic"),))]
    np.testing.assert_array_equal(aic.fitted, data[:7000])
    assert len(FakePredictor.made) == 1 + 1 + 2 + 5 + 1
    (preds, ev_log, train, horizons), = forecasters
    assert (preds, ev_log, train, list(horizons)) == ("PRESETS", log, 7000, list(range(1, 11)))
    # the numbers
    assert (f.source, f.label, f.n_frames, f.n_modes, f.rate, f.units) == (
        "a modal log", "Z2", 7100, 6, 2000.0, "rad")
    assert (f.frame_ms, f.t_unit, f.quick, f.elapsed) == (0.5, "ms", False, 3.5)
    np.testing.assert_array_equal(f.x, data[:, 0])
    np.testing.assert_array_equal(f.linear_frames, np.arange(6940, 7020))
    np.testing.assert_array_equal(f.linear_one_step, 1000.0 + np.arange(6939, 7019))
    np.testing.assert_array_equal(f.nn_frames, np.arange(6981, 7041))
    np.testing.assert_array_equal(f.nn_one_step, 2000.0 + np.arange(6980, 7040))
    np.testing.assert_array_equal(f.nn_paper_one_step, 3000.0 + np.arange(6980, 7040))
    np.testing.assert_array_equal(f.arma_interval_mean, [1.0] * 10)
    np.testing.assert_array_equal(f.arma_interval_lower, [0.5] * 10)
    np.testing.assert_array_equal(f.arma_interval_upper, [2.0] * 10)
    assert f.paper_nn_gains == (2.0, 4.0, 0.5, 0.25, 1.0)
    assert f.paper_nn_seeds == (0, 1, 2, 3, 4)
    assert f.evaluation.labels == ["Z2", "Z3", "Z4", "Z5", "Z6", "Z7"]
    # the increments' lag-1 correlation on frames 0-6999 only (column 0 alternates: the
    # increments +1, -1, ... are perfectly anti-correlated, up to their mean 1/6999)
    assert f.increment_correlation.shape == (6,)
    assert f.increment_correlation[0] == pytest.approx(-1.0, abs=1e-3)
    np.testing.assert_array_equal(f.aic_orders, [[7000, m] for m in range(6)])


def test_compute_quick_and_without_rate(forecasters):
    data = np.asarray(_alternating_log(7).coeffs)
    log = ModalLog(data, modes=list(range(2, 9)), units="rad")
    f = fig5.compute(log, source="mine", quick=True)
    (_, ev_log, _, _), = forecasters
    assert list(ev_log.labels) == ["Z2", "Z3", "Z4", "Z5", "Z6"]  # the first 5 modes
    aic = [p for p in FakePredictor.made if p.kw == {"order": "aic"}][0]
    np.testing.assert_array_equal(aic.fitted, data[:7000, :5])
    assert f.paper_nn_seeds == (0, 1) and f.paper_nn_gains == (2.0, 4.0)
    assert (f.source, f.quick, f.n_modes, f.rate) == ("mine", True, 7, None)
    assert (f.frame_ms, f.t_unit) == (1.0, "frames")
    assert f.aic_orders.shape == (5, 2)


def test_predictors_are_the_presets():
    from modalinfo.forecast.presets import PRESETS

    got = fig5._predictors()
    assert list(got) == [label for label, _ in PRESETS.values()]
    assert [type(p) for p in got.values()] == [type(f()) for _, f in PRESETS.values()]


def test_compute_refuses_one_frame_short(forecasters):
    # the bound is panel (c)'s last measured frame, NN_END + 60 = 7040 (a frame count of
    # 7041), beyond the ARMA windows' N_FIT + 2 H_ARMA = 7020; 7040 are refused
    data = np.asarray(_alternating_log(2).coeffs)
    with pytest.raises(ValueError) as err:
        fig5.compute(ModalLog(data[:7040], rate=2000.0, modes=[2, 3], units="rad"))
    assert str(err.value) == "`log` must hold at least 7041 frames for Figure 5; got 7040."
    assert FakePredictor.made == []          # refused before any fit


def test_compute_at_the_frame_bound(forecasters):
    # a log of exactly the bound is served: panel (c) measures frames NN_END + 1 ..
    # NN_END + 60 and reads the one-step path (one row per frame, as ``_forecast_path``
    # documents: path (T, H, M)) up to row NN_END + 59. A log of 7020-7040 frames passed
    # the old N_FIT + 2 H_ARMA check and raised IndexError after every fit.
    data = np.asarray(_alternating_log(2).coeffs)
    f = fig5.compute(ModalLog(data[:7041], rate=2000.0, modes=[2, 3], units="rad"))
    assert f.n_frames == 7041
    np.testing.assert_array_equal(f.nn_frames, np.arange(6981, 7041))


def test_compute_persistence_rmse_of_a_mode_with_a_mean(forecasters):
    # the first mode alternates 1, 3: persistence errs by +-2 (RMSE 2), the paper NN's
    # "truth + e" by e, so its gains are 2 / |e| (a sum in place of the difference, 4 / |e|)
    data = np.array(_alternating_log(2).coeffs)
    data[:, 0] = 1.0 + 2.0 * data[:, 0]
    f = fig5.compute(ModalLog(data, rate=2000.0, modes=[2, 3], units="rad"))
    assert f.paper_nn_gains == (4.0, 8.0, 1.0, 0.5, 2.0)
