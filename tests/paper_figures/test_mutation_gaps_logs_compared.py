"""The two shipped logs compared, on hand-made logs: every statistic and sentence.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all
outside the module:

- the logs are written in this file, 8 frames of the +-1 patterns
  ``p = 1 1 -1 -1 ...``, ``q = 1 -1 1 -1 ...``, ``r[t] = p[t - 1]`` and
  ``u = 1 1 1 1 -1 -1 -1 -1``, scaled per mode: each has mean 0 and variance 1, so the
  variances, the tilt ratio and the share of radial orders >= 5 (Noll 16 is n = 5) are
  read off the scales, and the lag-1 products ``sum_t a[t] b[t + 1] / 7`` are counted by
  hand in the comments (p: 1/7, q: -1, r: -1/7, u: 5/7; p -> r: 1);
- the units: a log in nm at 500 nm is in waves after dividing by 500 (the docstring's
  waves^2);
- the report's sentences written out word for word, each comparison on both sides.
~1 s.
"""

from __future__ import annotations

import types

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog
from paper_figures import logs_compared as lc

P = np.array([1, 1, -1, -1, 1, 1, -1, -1], dtype=float)
Q = np.array([1, -1, 1, -1, 1, -1, 1, -1], dtype=float)
R = np.roll(P, 1)                               # -1 1 1 -1 -1 1 1 -1
U = np.array([1, 1, 1, 1, -1, -1, -1, -1], dtype=float)


def log_a():
    """Modes in the order Z3, Z2, Z16, Z4 (waves): r, 2p, 2q, q.

    Variances 1, 4, 4, 1: total 10, Var(Z2) / Var(Z3) = 4, share of Z16 0.4. Lag-1
    autocorrelations -1/7, 1/7, -1, -1: mean -0.5. Largest lag-1 cross term: Z2 -> Z3,
    p[t] r[t + 1] = p[t]^2 = 1 (and Z16 -> Z4, q -> q: -1).
    """
    return ModalLog(np.column_stack([R, 2 * P, 2 * Q, Q]), rate=100.0, modes=[3, 2, 16, 4],
                    units="waves")


def log_b():
    """Z2, Z3, Z4, Z16 in nm at 500 nm: 500 p, 1000 q, 500 u, 250 u (waves: p, 2q, u, u/2).

    Variances 1, 4, 1, 0.25: total 6.25, tilt ratio 0.25, share 0.04. Lag-1
    autocorrelations 1/7, -1, 5/7, 5/7: mean 4/28 = 1/7. Cross terms: u -> u (Z4 ->
    Z16, Z16 -> Z4) 5/7, every other pair +-1/7; the diagonal's q (-1) is not a cross term.
    """
    x = np.column_stack([500 * P, 1000 * Q, 500 * U, 250 * U])
    return ModalLog(x, rate=100.0, modes=[2, 3, 4, 16], units="nm", wavelength=500e-9)


def test_statistics_by_hand():
    a = lc.statistics(log_a(), "A")
    assert a == lc.LogStatistics(name="A", total=10.0, tilt_ratio=4.0, high_order_share=0.4,
                                 lagged_cross=1.0, lag1=-0.5)
    b = lc.statistics(log_b(), "B")
    assert b.name == "B"
    assert b.total == pytest.approx(6.25, rel=1e-12)
    assert b.tilt_ratio == pytest.approx(0.25, rel=1e-12)
    assert b.high_order_share == pytest.approx(0.04, rel=1e-12)
    assert b.lagged_cross == pytest.approx(5 / 7, rel=1e-12)
    assert b.lag1 == pytest.approx(1 / 7, rel=1e-12)
    assert all(type(v) is float for v in (b.total, b.tilt_ratio, b.high_order_share,
                                          b.lagged_cross, b.lag1))


def test_statistics_remove_the_mean_and_keep_waves():
    # an offset on every mode changes nothing; a log in waves is not converted
    x = np.column_stack([R, 2 * P, 2 * Q, Q]) + np.array([3.0, -2.0, 0.5, 7.0])
    s = lc.statistics(ModalLog(x, rate=100.0, modes=[3, 2, 16, 4], units="waves"), "A")
    assert (s.total, s.tilt_ratio, s.high_order_share, s.lagged_cross, s.lag1) == pytest.approx(
        (10.0, 4.0, 0.4, 1.0, -0.5), rel=1e-12)
    # a log in waves with a wavelength: still waves
    w = ModalLog(np.column_stack([R, 2 * P, 2 * Q, Q]), rate=100.0, modes=[3, 2, 16, 4],
                 units="waves", wavelength=500e-9)
    assert lc.statistics(w, "A").total == 10.0


def test_statistics_of_a_float32_log_are_computed_in_double():
    # ModalLog keeps float32 as given; the statistics are those of the same numbers in
    # float64, bit for bit (a float32 variance differs in the 7th digit)
    rng = np.random.default_rng(1)
    x = rng.standard_normal((64, 4)).astype(np.float32)
    single = ModalLog(x, rate=100.0, modes=[2, 3, 4, 16], units="waves")
    double = ModalLog(x.astype(np.float64), rate=100.0, modes=[2, 3, 4, 16], units="waves")
    assert single.coeffs.dtype == np.float32
    assert lc.statistics(single, "s") == lc.statistics(double, "s")


def test_compute_names_the_two_logs():
    c = lc.compute(log_a(), log_b())
    assert c.spectral == lc.statistics(log_a(), "spectral")
    assert c.simulated == lc.statistics(log_b(), "simulated")


HEAD = """## The spectral and the simulated KAOS-like logs

Figures 1 and 5 run on two shipped logs of the same system (0.7 m, Z2-Z28, 2 kHz,
r0 = 7 cm, 130 Hz integrator): `data/kaos_like_closed_loop.npz`, drawn from Conan
spectra (`modalinfo.telemetry.synthetic.kaos_like`), and `data/kaos_closedloop.npz`,
the WFS residual of the `closedloop` `kaos` preset (frozen flow, Shack-Hartmann,
noise through the reconstructor; its provenance is in its metadata).
"""


def _table(a, b):
    return "\n".join([
        "| statistic | spectral log | simulated log |", "|---|---|---|",
        f"| total variance [waves^2] | {a[0]} | {b[0]} |",
        f"| Var(Z2) / Var(Z3) | {a[1]} | {b[1]} |",
        f"| variance share of radial orders >= 5 | {a[2]} | {b[2]} |",
        f"| largest lag-1 cross-correlation between modes | {a[3]} | {b[3]} |",
        f"| mean lag-1 autocorrelation | {a[4]} | {b[4]} |"])


A_TXT = ("10", "4.00", "40.0%", "1.00", "-0.50")
B_TXT = ("6.25", "0.25", "4.0%", "0.71", "0.14")


def test_report_spectral_a_simulated_b():
    text = lc.report(lc.compute(log_a(), log_b()))
    assert text == HEAD + "\n" + _table(A_TXT, B_TXT) + """

How and why they differ: frozen flow moves each layer's pattern along its wind, so
one mode's pattern flows into others from one frame to the next; the lagged coupling
between modes is not stronger in the simulated log (0.71 against
1.00 for spectra that are coupled only at zero lag), and the tilt ratio does not \
separate them here (Conan
spectra carry no wind direction). The Shack-Hartmann sees the turbulence beyond Z28,
which aliases into the measured modes, while the spectral model adds white noise of
equal variance to every mode: the spectral log's high orders hold more of its variance \
(40.0% against 4.0%): its white noise, equal in every mode, weighs most on the high \
orders whose turbulence the loop leaves small, more than aliasing from beyond Z28 lifts \
the simulated ones. The simulated residual is smoother in time (mean
lag-1 autocorrelation 0.14 against -0.50). \n"""


def test_report_the_other_way_round():
    text = lc.report(lc.compute(log_b(), log_a()))
    assert text == HEAD + "\n" + _table(B_TXT, A_TXT) + """

How and why they differ: frozen flow moves each layer's pattern along its wind, so
one mode's pattern flows into others from one frame to the next; the lagged coupling
between modes is stronger in the simulated log (1.00 against
0.71 for spectra that are coupled only at zero lag), and x and y tilt differ more \
(Var(Z2) / Var(Z3) 4.00 against 0.25) (Conan
spectra carry no wind direction). The Shack-Hartmann sees the turbulence beyond Z28,
which aliases into the measured modes, while the spectral model adds white noise of
equal variance to every mode: the simulated log's high orders hold more of its variance \
(40.0% against 4.0%), as aliasing from the turbulence beyond Z28 adds to them. The \
simulated residual is rougher in time (mean
lag-1 autocorrelation -0.50 against 0.14). \n"""


def test_report_ties_take_the_cautious_word():
    # the same log twice: nothing is stronger, smoother or more anisotropic
    text = lc.report(lc.compute(log_a(), log_a()))
    assert "between modes is not stronger in the simulated log" in text
    assert "and the tilt ratio does not separate them here" in text
    assert "the spectral log's high orders hold more of its variance (40.0% against 40.0%)" \
        in text
    assert "The simulated residual is rougher in time" in text
    # a tilt ratio as far below 1 as the other is above (0.5 vs 1.5): not "more"
    a = lc.LogStatistics("spectral", 1.0, 1.5, 0.1, 0.2, 0.3)
    b = lc.LogStatistics("simulated", 1.0, 0.5, 0.1, 0.2, 0.3)
    assert "the tilt ratio does not separate them" in lc.report(lc.LogsCompared(a, b))
    b = lc.LogStatistics("simulated", 1.0, 0.4375, 0.1, 0.2, 0.3)
    assert "x and y tilt differ more (Var(Z2) / Var(Z3) 0.44 against 1.50)" in lc.report(
        lc.LogsCompared(a, b))


def _fig1(n):
    return types.SimpleNamespace(typical=types.SimpleNamespace(modes_at_target=n))


class _Fig5:
    def __init__(self, gain, best):
        self._gain, self.best_one_step = gain, best

    def gain(self, name):
        assert name == "ARMA(2,3)"
        return self._gain


def test_report_quotes_figures_1_and_5_when_both_logs_have_them():
    cmp = lc.compute(log_a(), log_b())
    fig1 = {"spectral": _fig1({"zernike:standard": 20, "kl-theory:mi_greedy": 7}),
            "simulated": _fig1({"zernike:standard": 22, "kl-theory:mi_greedy": 9,
                                "zernike:mi_greedy": 16})}
    fig5 = {"spectral": _Fig5(1.25, "ARMA(2,3)"), "simulated": _Fig5(0.875, "NN")}
    text = lc.report(cmp, fig1, fig5)
    assert text.endswith(
        "lag-1 autocorrelation 0.14 against -0.50). Figure 1 on the typical frame, modes to "
        "reach the calibrated target (standard Zernike / MI K-L / MI Zernike): spectral "
        "20 / 7 / -, simulated 22 / 9 / 16. Figure 5, whole-wavefront gain over "
        "persistence at one frame: ARMA(2,3) x1.25 (spectral) vs x0.88 (simulated); best "
        "predictor ARMA(2,3) vs NN.\n")
    # one log only, or none: nothing quoted
    for f1, f5 in (({"spectral": fig1["spectral"]}, {"simulated": fig5["simulated"]}),
                   ({}, {}), (None, None)):
        assert lc.report(cmp, f1, f5).endswith("against -0.50). \n")
    assert lc.report(cmp, fig1).endswith("simulated 22 / 9 / 16.\n")
    assert lc.report(cmp, fig5=fig5).endswith("predictor ARMA(2,3) vs NN.\n")
