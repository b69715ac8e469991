"""Figure 3 (SR-peak spectra) on hand-made runs: band powers, words, rows, report, axes.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all
outside the module:

- the runs are written in this file: spectra on a 10-Hz grid (0 .. 100 Hz, Nyquist
  100 Hz) whose band powers are trapezoids done by hand (no prediction: 50 over
  40-60 Hz, 30 over 70-100 Hz) and whose predictors are the no-prediction spectrum
  scaled by 0.25, 0.75 or 1.5 per band, so each ratio is exact; SR series of two
  levels, so each mean and RMS is ``|a - b| sqrt(p q)`` by hand;
- the paper (Stangalini et al., Sect. 3.4, text on Fig. 3): the bands "~50 Hz" (read as
  40-60 Hz) and "above 70 Hz", and what each predictor does there (linear reduces in
  both bands, ARMA and NN damp at ~50 Hz and reduce above 70 Hz);
- the module docstring's words (< 0.5 damped, 0.5-0.9 reduced, 0.9-1.1 unchanged,
  > 1.1 amplified), the loss rule (mean SR peak over no prediction's window below half
  of no prediction's) and the Welch error ``1 / sqrt(n_bins n_seg)`` with Hann
  segments of up to 256 frames at 50 % overlap, worked out by hand (512 frames: 3
  segments);
- the figure read back from the ``Figure`` handed to ``savefig`` (log-log axes in Hz,
  the series drawn without the 0-Hz bin, the two bands, the paper's line styles).
No closed loop runs: ~2 s.
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest
from matplotlib.figure import Figure

from paper_figures import fig3_sr_spectrum as fig3
from paper_figures.closedloop_runs import ClosedLoopRuns, PredictorRun

from .conftest import saved_figures

FREQS = np.arange(0.0, 101.0, 10.0)      # 0, 10, ..., 100 Hz
# no prediction: 1 everywhere but 9 at 10 Hz, 8 at 20 Hz (not above 20 Hz) and 4 at 50 Hz
NONE_PSD = np.array([5.0, 9.0, 8.0, 1.0, 1.0, 4.0, 1.0, 1.0, 1.0, 1.0, 1.0])
# band powers of NONE_PSD: 40-60 Hz 10 (1 + 4) / 2 + 10 (4 + 1) / 2 = 50; 70-100 Hz: 30
LOW = FREQS <= 60.0
T, CLOSE = 600, 88                       # 512 frames after no prediction's closure


def _two_levels(a, b, start, before=None):
    """SR series: ``before`` up to ``start``, then a, b, a, b, ..."""
    s = np.empty(T)
    s[:start] = a if before is None else before
    s[start:] = np.where(np.arange(T - start) % 2 == 0, a, b)
    return s


def _run(name, factors, series, closure):
    low, high = factors
    psd = NONE_PSD * np.where(LOW, low, high)
    return PredictorRun(
        name=name, summary={"strehl_peak_mean": 0.0, "steps_per_second": 1.0},
        times=np.arange(1, T + 1) * 1e-3, strehl_peak=series, closure_index=closure,
        spectrum_freqs=FREQS.copy(), spectrum_psd=psd,
        strehl_map=np.zeros((2, 2)), fov_diameter=0.0)


def _runs(quick=False):
    runs = {
        "none": _run("none", (1.0, 1.0), _two_levels(0.25, 0.75, CLOSE), CLOSE),
        # ~50 Hz damped (the paper: reduced), > 70 Hz amplified (the paper: reduced)
        "linear": _run("linear", (0.25, 1.5), _two_levels(0.375, 0.625, CLOSE), CLOSE),
        # as in the paper in both bands; closes later, zeros before its closure
        "arma": _run("arma", (0.25, 0.75), _two_levels(0.375, 0.625, 100, before=0.0), 100),
        # the loop lost in no prediction's window (1.0 before frame 88, then 0.125); over
        # its own window (from frame 0) its mean would be 0.253 > 0.25
        "nn-paper": _run("nn-paper", (0.0625, 0.0625), _two_levels(0.125, 0.125, CLOSE,
                                                                   before=1.0), 0),
        "oracle": _run("oracle", (1.0, 1.0), np.full(T, 0.5), CLOSE),
        "arma-aic": _run("arma-aic", (1.0, 1.5), _two_levels(0.25, 0.75, CLOSE), CLOSE),
    }
    return ClosedLoopRuns(config_name="table1", seed=7, duration=0.6, field_size=60.0,
                          wavelength=500e-9, runs=runs, budget={}, quick=quick)


@pytest.fixture(scope="module")
def result():
    return fig3.compute(_runs())


def test_the_paper_constants():
    assert fig3.BAND_50 == (40.0, 60.0) and fig3.BAND_HIGH_MIN == 70.0
    assert fig3.PAPER_50 == {"linear": "reduced", "arma": "damped", "nn-paper": "damped"}
    assert fig3.PAPER_HIGH == {"linear": "reduced", "arma": "reduced", "nn-paper": "reduced"}
    assert (fig3.FIGURE_NAME, fig3.PDF_NAME) == ("fig3_sr_spectrum.png", "fig3_sr_spectrum.pdf")
    assert fig3.NEEDS_RUNS is True and fig3.DEGRADED == 0.5


def test_band_power_trapezoid_closed_band():
    # 40..60 inclusive: 50; the open band 40 < f < 60 would be a single bin -> NaN
    assert fig3.band_power(FREQS, NONE_PSD, 40.0, 60.0) == 50.0
    assert fig3.band_power(FREQS, NONE_PSD, 70.0, 100.0) == 30.0
    assert type(fig3.band_power(FREQS, NONE_PSD, 70.0, 100.0)) is float
    # two bins are enough, one is not
    assert fig3.band_power(FREQS, NONE_PSD, 50.0, 60.0) == 25.0
    assert math.isnan(fig3.band_power(FREQS, NONE_PSD, 45.0, 55.0))
    assert math.isnan(fig3.band_power(FREQS, NONE_PSD, 101.0, 200.0))


def test_band_powers_and_ratios(result):
    assert result.power_50 == {"none": 50.0, "linear": 12.5, "arma": 12.5, "nn-paper": 3.125,
                               "oracle": 50.0, "arma-aic": 50.0}
    assert result.power_high == {"none": 30.0, "linear": 45.0, "arma": 22.5,
                                 "nn-paper": 1.875, "oracle": 30.0, "arma-aic": 45.0}
    assert result.ratio_50 == {"none": 1.0, "linear": 0.25, "arma": 0.25, "nn-paper": 0.0625,
                               "oracle": 1.0, "arma-aic": 1.0}
    assert result.ratio_high == {"none": 1.0, "linear": 1.5, "arma": 0.75, "nn-paper": 0.0625,
                                 "oracle": 1.0, "arma-aic": 1.5}
    # the high band ends at each run's own Nyquist (its last frequency)
    runs = _runs()
    short = runs.runs["linear"]
    cut = PredictorRun(**{**short.__dict__, "spectrum_freqs": FREQS[:-1],
                          "spectrum_psd": short.spectrum_psd[:-1]})
    r = fig3.compute(ClosedLoopRuns(**{**runs.__dict__, "runs": {"none": runs.runs["none"],
                                                                  "linear": cut}}))
    assert r.power_high["linear"] == 30.0     # 70..90 Hz at 1.5: 1.5 * 20
    assert r.runs is not None and r.runs.runs["linear"] is cut


def test_words_at_their_boundaries():
    assert [fig3._word(v) for v in (0.0, 0.4999, 0.5, 0.8999, 0.9, 1.0, 1.1, 1.1001, 7.0)] == [
        "damped", "damped", "reduced", "reduced", "unchanged", "unchanged", "unchanged",
        "amplified", "amplified"]
    assert [fig3._word(v) for v in (math.nan, math.inf, -math.inf)] == ["n/a"] * 3


def test_loss_uses_no_predictions_window_and_is_strict(result):
    assert [n for n in result.runs.runs if fig3._degraded(result, n)] == ["nn-paper"]
    assert fig3._degraded(result, "nn-paper") is True
    assert fig3._degraded(result, "arma") is False
    # exactly half of no prediction's mean (0.25 of 0.5) keeps the loop
    runs = _runs()
    half = _run("linear", (1.0, 1.0), np.full(T, 0.25), CLOSE)
    r = fig3.compute(ClosedLoopRuns(**{**runs.__dict__, "runs": {"none": runs.runs["none"],
                                                                  "linear": half}}))
    assert fig3._degraded(r, "linear") is False
    low = _run("linear", (1.0, 1.0), np.full(T, 0.2499), CLOSE)
    r = fig3.compute(ClosedLoopRuns(**{**runs.__dict__, "runs": {"none": runs.runs["none"],
                                                                  "linear": low}}))
    assert fig3._degraded(r, "linear") is True


def test_relative_error_welch_segments(result):
    # 512 frames after closure: 256-frame segments at 50 % overlap -> 3; 3 bins in
    # 40-60 Hz -> 1 / sqrt(9); 4 bins in 70-100 Hz -> 1 / sqrt(12)
    assert fig3.relative_error(result, 40.0, 60.0) == pytest.approx(1 / 3, rel=1e-12)
    assert fig3.relative_error(result, 70.0, 100.0) == pytest.approx(1 / math.sqrt(12),
                                                                   rel=1e-12)
    # 100 frames: one segment of 100; 600 frames (closure 0): 1 + 344 // 128 = 3
    runs = _runs()
    for closure, n_seg in ((500, 1), (0, 3), (344, 1), (216, 2)):
        none = PredictorRun(**{**runs.runs["none"].__dict__, "closure_index": closure})
        r = fig3.compute(ClosedLoopRuns(**{**runs.__dict__, "runs": {"none": none}}))
        assert fig3.relative_error(r, 40.0, 60.0) == pytest.approx(
            1 / math.sqrt(3 * n_seg), rel=1e-12), closure
    # no bin in the band: the error of one
    assert fig3.relative_error(result, 41.0, 49.0) == 1.0


SCATTER = ("; the oscillations are of the whole residual (fitting, aliasing), not of the "
           "temporal term prediction changes")
LOST = "the loop was lost: the power is that of an SR near zero"


def _rows():
    q50, qh = "SR oscillation power at ~50 Hz / none, ", "SR oscillation power > 70 Hz / none, "
    return [
        (q50 + "linear (a=2, b=-1)", "reduced", "0.25 (damped)",
         "ratio scatter without any effect about 47%" + SCATTER),
        (qh + "linear (a=2, b=-1)", "reduced", "1.50 (amplified)",
         "ratio scatter without any effect about 41%" + SCATTER),
        (q50 + "ARMA(2,3)", "damped", "0.25 (damped)", "as in the paper"),
        (qh + "ARMA(2,3)", "reduced", "0.75 (reduced)", "as in the paper"),
        (q50 + "NN (paper, 10 patterns)", "damped", "0.06 (loop lost)", LOST),
        (qh + "NN (paper, 10 patterns)", "reduced", "0.06 (loop lost)", LOST),
        (q50 + "oracle (true future)", "-", "1.00 (unchanged)", "not in the paper"),
        (qh + "oracle (true future)", "-", "1.00 (unchanged)", "not in the paper"),
        (q50 + "ARMA (AIC order)", "-", "1.00 (unchanged)", "not in the paper"),
        (qh + "ARMA (AIC order)", "-", "1.50 (amplified)", "not in the paper"),
    ]


def test_table_rows_word_for_word(result):
    assert fig3.table_rows(result) == _rows()


def test_report_word_for_word(result):
    table = "\n".join(["| quantity | paper | ours | why they differ |", "|---|---|---|---|"]
                      + [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in _rows()])
    # NN's RMS over its own window (from frame 0): 88 frames of 1.0, 512 of 0.125
    nn_rms = 0.875 * math.sqrt(88 * 512) / 600
    expected = f"""## Figure 3: power spectra of the SR-peak oscillations

![Figure 3](fig3_sr_spectrum.png)

Welch spectra of the SR peak after the detected closure, or over the second half of a
run that did not close (512 frames without prediction, resolution 10.0 Hz);
band power = the PSD integrated over
40-60 Hz ("~50 Hz") and 70 Hz to Nyquist ("above
70 Hz"), divided by the no-prediction run's. Words: < 0.5 damped, 0.5-0.9 reduced,
0.9-1.1 unchanged, > 1.1 amplified.

{table}

RMS of the SR peak after closure: no prediction 0.2500, linear (a=2, b=-1) 0.1250, \
ARMA(2,3) 0.1250, NN (paper, 10 patterns) {nn_rms:.4f}, oracle (true future) 0.0000, \
ARMA (AIC order) 0.2500. Above 20 Hz the no-prediction
spectrum peaks at 50 Hz. Predictors whose behaviour in both bands matches the
paper's description: ARMA(2,3). Of the 4 runs that keep the loop, 2 raise the power in \
at least one band by more than 10 % (linear (a=2, b=-1), ARMA (AIC order)). Statistical \
precision: with 512
frames the band powers carry a relative standard error of about 33% (~50 Hz)
and 29% (> 70 Hz), so their ratios can scatter by up to about 47%
and 41% (less: the runs share one atmosphere) without any effect.
Lost the loop (mean SR peak below half of no prediction's; their low band powers are \
those of an SR near zero): NN (paper, 10 patterns). The SR-peak oscillations are the \
fluctuations of the whole residual,
dominated by fitting and aliasing (Figure 2's budget), of which the temporal term that
prediction changes is a few per cent; the oracle, whose forecast is exact, changes the
band powers too, so these ratios measure how each control law reshapes the residual's
fluctuations, not the quality of the forecast. The paper gives no numbers for its
spectra, only the statements in the table.
"""
    assert fig3.report(result) == expected
    assert f"{nn_rms:.4f}" == "0.3096"


def _unclosed(run, series):
    """``run`` that did not close: closure_index 0 (an SR that never rose), averages from
    the second half (frame T // 2 = 300, as closedloop.SimulationResult.averaging_start)."""
    return PredictorRun(**{**run.__dict__, "strehl_peak": series, "closure_index": 0,
                           "averaging_start": T // 2,
                           "summary": {**run.summary, "loop_status": "did not close: test"}})


def test_a_run_that_did_not_close_is_read_over_its_second_half():
    runs = _runs()
    # no prediction: 0.9 up to frame 300, then 0.25, 0.75, ...: over its second half the
    # RMS is 0.25 and the mean 0.5 (loss below 0.25); from frame 0 they would be 0.2669
    # and 0.7 (loss below 0.35)
    none = _unclosed(runs.runs["none"], _two_levels(0.25, 0.75, T // 2, before=0.9))
    # linear: 0.9 then 0.125, lost over the second half, kept from frame 0 (0.5125);
    # oracle: 0.2 then 0.3, kept over the second half, lost from frame 0 (0.25)
    # (linear did not close either: its RMS is over its second half, 0; the oracle closed
    # at frame 88: its RMS is over 212 frames of 0.2 and 300 of 0.3, 0.1 sqrt(pq))
    lin = _unclosed(runs.runs["linear"], _two_levels(0.125, 0.125, T // 2, before=0.9))
    ora = PredictorRun(**{**runs.runs["oracle"].__dict__,
                          "strehl_peak": _two_levels(0.3, 0.3, T // 2, before=0.2)})
    r = fig3.compute(ClosedLoopRuns(**{**runs.__dict__,
                                       "runs": {"none": none, "linear": lin, "oracle": ora}}))
    assert fig3._degraded(r, "linear") is True
    assert fig3._degraded(r, "oracle") is False
    # 300 frames: one 256-frame segment (1 + 44 // 128); from frame 0 (600 frames) 3
    assert fig3.relative_error(r, 40.0, 60.0) == pytest.approx(1 / math.sqrt(3), rel=1e-12)
    text = fig3.report(r)
    ora_rms = 0.1 * math.sqrt(212 * 300) / 512
    assert f"{ora_rms:.4f}" == "0.0493"
    assert ("RMS of the SR peak after closure: no prediction 0.2500 (did not close: second "
            "half), linear (a=2, b=-1) 0.0000 (did not close: second half), oracle (true "
            f"future) {ora_rms:.4f}.") in text
    assert "(300 frames without prediction" in text
    assert "Statistical precision: with 300\nframes" in text
    # a hand-built run without averaging_start / loop_status reads as closed at its closure
    assert runs.runs["none"].window_start == CLOSE and runs.runs["none"].closed is True
    assert none.window_start == T // 2 and none.closed is False


def test_report_without_matches_amplification_or_loss():
    runs = _runs()
    keep = {k: runs.runs[k] for k in ("none", "oracle")}
    text = fig3.report(fig3.compute(ClosedLoopRuns(**{**runs.__dict__, "runs": keep})))
    assert ("paper's description: none. Of the 1 runs that keep the loop, 0 raise the power "
            "in at least one band by more than 10 %. Statistical") in text
    assert "Lost the loop" not in text
    assert "without any effect.\nThe SR-peak oscillations" in text


def test_report_peak_above_20_hz_only():
    # no bin above 20 Hz: the peak is NaN
    runs = _runs()
    f = FREQS[:3]
    none = PredictorRun(**{**runs.runs["none"].__dict__, "spectrum_freqs": f,
                           "spectrum_psd": NONE_PSD[:3]})
    text = fig3.report(fig3.compute(ClosedLoopRuns(**{**runs.__dict__,
                                                      "runs": {"none": none}})))
    assert "spectrum peaks at nan Hz." in text


@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig3")
    with saved_figures() as figures:
        text = fig3.make(out, _runs(quick=True))
    return out, text, figures


def test_plot_read_back(drawn, result):
    # one test reads everything back: mutmut runs a plot mutant only with the tests that
    # called plot (the fixture's first user), see docs/MUTATION.md
    out, text, figures = drawn
    assert text == fig3.report(fig3.compute(_runs(quick=True)))
    fig = figures["fig3_sr_spectrum.png"]
    assert figures["fig3_sr_spectrum.pdf"] is fig
    assert tuple(fig.get_size_inches()) == (8.0, 4.8)
    assert matplotlib.image.imread(out / "fig3_sr_spectrum.png").shape[:2] == (528, 880)
    assert (out / "fig3_sr_spectrum.pdf").read_bytes()[:5] == b"%PDF-"
    (ax,) = fig.axes
    assert (ax.get_xscale(), ax.get_yscale()) == ("log", "log")
    assert ax.get_xlabel() == "frequency [Hz]"
    assert ax.get_ylabel() == "PSD of the SR peak [1/Hz]"
    assert ax.get_title() == "Figure 3: SR-peak oscillations after loop closure (Welch) (quick)"
    lines = ax.get_lines()
    labels = ["no prediction", "linear (a=2, b=-1)", "ARMA(2,3)", "NN (paper, 10 patterns)",
              "oracle (true future)", "ARMA (AIC order)"]
    assert [ln.get_label() for ln in lines[:6]] == labels
    factors = [(1.0, 1.0), (0.25, 1.5), (0.25, 0.75), (0.0625, 0.0625), (1.0, 1.0), (1.0, 1.5)]
    for ln, (lo, hi) in zip(lines[:6], factors, strict=True):
        np.testing.assert_array_equal(ln.get_xdata(), FREQS[1:])     # the 0-Hz bin left out
        np.testing.assert_array_equal(ln.get_ydata(),
                                      (NONE_PSD * np.where(LOW, lo, hi))[1:])
    # the paper's styles: black continuous none, red dots linear (4-pt), blue dash-dotted
    # ARMA, magenta dashed NN
    styles = [(ln.get_color(), ln.get_linestyle()) for ln in lines[:6]]
    assert styles == [("k", "-"), ("r", "None"), ("b", "-."), ("m", "--"), ("0.55", ":"),
                      ("c", "-.")]
    assert (lines[1].get_marker(), lines[1].get_markersize()) == (".", 4)
    assert lines[5].get_linewidth() == 0.8
    # the band lines at 50 and 70 Hz
    v50, v70 = lines[6:]
    np.testing.assert_array_equal(v50.get_xdata(), [50.0, 50.0])
    np.testing.assert_array_equal(v70.get_xdata(), [70.0, 70.0])
    assert (v50.get_color(), v50.get_linewidth()) == ("orange", 0.8)
    assert (v70.get_color(), v70.get_linewidth()) == ("0.5", 0.8)
    # the shaded bands: 40-60 Hz and 70 Hz to no prediction's Nyquist (100 Hz)
    spans = [p for p in ax.patches if p.get_label() in ("~50 Hz (40-60 Hz)", "> 70 Hz")]
    assert [p.get_label() for p in spans] == ["~50 Hz (40-60 Hz)", "> 70 Hz"]
    assert [(p.get_x(), p.get_x() + p.get_width()) for p in spans] == [(40.0, 60.0),
                                                                       (70.0, 100.0)]
    assert spans[0].get_alpha() == 0.15 and spans[1].get_alpha() == 0.4
    assert matplotlib.colors.to_rgb(spans[0].get_facecolor()) == matplotlib.colors.to_rgb(
        "orange")
    assert matplotlib.colors.to_rgb(spans[1].get_facecolor()) == (0.85, 0.85, 0.85)
    leg = ax.get_legend()
    assert [t.get_text() for t in leg.get_texts()] == labels + ["~50 Hz (40-60 Hz)",
                                                                 "> 70 Hz"]
    assert {t.get_fontsize() for t in leg.get_texts()} == {7}


def test_plot_title_without_quick(tmp_path):
    figures = {}
    savefig = Figure.savefig

    def recording(self, fname, *args, **kwargs):
        figures[Path(str(fname)).name] = self
        return savefig(self, fname, *args, **kwargs)

    runs = _runs()
    # a predictor of the user's without a style: matplotlib's defaults
    mine = PredictorRun(**{**runs.runs["oracle"].__dict__, "name": "my-own"})
    small = ClosedLoopRuns(**{**runs.__dict__, "runs": {"none": runs.runs["none"],
                                                        "my-own": mine}})
    mp = pytest.MonkeyPatch()
    mp.setattr(Figure, "savefig", recording)
    try:
        paths = fig3.plot(fig3.compute(small), tmp_path)
    finally:
        mp.undo()
    assert paths == [tmp_path / "fig3_sr_spectrum.png", tmp_path / "fig3_sr_spectrum.pdf"]
    (ax,) = figures["fig3_sr_spectrum.png"].axes
    assert ax.get_title() == "Figure 3: SR-peak oscillations after loop closure (Welch)"
    assert [ln.get_label() for ln in ax.get_lines()[:2]] == ["no prediction", "my-own"]


def _with_powers(runs, p50, phigh):
    # band powers written by hand: 55 / 50 and 11 / 10 are the double nearest 1.1
    return fig3.Figure3(runs=runs, power_50=p50, power_high=phigh)


def test_amplified_is_strictly_above_1_1_in_either_band():
    runs = _runs()
    keep = ClosedLoopRuns(**{**runs.__dict__, "runs": {k: runs.runs[k]
                                                       for k in ("none", "oracle")}})
    for p50, phigh in (((50.0, 55.0), (10.0, 10.0)), ((50.0, 50.0), (10.0, 11.0))):
        f = _with_powers(keep, dict(zip(("none", "oracle"), p50, strict=True)),
                         dict(zip(("none", "oracle"), phigh, strict=True)))
        assert "Of the 1 runs that keep the loop, 0 raise the power" in fig3.report(f)
    # amplified at ~50 Hz only (x1.5), then above 70 Hz only
    for p50, phigh in (((50.0, 75.0), (10.0, 10.0)), ((50.0, 50.0), (10.0, 15.0))):
        f = _with_powers(keep, dict(zip(("none", "oracle"), p50, strict=True)),
                         dict(zip(("none", "oracle"), phigh, strict=True)))
        assert ("Of the 1 runs that keep the loop, 1 raise the power in at least one band by "
                "more than 10 % (oracle (true future)).") in fig3.report(f)


def test_lists_of_several_runs():
    runs = _runs()
    lost = runs.runs["nn-paper"]
    nn = PredictorRun(**{**lost.__dict__, "name": "nn"})
    both = ClosedLoopRuns(**{**runs.__dict__, "runs": {"none": runs.runs["none"],
                                                       "linear": runs.runs["linear"],
                                                       "arma": runs.runs["arma"],
                                                       "nn-paper": lost, "nn": nn}})
    names = ("none", "linear", "arma", "nn-paper", "nn")
    # linear and ARMA as the paper says: reduced / damped at ~50 Hz, reduced above 70 Hz
    f = _with_powers(both, dict(zip(names, (40.0, 30.0, 10.0, 1.0, 1.0), strict=True)),
                     dict(zip(names, (40.0, 30.0, 30.0, 1.0, 1.0), strict=True)))
    text = fig3.report(f)
    assert ("paper's description: linear (a=2, b=-1), ARMA(2,3). Of the 2 runs that keep "
            "the loop") in text
    assert ("an SR near zero): NN (paper, 10 patterns), NN 10-10-1, 2000 patterns. The "
            "SR-peak") in text


def test_spectral_peak_strictly_above_20_hz():
    runs = _runs()
    f = np.array([0.0, 10.0, 20.0, 20.75, 30.0])
    none = PredictorRun(**{**runs.runs["none"].__dict__, "spectrum_freqs": f,
                           "spectrum_psd": np.array([5.0, 9.0, 8.0, 7.0, 1.0])})
    text = fig3.report(fig3.compute(ClosedLoopRuns(**{**runs.__dict__,
                                                      "runs": {"none": none}})))
    assert "spectrum peaks at 21 Hz." in text
