"""Figure 6 (compression x prediction) on a hand-made study: numbers, rows, report, axes.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all
outside the module:

- the study is written in this file: a ``CompressionStudy`` record whose SR tables are
  multiples of 1/8 (so every gain, optimum and "modes for 90 %" is exact and worked out
  by hand below), measured step times in whole microseconds, and synthetic cost curves
  that are exact power laws (``t = c n^2``: the log-log interpolation and the
  two-point extrapolation of :meth:`Figure6.crossing` are exact, e.g. 4e-8 n^2 reaches
  31.25 us at n = sqrt(781.25) = 27.95 and 0.5 ms at sqrt(12500) = 111.8);
- the module docstring's contract for :func:`compute` (the ``kaos`` preset, one
  no-prediction reference run shared by the screen and the studies, the best screened
  predictor other than "none" and "oracle", the VAR(4) always in the cost scaling, the
  slow-RTC study at ``rtc_speed`` 0.1 on two orderings), checked with recorders in
  place of the loops;
- the kaos frame (2 kHz: 0.5 ms) and the simulator's delay grid (8 steps per frame:
  62.5 us) for the lines of panel c, in microseconds;
- the figure read back from the ``Figure`` handed to ``savefig`` (panels, axis labels
  and units, the series drawn, line styles), and the report, the rows and the command
  line's messages written out here word for word.
No closed loop runs: ~4 s.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

import closedloop
import closedloop.studies.compression as comp
from closedloop.studies.compression import CompressionStudy, LatencyModel
from paper_figures import fig6_compression as fig6

ORDS = ("zernike", "kl", "zernike-mi", "kl-mi", "pca")
NAMES = {"zernike": "Zernike, standard order", "kl": "K-L (theory), variance order",
         "zernike-mi": "Zernike, MI order", "kl-mi": "K-L (theory), MI order",
         "pca": "data K-L (PCA of the POL)"}
N = np.array([3, 6, 10, 27])
PEAK = {  # (ordering, predictor) -> SR peak over N, fixed delay
    ("zernike", "none"): [0.125, 0.25, 0.375, 0.5], ("zernike", "arma"): [0.25, 0.375, 0.5, 0.625],
    ("kl", "none"): [0.25, 0.375, 0.5, 0.5], ("kl", "arma"): [0.375, 0.5, 0.625, 0.625],
    ("zernike-mi", "none"): [0.125, 0.375, 0.5, 0.5],
    ("zernike-mi", "arma"): [0.25, 0.5, 0.625, 0.625],
    ("kl-mi", "none"): [0.25, 0.5, 0.5, 0.5], ("kl-mi", "arma"): [0.375, 0.75, 0.625, 0.625],
    ("pca", "none"): [0.375, 0.5, 0.5, 0.5], ("pca", "arma"): [0.5, 0.625, 0.625, 0.625],
}
# with the latency model: the same, but PCA with ARMA peaks at 0.875 at n = 6
PCA_LATENCY = [0.5, 0.875, 0.625, 0.625]
STEP = 5e-4                 # kaos: 2 kHz
SCALING_N = np.array([27, 54, 108])


def _tables(field=False, pca_latency=PCA_LATENCY):
    shift = 0.125 if field else 0.0
    out = {}
    for (o, p), v in PEAK.items():
        out[(False, o, p)] = np.array(v) - shift
        out[(True, o, p)] = np.array(pca_latency if (o, p) == ("pca", "arma") else v) - shift
    return out


def _study(delay=None):
    return CompressionStudy(
        config_name="kaos", seed=3, duration=0.5, n_values=N.copy(), orderings=ORDS,
        predictor="arma", strehl_peak=_tables(), strehl_field=_tables(field=True),
        compute_time={"none": np.array([1.0, 2.0, 3.0, 4.0]) * 1e-6,
                      "arma": np.array([2.0, 4.0, 8.0, 16.0]) * 1e-6},
        delay=delay or {"none": np.full(4, STEP), "arma": np.full(4, STEP)},
        latency=LatencyModel(readout=STEP), time_step=STEP, window_start=0.0175,
        wavelength=500e-9)


def _slow():
    o2 = ("zernike", "pca")
    n = np.array([6, 15, 27])
    peak = {(False, "zernike", "arma"): np.array([0.375, 0.5, 0.625]),
            (True, "zernike", "arma"): np.array([0.25, 0.375, 0.5]),
            (True, "zernike", "none"): np.array([0.125, 0.5, 0.5]),
            (False, "pca", "arma"): np.array([0.5, 0.625, 0.75]),
            (True, "pca", "arma"): np.array([0.5, 0.75, 0.625]),
            (True, "pca", "none"): np.array([0.25, 0.5, 0.875])}
    field = {k: v - 0.125 for k, v in peak.items()}
    return CompressionStudy(
        config_name="kaos", seed=3, duration=0.5, n_values=n, orderings=o2,
        predictor="arma", strehl_peak=peak, strehl_field=field, compute_time={},
        delay={"none": np.array([5e-4, 5.625e-4, 6.25e-4]),
               "arma": np.array([5.625e-4, 6.25e-4, 7.5e-4])},
        latency=LatencyModel(readout=STEP, rtc_speed=0.1), time_step=STEP,
        window_start=0.0175, wavelength=500e-9)


def _figure(var=4e-8, study=None, slow=None, quick=False):
    scaling = {"none": 1e-6 * SCALING_N, "arma": 2e-8 * SCALING_N ** 2.0,
               "multivariate": var * SCALING_N ** 2.0}
    return fig6.Figure6(study=study or _study(), screen={"none": 0.5, "linear": 0.625,
                                                         "arma": 0.75, "oracle": 0.875},
                        scaling_n=SCALING_N, scaling_time=scaling, slow_rtc=slow,
                        quick=quick, elapsed=12.25)


def test_constants():
    assert (fig6.FIGURE_NAME, fig6.PDF_NAME) == ("fig6_compression.png", "fig6_compression.pdf")
    assert fig6.NEEDS_RUNS is False and fig6.NEEDS_LOG is False
    assert fig6.PRESET == "kaos" and fig6.VAR == "multivariate"
    assert fig6.CANDIDATES == ("linear", "arma", "multivariate")
    assert fig6.QUICK_CANDIDATES == ("linear", "multivariate")
    assert fig6.N_VALUES == (3, 6, 10, 15, 21, 27) and fig6.QUICK_N_VALUES == (6, 27)
    assert fig6.QUICK_ORDERINGS == ("zernike", "kl", "kl-mi", "pca")
    assert (fig6.DURATION, fig6.QUICK_DURATION) == (0.6, 0.6)     # 1200 frames at 2 kHz
    assert fig6.SCALING_N == (27, 50, 100, 200, 400) and fig6.QUICK_SCALING_N == (27, 60)
    assert (fig6.SLOW_RTC_SPEED, fig6.SLOW_ORDERINGS, fig6.SLOW_N_VALUES) == (
        0.1, ("zernike", "pca"), (6, 15, 27))
    assert fig6.SR_FRACTION == 0.9
    assert set(fig6.STYLES) == set(NAMES)


def test_crossing_on_power_laws():
    f = _figure()
    # 4e-8 n^2 reaches 31.25 us (half a delay step) at n = sqrt(781.25)
    assert f.crossing("multivariate", 31.25e-6) == pytest.approx(math.sqrt(781.25), rel=1e-12)
    assert type(f.crossing("multivariate", 31.25e-6)) is float
    # reached at the first size: that size; exactly at a measured point: that point
    assert f.crossing("multivariate", 1e-6) == 27.0
    assert f.crossing("none", 54e-6) == pytest.approx(54.0, rel=1e-12)
    # beyond the measured sizes: None; extrapolated along the last two points' law
    assert f.crossing("multivariate", STEP) is None
    assert f.extrapolated_crossing("multivariate", STEP) == pytest.approx(
        math.sqrt(12500.0), rel=1e-12)
    assert f.extrapolated_crossing("none", 1e-3) == pytest.approx(1000.0, rel=1e-12)
    assert f.extrapolated_crossing("multivariate", 31.25e-6) == pytest.approx(
        math.sqrt(781.25), rel=1e-12)
    # a cost that does not grow never reaches the budget
    flat = dataclasses.replace(f, scaling_time={"none": np.array([3e-6, 2e-6, 2e-6])})
    assert flat.extrapolated_crossing("none", 1e-3) == math.inf
    falling = dataclasses.replace(f, scaling_time={"none": np.array([3e-6, 2e-6, 1e-6])})
    assert falling.extrapolated_crossing("none", 1e-3) == math.inf
    # a growth within timing noise (CI of stop 52: 7.7618176e-05 s at 6 modes, 7.7622524e-05
    # at 27): n (budget / t)^(1 / slope) is beyond float64, no overflow warning (an error
    # under the suite's filters); exp(log) by hand: ln n = ln 27 + ln(5e-4 / t1) / slope
    noisy = dataclasses.replace(f, scaling_n=np.array([6, 27]),
                                scaling_time={"none": np.array([7.7618176e-05, 7.7622524e-05])})
    slope = math.log(7.7622524e-05 / 7.7618176e-05) / math.log(27 / 6)
    assert math.log(27) + math.log(5e-4 / 7.7622524e-05) / slope > 710  # beyond float64
    assert noisy.extrapolated_crossing("none", 5e-4) == math.inf
    # the report does not print "about inf modes"
    assert fig6._about_modes(math.inf).startswith("no number of modes")
    assert fig6._about_modes(431.6) == "about 432 modes"
    # a power law still in range keeps its value (n = 27 * 4^(1 / 0.5) = 432)
    steep = dataclasses.replace(f, scaling_n=np.array([6, 27]),
                                scaling_time={"none": np.array([1e-5, 1e-5 * 1.5])})
    slope = math.log(1.5) / math.log(27 / 6)
    assert steep.extrapolated_crossing("none", 6e-5) == pytest.approx(
        27 * (6e-5 / 1.5e-5) ** (1 / slope), rel=1e-12)


def test_extrapolation_only_beyond_the_measured_sizes():
    # not a power law: 27, 54, 216 us at 27, 54, 108 modes (slope 1, then 2); 40 us is
    # reached within the first segment, at 40 modes (the last two points' law: 46.5)
    f = _figure()
    f = dataclasses.replace(f, scaling_time={"none": np.array([27.0, 54.0, 216.0]) * 1e-6})
    assert f.extrapolated_crossing("none", 40e-6) == pytest.approx(40.0, rel=1e-12)


def test_synergy_reads_the_fixed_delay_runs():
    # the latency-model tables zeroed: the synergy of the fixed-delay runs is unchanged
    study = _study()
    peak = {k: (v * 0.0 if k[0] else v) for k, v in study.strehl_peak.items()}
    f = _figure(study=dataclasses.replace(study, strehl_peak=peak))
    assert fig6.synergy(f, 6) == fig6.synergy(_figure(), 6)
    assert fig6.synergy(f, 6)["mi_ordering"] == "kl-mi"


def test_latency_binds_only_when_a_delay_differs():
    assert _figure().latency_binds() is False
    bind = {"none": np.full(4, STEP), "arma": np.array([STEP, STEP, STEP, 5.625e-4])}
    assert _figure(study=_study(delay=bind)).latency_binds() is True
    bind = {"none": np.array([4.375e-4, STEP, STEP, STEP]), "arma": np.full(4, STEP)}
    assert _figure(study=_study(delay=bind)).latency_binds() is True


def test_synergy_at_six_modes():
    assert fig6.synergy(_figure(), 6) == {
        "n": 6, "mi_ordering": "kl-mi", "baseline": 0.25, "mi_own_base": 0.375, "mi": 0.5,
        "prediction": 0.375, "both": 0.75, "pca_both": 0.625}
    # at 3 modes Zernike MI and K-L MI tie at... no: 0.125 < 0.25, K-L MI again; at 10
    # modes they tie (0.5): the first, Zernike MI, over the Zernike basis
    s = fig6.synergy(_figure(), 10)
    assert (s["mi_ordering"], s["mi_own_base"], s["both"]) == ("zernike-mi", 0.375, 0.625)
    # without the K-L MI ordering
    study = dataclasses.replace(_study(), orderings=("zernike", "kl", "zernike-mi", "pca"))
    assert fig6.synergy(_figure(study=study), 6)["mi_ordering"] == "zernike-mi"
    assert fig6._fmt_n(None) == "-" and fig6._fmt_n(27) == "27"


ROW0 = ("MI ordering + prediction at n = 6 modes (SR peak)", "proposed, not done",
        "0.750 (Zernike alone 0.250, MI alone 0.500, prediction alone 0.375)",
        "MI order adds +0.250, prediction +0.125, both +0.500 over standard Zernikes (K-L "
        "(theory), MI order; over the same basis in its standard order the MI order adds "
        "+0.125): the gains do not simply add; ordering dominates because the temporal "
        "error of this loop is small (the data PCA order with prediction reaches 0.625)")
ROW1_WHY = ("the measured compute time of every n adds less than half a delay step "
            "(62.5 us), so the delay does not change and the optimum is all the modes; a "
            "VAR(4) step would fill a 0.5 ms frame at about 112 modes")


def test_table_rows_word_for_word():
    assert fig6.table_rows(_figure()) == [
        ROW0, ("optimum number of modes with the latency model", "proposed, not done",
               "n = 6 (data K-L (PCA of the POL), SR peak 0.875)", ROW1_WHY)]


def test_table_rows_branches():
    # gains that add up: both = 0.75 - 0.25 = 0.5 = MI 0.25 + prediction 0.25
    peak = _tables()
    peak[(False, "zernike", "arma")] = np.array([0.25, 0.5, 0.5, 0.625])
    study = dataclasses.replace(_study(), strehl_peak=peak)
    (row0, row1) = fig6.table_rows(_figure(study=study))
    assert "the gains add up;" in row0[3]
    # one optimum for every ordering, a binding delay, no VAR(4) measured
    flat = _tables(pca_latency=PEAK[("pca", "arma")])
    for o in ORDS:
        flat[(True, o, "arma")] = np.array([0.25, 0.375, 0.5, 0.625])
    bind = {"none": np.full(4, STEP), "arma": np.array([STEP, STEP, 5.625e-4, 6.25e-4])}
    f = _figure(study=dataclasses.replace(_study(delay=bind), strehl_peak=flat))
    f = dataclasses.replace(f, scaling_time={k: v for k, v in f.scaling_time.items()
                                             if k != "multivariate"})
    (_, row1) = fig6.table_rows(f)
    assert row1[2] == "n = 27 (every ordering, SR peak 0.625)"
    # the same n for every ordering at different SRs: still "every ordering"
    for k, o in enumerate(ORDS):
        flat[(True, o, "arma")] = np.array([0.125, 0.25, 0.375, 0.5 + 0.125 * k])
    f2 = dataclasses.replace(f, study=dataclasses.replace(f.study, strehl_peak=flat))
    assert fig6.table_rows(f2)[1][2] == "n = 27 (every ordering, SR peak 1.000)"
    assert row1[3] == "the modelled delay grows with n and moves the optimum"
    # an odd number of mode counts: the middle one
    study = dataclasses.replace(_study(), n_values=np.array([3, 6, 10]),
                                strehl_peak={k: v[:3] for k, v in _tables().items()})
    assert fig6.table_rows(_figure(study=study))[0][0] == (
        "MI ordering + prediction at n = 6 modes (SR peak)")
    # five counts: the third
    study = dataclasses.replace(_study(), n_values=np.array([3, 6, 10, 27, 40]),
                                strehl_peak={k: np.append(v, v[-1])
                                             for k, v in _tables().items()})
    assert fig6.table_rows(_figure(study=study))[0][0].startswith(
        "MI ordering + prediction at n = 10 modes")


def _sr_table(shift, extra):
    head = "| ordering | n=3 | n=6 | n=10 | n=27 |" + (" modes for 90% of all-mode SR |"
                                                       if extra else "")
    rule = "|---|---|---|---|---|" + ("---|" if extra else "")
    rows = [head, rule]
    modes = {"zernike": 27, "kl": 10, "zernike-mi": 10, "kl-mi": 6, "pca": 6}
    for o in ORDS:
        cells = " | ".join(f"{a - shift:.3f} / {b - shift:.3f}"
                           for a, b in zip(PEAK[(o, "none")], PEAK[(o, "arma")], strict=True))
        rows.append(f"| {NAMES[o]} | {cells} |" + (f" {modes[o]} |" if extra else ""))
    return "\n".join(rows)


def _expected_report(quick=False, latency=None, scale=None, slow=""):
    latency = latency or (
        "With the latency model every modelled delay equals the preset's 0.5 ms: our step "
        "costs at most 16.0 us for 27 modes, below half of the simulator's 62.5 us delay "
        "step (the delay is rounded to that step), so the latency runs are the fixed-delay "
        "runs and the optimum n is where the "
        "SR curves peak.")
    scale = scale or (
        "At larger sizes (synthetic reconstructor of 2 measurements per mode, the same "
        "code): n=27: 27 / 15 / 29 us, n=54: 54 / 58 / 117 us, n=108: 108 / 233 / 467 us "
        "(no prediction / arma / multivariate). The VAR(4) step grows as n^2 and stays "
        "below a frame over the measured range (the power law of the last two sizes "
        "reaches a 0.5 ms frame at about 112 modes) (without prediction it stays well "
        "below a frame): for DKIST/EST-class systems (over a thousand modes) compression "
        "would pay for prediction's latency, in a loop of KAOS's size it does not.")
    best = ("Zernike, standard order: n = 27 (SR 0.500) / n = 27 (SR 0.625); K-L (theory), "
            "variance order: n = 10 (SR 0.500) / n = 10 (SR 0.625); Zernike, MI order: n = 10 "
            "(SR 0.500) / n = 10 (SR 0.625); K-L (theory), MI order: n = 6 (SR 0.500) / n = 6 "
            "(SR 0.750); data K-L (PCA of the POL): n = 6 (SR 0.500) / n = 6 (SR 0.875)")
    quick_text = "(Quick settings: fewer orderings and mode counts.)" if quick else ""
    return f"""## Figure 6: compression x prediction (the study the paper proposes)

![Figure 6](fig6_compression.png)

Closed loop of the `kaos` preset (single conjugate, 27 Zernike modes, 2 kHz,
seed 3, 0.5 s per run; SR at 500 nm averaged from
17.5 ms, after the loop closure and 15 ms, on the same frames for
every run) controlling only the first n modes of each ordering, computed from the POL of
a no-prediction run that controls every mode; the predictor (arma) is the best
of those screened on the loop that controls every mode (mean SR peak: none 0.5000, \
linear 0.6250, arma 0.7500, oracle 0.8750) and
is trained on the no-prediction run of the same subspace, as the paper trains.
{quick_text}

SR peak, no prediction / with arma (fixed 0.5 ms delay):

{_sr_table(0.0, True)}

Field-averaged SR (3x3 directions over 10"), no prediction / with arma:

{_sr_table(0.125, False)}

**Latency model.** delay(n) = readout (0.5 ms, the preset's
delay) + compute(n) / rtc_speed, rounded to the simulator's step
62.5 us; compute(n) is the measured median
wall time of our real-time step for n modes on this machine (projected reconstructor
matrix-vector product, POL and integrator update, predictor update), rtc_speed = 1: the
real-time computer is a CPU core running this code (CPU real-time controllers such as
DARC serve AO up to 8 m class; Basden et al. 2010, Appl. Opt. 49, 6354). Measured
compute(n), no prediction / arma: n=3: 1.0 / 2.0 us, n=6: 2.0 / 4.0 us, n=10: 3.0 / 8.0 \
us, n=27: 4.0 / 16.0 us. {latency} Optimum n per ordering
with the latency model, no prediction / arma: {best}.{slow}

{scale}

**Conclusion.** {ROW0[3]}. The{fig6.table_rows(_figure())[1][3][3:]}. Of the \
orderings, the data PCA (the empirical K-L of the POL) needs
the fewest modes (6 for
90% of the all-mode SR peak, against
27 for standard Zernikes); the MI orders
sit between the standard and the PCA order.

_(computed in 12.2 s)_
"""


def test_report_word_for_word():
    assert fig6.report(_figure()) == _expected_report()
    assert fig6.report(_figure(quick=True)) == _expected_report(quick=True)


def test_report_crossings_within_the_range():
    # 5e-8 n^2: half a delay step (31.25 us) at n = 25 -> below the first size: 27;
    # a 0.5 ms frame at n = 100 (within 54 .. 108); without prediction: 1e-5 n reaches
    # the frame within the range at 50 modes when the frame is 0.5 ms
    f = _figure(var=5e-8)
    f = dataclasses.replace(f, scaling_time={**f.scaling_time,
                                             "none": 1e-5 * SCALING_N.astype(float)})
    text = fig6.report(f)
    assert ("The VAR(4) step grows as n^2 and reaches half a delay step at about 27 modes "
            "and a whole 0.5 ms frame at about 100 modes (without prediction a frame is "
            "reached at about 50 modes): for DKIST") in text


def test_report_half_a_delay_step_between_measured_sizes():
    # not a power law: the VAR(4) step 20, 100, 600 us at 27, 54, 108 modes; between two
    # sizes the cost follows the power law through them: n = n0 (t / t0)^(ln 2 / ln(t1/t0))
    f = _figure()
    f = dataclasses.replace(f, scaling_time={**f.scaling_time, "multivariate":
                                             np.array([20.0, 100.0, 600.0]) * 1e-6})
    half = 27 * (31.25 / 20) ** (math.log(2) / math.log(5))        # 32.7: half a step
    frame = 54 * (500 / 100) ** (math.log(2) / math.log(6))       # 100.7: one frame
    assert (f"{half:.0f}", f"{frame:.0f}") == ("33", "101")
    assert (f"reaches half a delay step at about {half:.0f} modes and a whole 0.5 ms frame "
            f"at about {frame:.0f} modes") in fig6.report(f)


def test_report_tables_are_the_fixed_delay_runs():
    # the latency-model tables zeroed: the two SR tables of the report are unchanged
    study = _study()
    zero = {k: (v * 0.0 if k[0] else v) for k, v in study.strehl_peak.items()}
    zero_f = {k: (v * 0.0 if k[0] else v) for k, v in study.strehl_field.items()}
    text = fig6.report(_figure(study=dataclasses.replace(study, strehl_peak=zero,
                                                         strehl_field=zero_f)))
    assert _sr_table(0.0, True) in text and _sr_table(0.125, False) in text


def test_report_binding_latency_and_slow_rtc():
    bind = {"none": np.full(4, STEP), "arma": np.array([STEP, STEP, 6.25e-4, 7.5e-4])}
    text = fig6.report(_figure(study=_study(delay=bind), slow=_slow()))
    assert ("With the latency model the delay grows with n (dotted lines in a and b): "
            "none: 0.500, 0.500, 0.500, 0.500 ms, arma: 0.500, 0.500, 0.625, 0.750 ms. "
            "Optimum n per ordering") in text
    slow = ("\n\n**How much this moves with the RTC's speed** (the paper leaves it open): "
            "with an RTC 10 times slower than this machine running our code (rtc_speed 0.1; "
            "crosses in panels a and b), the modelled delays for n = 6, 15, 27 are no "
            "prediction: 0.5, 0.5625, 0.625 ms; arma: 0.5625, 0.625, 0.75 ms. SR peak with "
            "arma, fixed delay -> slow RTC: Zernike, standard order: n=6 0.375 -> 0.250, "
            "n=15 0.500 -> 0.375, n=27 0.625 -> 0.500; data K-L (PCA of the POL): n=6 0.500 "
            "-> 0.500, n=15 0.625 -> 0.750, n=27 0.750 -> 0.625. Prediction's gain over no "
            "prediction with the same slow RTC: Zernike, standard order n=6: +0.125; "
            "Zernike, standard order n=15: -0.125; Zernike, standard order n=27: +0.000; "
            "data K-L (PCA of the POL) n=6: +0.250; data K-L (PCA of the POL) n=15: +0.250; "
            "data K-L (PCA of the POL) n=27: -0.250. Optimum n with prediction: Zernike, "
            "standard order n = 27, data K-L (PCA of the POL) n = 15.\n\n")
    assert slow in text


# ---- compute with recorders --------------------------------------------------------------

class _Recorder:
    def __init__(self, result):
        self.calls = []
        self.result = result

    def __call__(self, *args, **kwargs):
        self.calls.append((args, kwargs))
        return self.result(*args, **kwargs) if callable(self.result) else self.result


@pytest.mark.parametrize("quick", [False, True])
def test_compute_contract(monkeypatch, quick):
    model, reference = object(), object()
    loop_model = _Recorder(model)
    sim = _Recorder(reference)
    screen = _Recorder({"none": 0.5, "linear": 0.625, "arma": 0.75, "multivariate": 0.5,
                        "oracle": 0.875})
    studies, made = [], (_study(), _slow())

    def study(*args, **kwargs):
        studies.append((args, kwargs))
        return made[len(studies) - 1]

    scaling = _Recorder(lambda n, predictor=None: np.asarray(n, float) * 1e-6)
    monkeypatch.setattr(closedloop, "LoopModel", loop_model)
    monkeypatch.setattr(closedloop, "simulate", sim)
    monkeypatch.setattr(comp, "predictor_screen", screen)
    monkeypatch.setattr(comp, "compression_study", study)
    monkeypatch.setattr(comp, "rtc_scaling", scaling)
    import time
    t0 = time.perf_counter()
    f = fig6.compute(quick=quick, seed=4, progress="p")
    wall = time.perf_counter() - t0
    cfg = closedloop.presets.get("kaos")
    ((cfg_a,), kw), = loop_model.calls
    assert cfg_a == cfg and kw == {}
    ((cfg_b, duration), kw), = sim.calls
    assert cfg_b == cfg and duration == 0.6
    assert kw == {"model": model, "seed": 4, "progress": False}
    ((cfg_c, cands), kw), = screen.calls
    assert cfg_c == cfg
    assert cands == (("linear", "multivariate") if quick else ("linear", "arma", "multivariate"))
    assert kw == {"duration": 0.6, "seed": 4, "model": model, "reference": reference}
    # the best screened predictor: arma (0.75), not the oracle (0.875)
    assert f.screen == screen.result and f.study is made[0]
    (args, kw) = studies[0]
    expected = {"n_values": (6, 27) if quick else (3, 6, 10, 15, 21, 27), "duration": 0.6,
                "predictor": "arma", "seed": 4, "progress": "p", "model": model,
                "reference": reference}
    if quick:
        expected["orderings"] = ("zernike", "kl", "kl-mi", "pca")
    assert args == (cfg,) and kw == expected
    assert [c[1]["predictor"] for c in scaling.calls] == [None, "arma", "multivariate"]
    n = (27, 60) if quick else (27, 50, 100, 200, 400)
    for (a, _) in scaling.calls:
        np.testing.assert_array_equal(a[0], n)
    np.testing.assert_array_equal(f.scaling_n, n)
    assert list(f.scaling_time) == ["none", "arma", "multivariate"]
    np.testing.assert_array_equal(f.scaling_time["arma"], np.array(n) * 1e-6)
    if quick:
        assert len(studies) == 1 and f.slow_rtc is None
    else:
        (args, kw) = studies[1]
        assert args == (cfg,)
        assert kw == {"n_values": (6, 15, 27), "duration": 0.6, "predictor": "arma",
                      "seed": 4, "progress": "p", "model": model,
                      "orderings": ("zernike", "pca"), "reference": reference,
                      "latency": LatencyModel(readout=cfg.loop.delay, rtc_speed=0.1)}
        assert f.slow_rtc is made[1]
    assert f.quick is quick and 0.0 <= f.elapsed <= wall


def test_compute_var_is_best_once(monkeypatch):
    # no prediction (0.75) above every predictor is still not "the best predictor"
    monkeypatch.setattr(closedloop, "LoopModel", _Recorder(None))
    monkeypatch.setattr(closedloop, "simulate", _Recorder(None))
    monkeypatch.setattr(comp, "predictor_screen", _Recorder({"none": 0.75, "linear": 0.5,
                                                             "multivariate": 0.625,
                                                             "oracle": 1.0}))
    study = _Recorder(_study())
    monkeypatch.setattr(comp, "compression_study", study)
    scaling = _Recorder(lambda n, predictor=None: np.ones(len(n)))
    monkeypatch.setattr(comp, "rtc_scaling", scaling)
    f = fig6.compute(quick=True)
    assert [c[1]["predictor"] for c in scaling.calls] == [None, "multivariate"]
    assert list(f.scaling_time) == ["none", "multivariate"]
    assert [c[1]["predictor"] for c in study.calls] == ["multivariate"]
    assert [c[1]["seed"] for c in study.calls] == [0]
    # the defaults: the full study (all mode counts and the slow RTC), seed 0
    study.calls.clear()
    fig6.compute()
    assert [c[1]["n_values"] for c in study.calls] == [(3, 6, 10, 15, 21, 27), (6, 15, 27)]
    assert [c[1]["seed"] for c in study.calls] == [0, 0]


# ---- plot: read back ---------------------------------------------------------------------

@pytest.fixture(scope="module")
def drawn(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig6")
    figures = []
    savefig = Figure.savefig

    def recording(self, fname, *args, **kwargs):
        if not figures or figures[-1] is not self:
            figures.append(self)
        return savefig(self, fname, *args, **kwargs)

    bind = {"none": np.full(4, STEP), "arma": np.array([STEP, STEP, 6.25e-4, 7.5e-4])}
    mp = pytest.MonkeyPatch()
    mp.setattr(Figure, "savefig", recording)
    try:
        # the latency-model runs of no prediction 1/16 lower than the fixed-delay ones, so
        # that the solid lines (the docstring: "solid without ... prediction (fixed delay)")
        # tell the two tables apart; no other line of the figure reads them
        study = _study(delay=bind)
        for table in (study.strehl_peak, study.strehl_field):
            for o in ORDS:
                table[(True, o, "none")] = table[(False, o, "none")] - 0.0625
        paths = fig6.plot(_figure(study=study, slow=_slow()), out / "a" / "b")
        fig6.plot(_figure(), out)
    finally:
        mp.undo()
    return out, paths, figures


def _rgb(c):
    import matplotlib.colors

    return matplotlib.colors.to_rgb(c)


def test_plot_read_back(drawn):
    # one test reads everything back: mutmut runs a plot mutant only with the tests that
    # called plot (the fixture's first user), see docs/MUTATION.md
    out, paths, (fig, plain) = drawn
    assert paths == [out / "a" / "b" / "fig6_compression.png",
                     out / "a" / "b" / "fig6_compression.pdf"]
    assert paths[1].read_bytes()[:5] == b"%PDF-"
    assert tuple(fig.get_size_inches()) == (17.0, 4.8)
    a, b, c = fig.axes
    assert len(fig.axes) == 3 and a.get_position().x1 < b.get_position().x0 < c.get_position().x0
    # (a), (b): per ordering a solid line without prediction, dashed with, dotted with the
    # latency model (it binds here); the slow RTC's crosses; then the legend's dummies
    for ax, tables in ((a, _tables()), (b, _tables(field=True))):
        lines = ax.get_lines()
        assert len(lines) == 3 * 5 + 2 + (2 if ax is a else 0)
        for k, o in enumerate(ORDS):
            solid, dashed, dotted = lines[3 * k: 3 * k + 3]
            color = fig6.STYLES[o]["color"]
            np.testing.assert_array_equal(solid.get_xdata(), N)
            np.testing.assert_array_equal(dashed.get_xdata(), N)
            np.testing.assert_array_equal(dotted.get_xdata(), N)
            np.testing.assert_array_equal(solid.get_ydata(), tables[(False, o, "none")])
            np.testing.assert_array_equal(dashed.get_ydata(), tables[(False, o, "arma")])
            np.testing.assert_array_equal(dotted.get_ydata(), tables[(True, o, "arma")])
            assert solid.get_label() == NAMES[o]
            assert (solid.get_linestyle(), solid.get_marker()) == ("-", fig6.STYLES[o]["marker"])
            assert _rgb(solid.get_color()) == _rgb(color)
            assert (dashed.get_linestyle(), dashed.get_linewidth()) == ("--", 0.9)
            assert (dotted.get_linestyle(), dotted.get_linewidth()) == (":", 0.9)
            assert _rgb(dashed.get_color()) == _rgb(dotted.get_color()) == _rgb(color)
        slow = _slow()
        wt = slow.strehl_peak if ax is a else slow.strehl_field
        for ln, o in zip(lines[15:17], ("zernike", "pca"), strict=True):
            np.testing.assert_array_equal(ln.get_xdata(), [6, 15, 27])
            np.testing.assert_array_equal(ln.get_ydata(), wt[(True, o, "arma")])
            assert (ln.get_marker(), ln.get_linestyle(), ln.get_markersize(),
                    ln.get_linewidth()) == ("x", ":", 6, 0.9)
            assert _rgb(ln.get_color()) == _rgb(fig6.STYLES[o]["color"])
        assert ax.get_xlabel() == "controlled modes n"
        assert ax.get_ylim()[0] == 0.0
    assert a.get_ylabel() == "SR peak over the field (500 nm)"
    assert b.get_ylabel() == "field-averaged SR (500 nm)"
    assert a.get_title() == "(a) kaos: SR peak vs controlled modes"
    assert b.get_title() == "(b) field average (0.5 s, seed 3)"
    assert [t.get_text() for t in a.get_legend().get_texts()] == [
        *NAMES.values(), "dashed: with arma prediction", "x: with prediction, RTC x0.1"]
    assert {t.get_fontsize() for t in a.get_legend().get_texts()} == {7}
    # the two legend keys look like the lines their words name: "dashed" as the dashed
    # lines (black, not an ordering's colour), "x" as the slow RTC's crosses
    dashed, crosses = a.get_lines()[17:]
    assert (dashed.get_linestyle(), dashed.get_marker(), _rgb(dashed.get_color())) == (
        "--", "None", (0.0, 0.0, 0.0))
    assert dashed.get_linewidth() == a.get_lines()[1].get_linewidth()
    assert (crosses.get_linestyle(), crosses.get_marker(), _rgb(crosses.get_color())) == (
        ":", "x", (0.0, 0.0, 0.0))
    assert crosses.get_linewidth() == a.get_lines()[15].get_linewidth()
    assert b.get_legend() is None
    # (c): the measured step in microseconds, log-log, with the frame and half a delay step
    assert (c.get_xscale(), c.get_yscale()) == ("log", "log")
    assert c.get_xlabel() == "controlled modes n"
    assert c.get_ylabel() == "real-time step [us] (this machine)"
    assert c.get_title() == "(c) measured real-time step vs n"
    lines = c.get_lines()
    labels = ["synthetic sizes, no prediction", "kaos loop, no prediction",
              "synthetic sizes, arma", "kaos loop, arma", "synthetic sizes, multivariate"]
    assert [ln.get_label() for ln in lines[:5]] == labels
    syn = {"none": SCALING_N * 1.0, "arma": 2e-2 * SCALING_N ** 2.0,
           "multivariate": 4e-2 * SCALING_N ** 2.0}              # us
    for ln, key, k in ((lines[0], "none", 0), (lines[2], "arma", 1),
                       (lines[4], "multivariate", 2)):
        np.testing.assert_array_equal(ln.get_xdata(), SCALING_N)
        np.testing.assert_allclose(ln.get_ydata(), syn[key], rtol=1e-12)
        assert (ln.get_marker(), ln.get_linestyle()) == ("os^"[k], "-")
        assert _rgb(ln.get_color()) == _rgb(f"C{k}")
    for ln, us, k in ((lines[1], [1.0, 2.0, 3.0, 4.0], 0), (lines[3], [2.0, 4.0, 8.0, 16.0], 1)):
        np.testing.assert_array_equal(ln.get_xdata(), N)
        np.testing.assert_allclose(ln.get_ydata(), us, rtol=1e-12)
        assert (ln.get_marker(), ln.get_linestyle(), ln.get_markerfacecolor()) == (
            "os^"[k], "None", "none")
        assert _rgb(ln.get_color()) == _rgb(f"C{k}")
    frame, half = lines[5:]
    np.testing.assert_allclose(frame.get_ydata(), [500.0, 500.0], rtol=1e-12)
    np.testing.assert_allclose(half.get_ydata(), [31.25, 31.25], rtol=1e-12)
    assert (_rgb(frame.get_color()), frame.get_linewidth()) == ((0.3, 0.3, 0.3), 0.8)
    assert (_rgb(half.get_color()), half.get_linewidth(), half.get_linestyle()) == (
        (0.6, 0.6, 0.6), 0.8, ":")
    texts = [(t.get_text(), t.get_position()) for t in c.texts]
    assert [t for t, _ in texts] == [" one frame", " adds a delay step"]
    np.testing.assert_allclose([p for _, p in texts], [(27, 500.0), (27, 31.25)], rtol=1e-12)
    assert all((t.get_fontsize(), t.get_va()) == (7, "bottom") for t in c.texts)
    assert [t.get_text() for t in c.get_legend().get_texts()] == labels
    assert {t.get_fontsize() for t in c.get_legend().get_texts()} == {7}
    # the plain figure: no dotted lines (the latency does not bind), no slow RTC
    pa = plain.axes[0]
    assert len(pa.get_lines()) == 2 * 5 + 1
    assert [t.get_text() for t in pa.get_legend().get_texts()] == [
        *NAMES.values(), "dashed: with arma prediction"]
    assert (out / "fig6_compression.png").is_file()


# ---- make and the command line ---------------------------------------------------------

@pytest.fixture
def fake_compute(monkeypatch):
    rec = _Recorder(lambda **kw: _figure(quick=kw["quick"]))
    monkeypatch.setattr(fig6, "compute", rec)
    monkeypatch.setattr(fig6, "plot", _Recorder(lambda f, out: Path(out).mkdir(
        parents=True, exist_ok=True) or [Path(out) / fig6.FIGURE_NAME]))
    return rec


def test_make_and_main(tmp_path, monkeypatch, capsys, fake_compute):
    assert fig6.make(tmp_path, quick=True, seed=2) == _expected_report(quick=True)
    assert fake_compute.calls == [((), {"quick": True, "seed": 2})]
    assert fig6.plot.calls[0][0][1] == tmp_path
    drawn_fig = fig6.plot.calls[0][0][0]
    assert isinstance(drawn_fig, fig6.Figure6) and drawn_fig.quick is True
    fake_compute.calls.clear()
    assert fig6.make(tmp_path) == _expected_report()
    assert fake_compute.calls == [((), {"quick": False, "seed": 0})]
    fake_compute.calls.clear()
    assert fig6.main(["--out", str(tmp_path / "o"), "--quick"]) == 0
    assert fake_compute.calls == [((), {"quick": True, "seed": 0})]
    assert capsys.readouterr().out == _expected_report(quick=True) + "\n"
    for name in (fig6.FIGURE_NAME, fig6.PDF_NAME):
        d = tmp_path / name.replace(".", "_")
        d.mkdir()
        (d / name).write_bytes(b"x")
        assert fig6.main(["--out", str(d)]) == 2
        assert capsys.readouterr().err == (
            f"python -m paper_figures.fig6_compression: error: "
            f"'{d / name}' exists; pass --overwrite\n")
        assert fig6.main(["--out", str(d), "--overwrite"]) == 0
        assert fake_compute.calls[-1] == ((), {"quick": False, "seed": 0})
    monkeypatch.chdir(tmp_path)
    assert fig6.main([]) == 0
    # drawn in a staging folder of out/, under its lock, moved in at the end (left13-cli)
    drawn = fig6.plot.calls[-1][0][1]
    assert drawn.parent == Path("out") and drawn.name.startswith(".out.partial-")


def test_main_help(capsys):
    with pytest.raises(SystemExit) as exc:
        fig6.main(["--help"])
    assert exc.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    assert out.startswith("usage: python -m paper_figures.fig6_compression [-h] "
                          "[--out OUT] [--overwrite] [--quick]")
    for text in ("[--quick] Regenerate Figure 6 (compression x prediction). options:",
                 "--out OUT output directory", "--overwrite replace an existing figure",
                 "--quick fewer mode counts"):
        assert text in out
