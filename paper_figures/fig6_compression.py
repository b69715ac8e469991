"""Figure 6 (not in the paper): compression x prediction, the study its conclusion proposes.

The paper ends by proposing to combine its two results: an MI-ordered basis so that the
fewest modes carry the wavefront, and prediction to beat the loop delay, compressing the
basis also to save real-time computation. Here, in the closed loop of the ``kaos`` preset
(single conjugate, 0.7 m, 27 Zernike modes, 2 kHz; :mod:`closedloop.presets`), every
ordering of :data:`closedloop.studies.compression.ORDERINGS` controls only its first ``n``
modes, without prediction and with the best of the predictors screened on the loop
that controls every mode (:func:`closedloop.studies.compression.predictor_screen`), for a
range of ``n``; then the loop delay is modelled as readout + compute(n)
with the measured cost of our reconstruction and prediction
(:class:`closedloop.studies.compression.LatencyModel`).

Panels: (a) SR peak and (b) field-averaged SR against ``n`` for every ordering, solid
without and dashed with prediction (fixed delay); (c) the measured real-time step time
against ``n``, for the preset's sizes and for larger synthetic systems, with the frame
period and the simulator's delay resolution.

Usage::

    python -m paper_figures.fig6_compression [--out DIR] [--overwrite] [--quick]
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from modalinfo.common.cli import Parser
from paper_figures._common import save_png_pdf, write_figure

FIGURE_NAME = "fig6_compression.png"
PDF_NAME = "fig6_compression.pdf"
NEEDS_RUNS = False
#: Figure 6 runs its own loops: it needs neither the shared runs nor a log
NEEDS_LOG = False

PRESET = "kaos"
#: predictors screened on the all-mode loop; the study uses the best of them
CANDIDATES = ("linear", "arma", "multivariate")
QUICK_CANDIDATES = ("linear", "multivariate")
VAR = "multivariate"
N_VALUES = (3, 6, 10, 15, 21, 27)
QUICK_N_VALUES = (6, 27)
QUICK_ORDERINGS = ("zernike", "kl", "kl-mi", "pca")
DURATION = 0.6          # s: 1200 frames, enough to fit a VAR(4) on 27 modes after 15 ms
QUICK_DURATION = 0.6
SCALING_N = (27, 50, 100, 200, 400)
QUICK_SCALING_N = (27, 60)
#: the sensitivity to the RTC's speed (the paper leaves it open): an RTC this much slower
#: than this machine running our code, on two orderings and three mode counts
SLOW_RTC_SPEED = 0.1
SLOW_ORDERINGS = ("zernike", "pca")
SLOW_N_VALUES = (6, 15, 27)
SR_FRACTION = 0.9       # "modes needed": SR peak within this fraction of all modes'

STYLES = {
    "zernike": {"color": "b", "marker": "o"},
    "kl": {"color": "g", "marker": "s"},
    "zernike-mi": {"color": "r", "marker": "^"},
    "kl-mi": {"color": "orange", "marker": "v"},
    "pca": {"color": "k", "marker": "D"},
}


@dataclass(frozen=True)
class Figure6:
    """The study and the measured cost scaling.

    Attributes
    ----------
    study : closedloop.studies.compression.CompressionStudy
    screen : dict
        Predictor name -> mean SR peak on the loop that controls every mode (with
        ``"none"`` and ``"oracle"``); the study's predictor is the best screened one.
    scaling_n : (K,) int ndarray
        Mode counts of the synthetic cost measurement.
    scaling_time : dict
        ``"none"`` / predictor name -> ``(K,)`` measured RTC step time [s].
    slow_rtc : closedloop.studies.compression.CompressionStudy or None
        The same study with an RTC ``SLOW_RTC_SPEED`` times this machine's speed
        (None with ``quick``).
    quick : bool
    elapsed : float
        Wall time of the computation [s].
    """

    study: object
    screen: dict
    scaling_n: np.ndarray
    scaling_time: dict
    slow_rtc: object
    quick: bool
    elapsed: float

    # ------------------------------------------------------------ derived numbers
    def crossing(self, name: str, budget: float) -> float | None:
        """Modes at which the measured step time reaches ``budget`` [s].

        Log-log interpolation of the scaling measurement; None beyond the measured range.
        """
        t = self.scaling_time[name]
        n = self.scaling_n.astype(float)
        above = np.flatnonzero(t >= budget)
        if above.size == 0:
            return None
        k = int(above[0])
        if k == 0:
            return float(n[0])
        x0, x1 = np.log(n[k - 1]), np.log(n[k])
        y0, y1 = np.log(t[k - 1]), np.log(t[k])
        return float(np.exp(x0 + (np.log(budget) - y0) * (x1 - x0) / (y1 - y0)))

    def extrapolated_crossing(self, name: str, budget: float) -> float:
        """Like :meth:`crossing`, extending the last two measurements' power law."""
        within = self.crossing(name, budget)
        if within is not None:
            return within
        t = self.scaling_time[name]
        n = self.scaling_n.astype(float)
        slope = np.log(t[-1] / t[-2]) / np.log(n[-1] / n[-2])
        if slope <= 0:
            return float("inf")
        # in logarithms: times equal to timing noise (7.7618e-5 and 7.7622e-5 s at 6 and 27
        # modes on a loaded CI machine) give a slope of 3e-5 and a power of ~1e4, which
        # overflowed float64 (a RuntimeWarning, an error under the suite's filters)
        log_n = np.log(n[-1]) + np.log(budget / t[-1]) / slope
        return float(np.exp(log_n)) if log_n < np.log(np.finfo(float).max) else float("inf")

    def latency_binds(self) -> bool:
        """Whether any modelled delay differs from the preset's fixed delay."""
        s = self.study
        return any(np.any(d != s.latency.readout) for d in s.delay.values())


def compute(*, quick: bool = False, seed: int = 0, progress=None) -> Figure6:
    """Run the study on the ``kaos`` preset and measure the cost scaling."""
    from closedloop import LoopModel, presets, simulate
    from closedloop.studies.compression import (
        LatencyModel,
        compression_study,
        predictor_screen,
        rtc_scaling,
    )

    start = time.perf_counter()
    config = presets.get(PRESET)
    model = LoopModel(config)
    duration = QUICK_DURATION if quick else DURATION
    # one no-prediction all-mode run serves the screen and every study
    reference = simulate(config, duration, model=model, seed=seed, progress=False)
    screen = predictor_screen(config, QUICK_CANDIDATES if quick else CANDIDATES,
                              duration=duration, seed=seed, model=model, reference=reference)
    best = max((n for n in screen if n not in ("none", "oracle")), key=screen.get)
    study = compression_study(config, n_values=QUICK_N_VALUES if quick else N_VALUES,
                              duration=duration, predictor=best, seed=seed,
                              progress=progress, model=model, reference=reference,
                              **({"orderings": QUICK_ORDERINGS} if quick else {}))
    scaling_n = np.array(QUICK_SCALING_N if quick else SCALING_N)
    # the VAR(4) always: its n^2 step is where latency would start to bind
    scaling = {name: rtc_scaling(scaling_n, predictor=None if name == "none" else name)
               for name in dict.fromkeys(("none", best, VAR))}
    slow = None
    if not quick:
        slow = compression_study(config, n_values=SLOW_N_VALUES, duration=duration,
                                 predictor=best, seed=seed, progress=progress, model=model,
                                 orderings=SLOW_ORDERINGS, reference=reference,
                                 latency=LatencyModel(readout=config.loop.delay,
                                                      rtc_speed=SLOW_RTC_SPEED))
    return Figure6(study=study, screen=screen, scaling_n=scaling_n, scaling_time=scaling,
                   slow_rtc=slow, quick=quick, elapsed=time.perf_counter() - start)


def plot(fig6: Figure6, out_dir: Path) -> list[Path]:
    """Draw Figure 6 (PNG and PDF) into ``out_dir``."""
    # a Figure of its own, no backend switch: the caller's backend stays as it was
    # (round 45 PART a, G15); Figure.savefig draws with Agg all the same
    from matplotlib.figure import Figure

    from closedloop.studies.compression import ORDERINGS

    s = fig6.study
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(17, 4.8))
    axes = fig.subplots(1, 3)
    for ax, table, what in ((axes[0], s.strehl_peak, "SR peak over the field"),
                            (axes[1], s.strehl_field, "field-averaged SR")):
        for o in s.orderings:
            st = STYLES.get(o, {})
            ax.plot(s.n_values, table[(False, o, "none")], "-", label=ORDERINGS[o], **st)
            ax.plot(s.n_values, table[(False, o, s.predictor)], "--", color=st.get("color"),
                    lw=0.9)
            if fig6.latency_binds():
                ax.plot(s.n_values, table[(True, o, s.predictor)], ":",
                        color=st.get("color"), lw=0.9)
        slow = fig6.slow_rtc
        if slow is not None:
            tab = slow.strehl_peak if table is s.strehl_peak else slow.strehl_field
            for o in slow.orderings:
                ax.plot(slow.n_values, tab[(True, o, slow.predictor)], "x:",
                        color=STYLES.get(o, {}).get("color"), lw=0.9, ms=6)
        ax.set_xlabel("controlled modes n")
        ax.set_ylabel(f"{what} ({s.wavelength * 1e9:.0f} nm)")
        ax.set_ylim(0, None)
    axes[0].plot([], [], "k--", lw=0.9, label=f"dashed: with {s.predictor} prediction")
    if fig6.slow_rtc is not None:
        axes[0].plot([], [], "kx:", lw=0.9,
                     label=f"x: with prediction, RTC x{fig6.slow_rtc.latency.rtc_speed:g}")
    axes[0].legend(fontsize=7)
    axes[0].set_title(f"(a) {s.config_name}: SR peak vs controlled modes")
    axes[1].set_title(f"(b) field average ({s.duration:g} s, seed {s.seed})")
    ax = axes[2]
    markers = ("o", "s", "^")
    for k, name in enumerate(fig6.scaling_time):
        what = "no prediction" if name == "none" else name
        color = f"C{k}"
        ax.loglog(fig6.scaling_n, fig6.scaling_time[name] * 1e6, markers[k] + "-",
                  color=color, label=f"synthetic sizes, {what}")
        if name in s.compute_time:
            ax.loglog(s.n_values, s.compute_time[name] * 1e6, markers[k], mfc="none",
                      color=color, label=f"{s.config_name} loop, {what}")
    ax.axhline(s.time_step * 1e6, color="0.3", lw=0.8)
    ax.text(fig6.scaling_n[0], s.time_step * 1e6, " one frame", fontsize=7, va="bottom")
    grid = s.time_step / s.latency.oversampling
    ax.axhline(grid / 2 * 1e6, color="0.6", lw=0.8, ls=":")
    ax.text(fig6.scaling_n[0], grid / 2 * 1e6, " adds a delay step", fontsize=7, va="bottom")
    ax.set_xlabel("controlled modes n")
    ax.set_ylabel("real-time step [us] (this machine)")
    ax.set_title("(c) measured real-time step vs n")
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save_png_pdf(fig, out_dir, FIGURE_NAME, PDF_NAME)


def _fmt_n(n) -> str:
    return "-" if n is None else str(n)


def synergy(fig6: Figure6, n: int) -> dict:
    """SR peak at ``n`` modes: standard Zernike alone, MI alone, prediction alone, both.

    The MI ordering is the better of the two MI orderings at ``n``; ``mi_own_base`` is
    the same basis in its own standard order (Zernike: Noll; K-L: variance), which
    separates what the MI ordering adds from what the change of basis adds.
    """
    s = fig6.study
    i = int(np.flatnonzero(s.n_values == n)[0])
    mi = max(("zernike-mi", "kl-mi"),
             key=lambda o: s.strehl_peak[(False, o, "none")][i] if o in s.orderings else -1)
    return {
        "n": n,
        "mi_ordering": mi,
        "baseline": s.strehl_peak[(False, "zernike", "none")][i],
        "mi_own_base": s.strehl_peak[(False, "zernike" if mi == "zernike-mi" else "kl",
                                      "none")][i],
        "mi": s.strehl_peak[(False, mi, "none")][i],
        "prediction": s.strehl_peak[(False, "zernike", s.predictor)][i],
        "both": s.strehl_peak[(False, mi, s.predictor)][i],
        "pca_both": s.strehl_peak[(False, "pca", s.predictor)][i],
    }


def table_rows(fig6: Figure6) -> list[tuple[str, str, str, str]]:
    """Rows ``(quantity, paper, ours, why)`` of the comparison table."""
    from closedloop.studies.compression import ORDERINGS

    s = fig6.study
    mid = int(s.n_values[len(s.n_values) // 2 - (1 if len(s.n_values) % 2 == 0 else 0)])
    syn = synergy(fig6, mid)
    gain_mi = syn["mi"] - syn["baseline"]
    gain_mi_own = syn["mi"] - syn["mi_own_base"]
    gain_pred = syn["prediction"] - syn["baseline"]
    gain_both = syn["both"] - syn["baseline"]
    best_o = max(s.orderings, key=lambda o: s.optimum(o, s.predictor, latency=True)[1])
    n_opt, sr_opt = s.optimum(best_o, s.predictor, latency=True)
    optima = {s.optimum(o, s.predictor, latency=True)[0] for o in s.orderings}
    where = ("every ordering" if len(optima) == 1 else ORDERINGS[best_o])
    cross = (fig6.extrapolated_crossing(VAR, s.time_step) if VAR in fig6.scaling_time
             else None)
    rows = [
        (f"MI ordering + prediction at n = {mid} modes (SR peak)",
         "proposed, not done",
         f"{syn['both']:.3f} (Zernike alone {syn['baseline']:.3f}, MI alone "
         f"{syn['mi']:.3f}, prediction alone {syn['prediction']:.3f})",
         f"MI order adds {gain_mi:+.3f}, prediction {gain_pred:+.3f}, both "
         f"{gain_both:+.3f} over standard Zernikes ({ORDERINGS[syn['mi_ordering']]}; "
         f"over the same basis in its standard order the MI order adds "
         f"{gain_mi_own:+.3f}): the gains "
         + ("add up" if abs(gain_both - gain_mi - gain_pred) < 0.25 * max(abs(gain_both), 1e-3)
            else "do not simply add")
         + f"; ordering dominates because the temporal error of this loop is small "
           f"(the data PCA order with prediction reaches {syn['pca_both']:.3f})"),
        ("optimum number of modes with the latency model", "proposed, not done",
         f"n = {n_opt} ({where}, SR peak {sr_opt:.3f})",
         ("the measured compute time of every n adds less than half a delay step "
          f"({s.time_step / s.latency.oversampling * 1e6:.1f} us), so the delay does not "
          "change and the optimum is all the modes" if not fig6.latency_binds() else
          "the modelled delay grows with n and moves the optimum")
         + (f"; a VAR(4) step would fill a {s.time_step * 1e3:g} ms frame at "
            f"{_about_modes(cross)}" if cross is not None else "")),
    ]
    return rows


def _about_modes(n: float) -> str:
    """``about N modes``, or what an infinite extrapolation means."""
    if math.isfinite(n):
        return f"about {n:.0f} modes"
    return "no number of modes (the last two sizes' step times do not grow measurably)"


def report(fig6: Figure6) -> str:
    """Figure 6's section of the report (Markdown)."""
    from closedloop.studies.compression import ORDERINGS

    s = fig6.study
    def sr_table(table, extra=None) -> list[str]:
        # "no prediction / with prediction" per n, one row per ordering
        head = "| ordering | " + " | ".join(f"n={n}" for n in s.n_values) + " |"
        rule = "|---|" + "---|" * len(s.n_values)
        if extra:
            head, rule = head + f" {extra[0]} |", rule + "---|"
        out = [head, rule]
        for o in s.orderings:
            cells = [f"{a:.3f} / {b:.3f}" for a, b in zip(table[(False, o, "none")],
                                                          table[(False, o, s.predictor)],
                                                          strict=True)]
            out.append(f"| {ORDERINGS[o]} | " + " | ".join(cells) + " |"
                       + (f" {extra[1](o)} |" if extra else ""))
        return out

    lines = sr_table(s.strehl_peak, (f"modes for {SR_FRACTION:.0%} of all-mode SR",
                                     lambda o: _fmt_n(s.modes_to_reach(SR_FRACTION, o))))
    field_lines = sr_table(s.strehl_field)
    comp = ", ".join(f"n={n}: {a * 1e6:.1f} / {b * 1e6:.1f} us" for n, a, b in
                     zip(s.n_values, s.compute_time["none"], s.compute_time[s.predictor],
                         strict=True))
    names = list(fig6.scaling_time)
    scal = ", ".join(f"n={n}: " + " / ".join(f"{fig6.scaling_time[k][i] * 1e6:.0f}"
                                             for k in names) + " us"
                     for i, n in enumerate(fig6.scaling_n))
    cross_frame = fig6.crossing(VAR, s.time_step)
    cross_step = fig6.crossing(VAR, s.time_step / s.latency.oversampling / 2)
    cross_none = fig6.crossing("none", s.time_step)
    rows = table_rows(fig6)
    latency_text = (
        "With the latency model every modelled delay equals the preset's "
        f"{s.latency.readout * 1e3:g} ms: our step costs at most "
        f"{max(v.max() for v in s.compute_time.values()) * 1e6:.1f} us for "
        f"{s.n_values[-1]} modes, below half of the simulator's "
        f"{s.time_step / s.latency.oversampling * 1e6:.1f} us delay step (the delay is "
        "rounded to that step), so the latency runs are "
        "the fixed-delay runs and the optimum n is where the SR curves peak."
        if not fig6.latency_binds() else
        "With the latency model the delay grows with n (dotted lines in a and b): "
        + ", ".join(f"{k}: {', '.join(f'{d * 1e3:.3f}' for d in v)} ms"
                    for k, v in s.delay.items()) + "." + _retuned_text(s))
    scale_text = (
        f"At larger sizes (synthetic reconstructor of 2 measurements per mode, the same "
        f"code): {scal} ({' / '.join('no prediction' if k == 'none' else k for k in names)})"
        ". The VAR(4) step grows as n^2 and "
        + (f"reaches half a delay step at about {cross_step:.0f} modes and a whole "
           f"{s.time_step * 1e3:g} ms frame at about {cross_frame:.0f} modes"
           if cross_frame is not None and cross_step is not None else
           f"stays below a frame over the measured range (the power law of the last two "
           f"sizes reaches a {s.time_step * 1e3:g} ms frame at "
           f"{_about_modes(fig6.extrapolated_crossing(VAR, s.time_step))})")
        + (f" (without prediction a frame is reached at about {cross_none:.0f} modes)"
           if cross_none is not None else
           " (without prediction it stays well below a frame)")
        + ": for DKIST/EST-class systems (over a thousand modes) compression would pay "
          "for prediction's latency, in a loop of KAOS's size it does not.")
    best = {(o, name): s.optimum(o, name, latency=True)
            for o in s.orderings for name in ("none", s.predictor)}
    screen_text = ", ".join(f"{k} {v:.4f}" for k, v in fig6.screen.items())
    slow_text = ""
    if fig6.slow_rtc is not None:
        w = fig6.slow_rtc
        delays = "; ".join(
            f"{'no prediction' if k == 'none' else k}: "
            + ", ".join(f"{d * 1e3:.4g}" for d in v) + " ms" for k, v in w.delay.items())
        moves = "; ".join(
            f"{ORDERINGS[o]}: "
            + ", ".join(
                f"n={n} {w.strehl_peak[(False, o, name)][i]:.3f} -> "
                f"{w.strehl_peak[(True, o, name)][i]:.3f}"
                for i, n in enumerate(w.n_values) for name in (w.predictor,))
            for o in w.orderings)
        gain = {o: w.strehl_peak[(True, o, w.predictor)] - w.strehl_peak[(True, o, "none")]
                for o in w.orderings}
        gains = "; ".join(f"{ORDERINGS[o]} n={n}: {gain[o][i]:+.3f}"
                          for o in w.orderings for i, n in enumerate(w.n_values))
        opt = ", ".join(f"{ORDERINGS[o]} n = {w.optimum(o, w.predictor, latency=True)[0]}"
                        for o in w.orderings)
        slow_text = (
            f"\n\n**How much this moves with the RTC's speed** (the paper leaves it open): "
            f"with an RTC {1 / w.latency.rtc_speed:g} times slower than this machine "
            f"running our code (rtc_speed {w.latency.rtc_speed:g}; crosses in panels a and b), "
            f"the modelled delays for n = {', '.join(map(str, w.n_values))} are {delays}. "
            f"SR peak with {w.predictor}, fixed delay -> slow RTC: {moves}. Prediction's gain "
            f"over no prediction with the same slow RTC: {gains}. Optimum n with prediction: "
            f"{opt}." + _retuned_text(w))
    quick_text = "(Quick settings: fewer orderings and mode counts.)" if fig6.quick else ""
    best_text = "; ".join(
        f"{ORDERINGS[o]}: n = {best[(o, 'none')][0]} (SR {best[(o, 'none')][1]:.3f}) / "
        f"n = {best[(o, s.predictor)][0]} (SR {best[(o, s.predictor)][1]:.3f})"
        for o in s.orderings)
    return f"""## Figure 6: compression x prediction (the study the paper proposes)

![Figure 6]({FIGURE_NAME})

Closed loop of the `{s.config_name}` preset (single conjugate, 27 Zernike modes, 2 kHz,
seed {s.seed}, {s.duration:g} s per run; SR at {s.wavelength * 1e9:.0f} nm averaged from
{s.window_start * 1e3:.1f} ms, after the loop closure and 15 ms, on the same frames for
every run) controlling only the first n modes of each ordering, computed from the POL of
a no-prediction run that controls every mode; the predictor ({s.predictor}) is the best
of those screened on the loop that controls every mode (mean SR peak: {screen_text}) and
is trained on the no-prediction run of the same subspace, as the paper trains.
{quick_text}

SR peak, no prediction / with {s.predictor} (fixed {s.latency.readout * 1e3:g} ms delay):

{chr(10).join(lines)}

Field-averaged SR (3x3 directions over 10"), no prediction / with {s.predictor}:

{chr(10).join(field_lines)}

**Latency model.** delay(n) = readout ({s.latency.readout * 1e3:g} ms, the preset's
delay) + compute(n) / rtc_speed, rounded to the simulator's step
{s.time_step / s.latency.oversampling * 1e6:.1f} us; compute(n) is the measured median
wall time of our real-time step for n modes on this machine (projected reconstructor
matrix-vector product, POL and integrator update, predictor update), rtc_speed = 1: the
real-time computer is a CPU core running this code (CPU real-time controllers such as
DARC serve AO up to 8 m class; Basden et al. 2010, Appl. Opt. 49, 6354). Measured
compute(n), no prediction / {s.predictor}: {comp}. {latency_text} Optimum n per ordering
with the latency model, no prediction / {s.predictor}: {best_text}.{slow_text}

{scale_text}

**Conclusion.** {rows[0][3][0].upper() + rows[0][3][1:]}. {rows[1][3][0].upper()
+ rows[1][3][1:]}. Of the orderings, the data PCA (the empirical K-L of the POL) needs
the fewest modes ({_fmt_n(s.modes_to_reach(SR_FRACTION, 'pca'))} for
{SR_FRACTION:.0%} of the all-mode SR peak, against
{_fmt_n(s.modes_to_reach(SR_FRACTION, 'zernike'))} for standard Zernikes); the MI orders
sit between the standard and the PCA order.

_(computed in {fig6.elapsed:.1f} s)_
"""


def make(out_dir: Path, *, quick: bool = False, seed: int = 0) -> str:
    """Compute, draw and report Figure 6."""
    fig6 = compute(quick=quick, seed=seed)
    plot(fig6, out_dir)
    return report(fig6)


def main(argv: list[str] | None = None) -> int:
    """Command line: draw the figure and print the report section."""
    parser = Parser(prog="python -m paper_figures.fig6_compression",
                                     description="Regenerate Figure 6 (compression x "
                                                 "prediction).")
    parser.add_argument("--out", type=Path, default=Path("out"), help="output directory")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing figure")
    parser.add_argument("--quick", action="store_true", help="fewer mode counts")
    args = parser.parse_args(argv)
    # under the lock python -m paper_figures takes; staged, all or nothing (left13-cli)
    return write_figure(args.out, [FIGURE_NAME, PDF_NAME], args.overwrite,
                        lambda stage: make(stage, quick=args.quick), parser.prog)


if __name__ == "__main__":
    sys.exit(main())


def _retuned_text(study) -> str:
    """Say which modelled delays ran with a lowered gain (``gain_for_delay``), if any."""
    retuned = getattr(study, "retuned_gain", None) or {}
    if not retuned:
        return ""
    pairs = ", ".join(f"{d * 1e3:.4g} ms: {g:.3f}" for d, g in sorted(retuned.items()))
    return (" At delays where the preset's gain is unstable the loop ran with the gain "
            "scaled to keep the preset's gain margin (gain x g_max(delay) / g_max(preset "
            f"delay)): {pairs}. The delays are measured on this machine, so a loaded "
            "machine's are longer.")
