"""Figure 3 of the paper: power spectra of the SR-peak oscillations after loop closure.

Paper (Stangalini et al., Section 3.4, Fig. 3): power spectra of the SR peak after the
loop closure, same line styles as Figure 2; "all three tools are able to reduce the
power of the oscillations for frequencies above 70 Hz"; "at low frequencies (~50 Hz)
only the ARMA and the NN approaches can damp out the SR oscillation power, while the
linear prediction can only reduce the amplitude".

Here: Welch spectra (:meth:`closedloop.SimulationResult.strehl_peak_spectrum`, Hann
windows of up to 256 frames, from each run's averaging window: its detected closure, or
its second half if it did not close, :attr:`closedloop.SimulationResult.averaging_start`;
the RMS and the error estimate below use the same frames) of the shared runs
(:mod:`paper_figures.closedloop_runs`), log-log, the paper's two bands shaded, and the
band powers (the PSD integrated over 40-60 Hz and over 70 Hz to Nyquist) of each
predictor relative to no prediction. Steps: :func:`compute`, :func:`plot`, :func:`report`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from paper_figures._common import save_png_pdf
from paper_figures.closedloop_runs import STYLES, ClosedLoopRuns

FIGURE_NAME = "fig3_sr_spectrum.png"
PDF_NAME = "fig3_sr_spectrum.pdf"
NEEDS_RUNS = True

# Stangalini et al., Sect. 3.4 (text on Fig. 3): the paper's two bands, "~50 Hz" and
# "above 70 Hz"; we read "~50 Hz" as 40-60 Hz
BAND_50 = (40.0, 60.0)
BAND_HIGH_MIN = 70.0
# what the paper says each predictor does to the oscillation power in each band
PAPER_50 = {"linear": "reduced", "arma": "damped", "nn-paper": "damped"}
PAPER_HIGH = {"linear": "reduced", "arma": "reduced", "nn-paper": "reduced"}


def band_power(freqs: np.ndarray, psd: np.ndarray, low: float, high: float) -> float:
    """Integral of ``psd`` over ``low <= f <= high`` (trapezoid on the Welch grid)."""
    sel = (freqs >= low) & (freqs <= high)
    if sel.sum() < 2:
        return float("nan")
    return float(np.trapezoid(psd[sel], freqs[sel]))


@dataclass(frozen=True)
class Figure3:
    """Band powers of the SR-peak oscillations per predictor (absolute and / none)."""

    runs: ClosedLoopRuns
    power_50: dict
    power_high: dict

    @property
    def ratio_50(self) -> dict:
        """Power at ~50 Hz over the no-prediction run's, per predictor."""
        return {k: v / self.power_50["none"] for k, v in self.power_50.items()}

    @property
    def ratio_high(self) -> dict:
        """Power above 70 Hz over the no-prediction run's, per predictor."""
        return {k: v / self.power_high["none"] for k, v in self.power_high.items()}


def compute(runs: ClosedLoopRuns) -> Figure3:
    """Band powers from the shared runs' Welch spectra."""
    p50, phigh = {}, {}
    for name, r in runs.runs.items():
        f, s = r.spectrum_freqs, r.spectrum_psd
        p50[name] = band_power(f, s, *BAND_50)
        phigh[name] = band_power(f, s, BAND_HIGH_MIN, float(f[-1]))
    return Figure3(runs=runs, power_50=p50, power_high=phigh)


def plot(fig3: Figure3, out_dir: Path) -> list[Path]:
    """Draw Figure 3 (PNG and PDF) into ``out_dir``."""
    # a Figure of its own, no backend switch: the caller's backend stays as it was
    # (round 45 PART a, G15); Figure.savefig draws with Agg all the same
    from matplotlib.figure import Figure

    runs = fig3.runs
    fig = Figure(figsize=(8, 4.8))
    ax = fig.subplots()
    for name, r in runs.runs.items():
        f, s = r.spectrum_freqs[1:], r.spectrum_psd[1:]
        style = dict(STYLES.get(name, {}))
        if style.get("linestyle") == "none":
            style["markersize"] = 4
        ax.loglog(f, s, label=r.label, **style)
    ax.axvspan(*BAND_50, color="orange", alpha=0.15, label="~50 Hz (40-60 Hz)")
    ax.axvspan(BAND_HIGH_MIN, runs.runs["none"].spectrum_freqs[-1], color="0.85",
               alpha=0.4, label="> 70 Hz")
    ax.axvline(50.0, color="orange", lw=0.8)
    ax.axvline(BAND_HIGH_MIN, color="0.5", lw=0.8)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD of the SR peak [1/Hz]")
    ax.set_title("Figure 3: SR-peak oscillations after loop closure (Welch)"
                 + (" (quick)" if runs.quick else ""))
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save_png_pdf(fig, out_dir, FIGURE_NAME, PDF_NAME)


#: a run whose mean SR peak falls below this fraction of no prediction's has lost the
#: loop: its "damped" oscillations are those of an SR near zero, not a better loop
DEGRADED = 0.5


def _degraded(fig3: Figure3, name: str) -> bool:
    runs = fig3.runs
    start = runs.runs["none"].window_start
    ref = np.mean(runs.runs["none"].strehl_peak[start:])
    return bool(np.mean(runs.runs[name].strehl_peak[start:]) < DEGRADED * ref)


def relative_error(fig3: Figure3, low: float, high: float) -> float:
    """Approximate relative standard error of a band power of the no-prediction run.

    A Welch estimate averages ``n_seg`` Hann segments at 50 % overlap (about
    ``n_seg`` independent ones) in each of the ``n_bins`` bins of the band: relative
    error about ``1 / sqrt(n_bins * n_seg)``, over the frames its spectrum used (from
    the run's averaging window, :attr:`PredictorRun.window_start`).
    """
    r = fig3.runs.runs["none"]
    n = r.times.size - r.window_start
    nper = min(n, 256)
    n_seg = 1 + (n - nper) // (nper // 2)
    f = r.spectrum_freqs
    n_bins = int(np.sum((f >= low) & (f <= high)))
    return 1.0 / np.sqrt(max(n_bins * n_seg, 1))


def _word(ratio: float) -> str:
    if not np.isfinite(ratio):
        return "n/a"
    if ratio < 0.5:
        return "damped"
    if ratio < 0.9:
        return "reduced"
    if ratio <= 1.1:
        return "unchanged"
    return "amplified"


def table_rows(fig3: Figure3) -> list[tuple[str, str, str, str]]:
    """Rows ``(quantity, paper, ours, why)``: band power relative to no prediction."""
    rows = []
    r50, rh = fig3.ratio_50, fig3.ratio_high
    none = fig3.runs.runs["none"]
    err50 = np.sqrt(2) * relative_error(fig3, *BAND_50)
    errh = np.sqrt(2) * relative_error(fig3, BAND_HIGH_MIN, float(none.spectrum_freqs[-1]))
    for name in fig3.runs.runs:
        if name == "none":
            continue
        label = fig3.runs.runs[name].label
        lost = _degraded(fig3, name)
        w50 = "loop lost" if lost else _word(r50[name])
        wh = "loop lost" if lost else _word(rh[name])
        for quantity, paper, ratio, word, err in (
                (f"SR oscillation power at ~50 Hz / none, {label}", PAPER_50.get(name, "-"),
                 r50[name], w50, err50),
                (f"SR oscillation power > 70 Hz / none, {label}", PAPER_HIGH.get(name, "-"),
                 rh[name], wh, errh)):
            if lost:
                why = "the loop was lost: the power is that of an SR near zero"
            elif paper == "-":
                why = "not in the paper"
            elif word == paper:
                why = "as in the paper"
            else:
                why = (f"ratio scatter without any effect about {err:.0%}; the oscillations "
                       "are of the whole residual (fitting, aliasing), not of the temporal "
                       "term prediction changes")
            rows.append((quantity, paper, f"{ratio:.2f} ({word})", why))
    return rows


def report(fig3: Figure3) -> str:
    """Figure 3's section of the report (Markdown)."""
    from paper_figures._common import markdown_table

    runs = fig3.runs
    none = runs.runs["none"]
    n_after = none.times.size - none.window_start
    df = float(none.spectrum_freqs[1] - none.spectrum_freqs[0])
    # over the frames of each run's spectrum (its averaging window)
    rms = {n: float(np.std(r.strehl_peak[r.window_start:])) for n, r in runs.runs.items()}
    rms_text = ", ".join(f"{runs.runs[n].label} {v:.4f}" + ("" if runs.runs[n].closed else
                                                          " (did not close: second half)")
                         for n, v in rms.items())
    matches = [n for n in PAPER_50 if n in runs.runs and not _degraded(fig3, n)
               and _word(fig3.ratio_50[n]) == PAPER_50[n]
               and _word(fig3.ratio_high[n]) == PAPER_HIGH[n]]
    err50 = relative_error(fig3, *BAND_50)
    errh = relative_error(fig3, BAND_HIGH_MIN, float(none.spectrum_freqs[-1]))
    ratio_err50, ratio_errh = np.sqrt(2) * err50, np.sqrt(2) * errh
    ok = [n for n in runs.runs if n != "none" and not _degraded(fig3, n)]
    amp = [n for n in ok if fig3.ratio_50[n] > 1.1 or fig3.ratio_high[n] > 1.1]
    amp_text = (f"Of the {len(ok)} runs that keep the loop, {len(amp)} raise the power in at "
                "least one band by more than 10 %"
                + (f" ({', '.join(runs.runs[n].label for n in amp)})." if amp else "."))
    lost = [n for n in runs.runs if n != "none" and _degraded(fig3, n)]
    lost_text = (("Lost the loop (mean SR peak below half of no prediction's; their low "
                  "band powers are those of an SR near zero): "
                  + ", ".join(runs.runs[n].label for n in lost) + ". ") if lost else "")
    matching = ", ".join(runs.runs[n].label for n in matches) or "none"
    sel = none.spectrum_freqs > 20.0
    f_peak = float(none.spectrum_freqs[sel][np.argmax(none.spectrum_psd[sel])]) if sel.any() \
        else float("nan")
    return f"""## Figure 3: power spectra of the SR-peak oscillations

![Figure 3]({FIGURE_NAME})

Welch spectra of the SR peak after the detected closure, or over the second half of a
run that did not close ({n_after} frames without prediction, resolution {df:.1f} Hz);
band power = the PSD integrated over
{BAND_50[0]:g}-{BAND_50[1]:g} Hz ("~50 Hz") and {BAND_HIGH_MIN:g} Hz to Nyquist ("above
70 Hz"), divided by the no-prediction run's. Words: < 0.5 damped, 0.5-0.9 reduced,
0.9-1.1 unchanged, > 1.1 amplified.

{markdown_table(table_rows(fig3))}

RMS of the SR peak after closure: {rms_text}. Above 20 Hz the no-prediction
spectrum peaks at {f_peak:.0f} Hz. Predictors whose behaviour in both bands matches the
paper's description: {matching}. {amp_text} Statistical precision: with {n_after}
frames the band powers carry a relative standard error of about {err50:.0%} (~50 Hz)
and {errh:.0%} (> 70 Hz), so their ratios can scatter by up to about {ratio_err50:.0%}
and {ratio_errh:.0%} (less: the runs share one atmosphere) without any effect.
{lost_text}The SR-peak oscillations are the fluctuations of the whole residual,
dominated by fitting and aliasing (Figure 2's budget), of which the temporal term that
prediction changes is a few per cent; the oracle, whose forecast is exact, changes the
band powers too, so these ratios measure how each control law reshapes the residual's
fluctuations, not the quality of the forecast. The paper gives no numbers for its
spectra, only the statements in the table.
"""


def make(out_dir: Path, runs: ClosedLoopRuns) -> str:
    """Compute, draw and report Figure 3 from the shared runs."""
    fig3 = compute(runs)
    plot(fig3, out_dir)
    return report(fig3)
