"""Logs upsampled by linear interpolation, or with frames filled by it (fix57-c, issue 27).

Round 55 PART a (docs/ADVERSARIAL.md, O01-O06): archives that bring WFS and DM telemetry
to one rate upsample by linear interpolation, and RTCs fill dropped frames by it; then
k - 1 of every k frames are exact affine functions of their neighbours
(x_t = 2 x_(t-1) - x_(t-2)), I(x_t; x_(t-2) | x_(t-1)) is infinite on them, and the
estimators read 0.007-1.23 nats without a word while the quality pass named neither.

References (from outside the code): the logs are built with ``numpy.interp`` (linear
interpolation of an AR(1) drawn by ``scipy.signal.lfilter``) and ``numpy.linspace``
(filled gaps), so the upsampling factor and the filled rows are known by construction;
a zero-order hold is ``numpy.repeat``. False alarms: stationary AR(1) 0.99 logs
(float64 and float32), an AR(2) near-line at pole radius 0.999, ``kaos_like`` logs and
the closed-loop simulator's noise-free POL (the generator of
tests/ordering/test_calibration_simulator_fix55b.py) must not be named: the rule's
tolerance is a few ulps of the mode's largest magnitude, which continuous telemetry's
second differences reach with probability ~1e-13 per frame (measured: 0 of 100 AR(1)
0.99 logs, 0 of 100 AR(2) r 0.999, 0 of 100 kaos_like open / closed loop, 0 of 5
simulator POLs of 2,993 x 27; docs/ADVERSARIAL.md, "Interpolated logs (fix57-c)").
Seeds fixed.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.information import (
    conditional_mutual_information,
    select_inputs,
    transfer_entropy,
)
from modalinfo.telemetry import InterpolationWarning, ModalLog, assess_quality
from modalinfo.telemetry.synthetic.presets import kaos_like


def _ar1(n: int, m: int, rho: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return lfilter([1.0], [1.0, -rho], rng.standard_normal((n + 300, m)), axis=0)[300:]


def _upsampled(k: int, seed: int = 57_000, n: int = 1000, m: int = 3) -> np.ndarray:
    """An AR(1) 0.95 log of ``n`` frames linearly interpolated ``k`` times (numpy.interp)."""
    base = _ar1(n, m, 0.95, seed)
    t0, t1 = np.arange(n), np.arange((n - 1) * k + 1) / k
    return np.stack([np.interp(t1, t0, base[:, j]) for j in range(m)], axis=1)


def _filled(seed: int = 57_001) -> tuple[np.ndarray, list]:
    """AR(1) 0.95 with 20 gaps of 9 frames filled by straight lines (5 %), the made-up rows."""
    a = _ar1(4000, 3, 0.95, seed).copy()
    rows = []
    for s in range(0, 4000, 200):
        lo, hi = s + 100, s + 110  # kept frames lo and hi; lo + 1 .. hi - 1 made up
        for j in range(3):
            a[lo:hi + 1, j] = np.linspace(a[lo, j], a[hi, j], hi - lo + 1)
        rows.append((lo + 1, hi))
    return a, rows


def _log(a: np.ndarray) -> ModalLog:
    return ModalLog(a, rate=2000.0, modes=list(range(2, 2 + a.shape[1])), units="rad")


@pytest.mark.parametrize("k", [2, 4])
@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_upsampled_log_named_with_its_factor(k, dtype):
    report = assess_quality(_log(_upsampled(k).astype(dtype)))
    assert report.upsampled == (("Z2", k), ("Z3", k), ("Z4", k))
    words = report.describe()
    assert f"upsampled x{k} by linear interpolation" in words
    assert f"log[::{k}]" in words
    assert report.to_dict()["upsampled"] == f"Z2 x{k}, Z3 x{k}, Z4 x{k}"
    # the pair-order rule's null does not hold on it: not misnamed "swapped pairs"
    assert not report.pair_order and "swapped pairs" not in words


def test_filled_gaps_named_by_rows():
    a, rows = _filled()
    report = assess_quality(_log(a))
    assert [(s, e) for s, e, _ in report.filled_runs] == rows
    assert all(n == 3 for _, _, n in report.filled_runs)
    words = report.describe()
    assert "20 run(s) of frames filled by linear interpolation (180 frames" in words
    assert "rows 101..109, 301..309" in words
    assert report.to_dict()["filled_rows"].startswith("101-109, 301-309")
    assert not report.upsampled


def test_zero_order_hold_still_named_as_repeats_not_interpolation():
    hold = np.repeat(_ar1(1000, 3, 0.95, 57_002), 4, axis=0)
    report = assess_quality(_log(hold))
    assert report.repeated_frames.size == 3000
    assert not report.upsampled and not report.filled_runs
    # the words name the repeats (the too-short branch of describe said nothing of them)
    assert "3000 repeated frame(s) equal to the frame before" in report.describe()
    assert "upsampled" not in report.to_dict() and "filled_rows" not in report.to_dict()


def _silent(a: np.ndarray) -> None:
    report = assess_quality(_log(a))
    assert report.upsampled == () and report.filled_runs == ()
    assert "interpolation" not in report.describe()
    assert "upsampled" not in report.to_dict()


@pytest.mark.parametrize("seed", range(5))
def test_no_false_alarm_on_ar1_logs(seed):
    a = _ar1(4000, 10, 0.99, 57_100 + seed)
    _silent(a)
    _silent(a.astype(np.float32))


def test_no_false_alarm_on_a_near_line_ar2():
    r, period = 0.999, 50.0
    a1, a2 = 2 * r * np.cos(2 * np.pi / period), -r * r
    rng = np.random.default_rng(57_200)
    a = lfilter([1.0], [1.0, -a1, -a2], rng.standard_normal((8000, 3)), axis=0)[4000:]
    _silent(a)
    _silent(a.astype(np.float32))


@pytest.mark.parametrize("closed", [False, True])
def test_no_false_alarm_on_kaos_like(closed):
    _silent(np.asarray(kaos_like(n_frames=4000, closed_loop=closed, seed=57_300).coeffs))


def test_no_false_alarm_on_the_simulators_noise_free_pol():
    from tests.ordering.test_calibration_simulator_fix55b import _pol  # noqa: PLC0415

    _silent(_pol(0))


def test_a_straight_mode_is_not_a_filled_run():
    a = _ar1(2000, 3, 0.9, 57_400)
    a[:, 1] = np.linspace(-1.0, 1.0, a.shape[0])  # a ramp: one line, not a fill
    assert assess_quality(_log(a)).filled_runs == ()


@pytest.mark.parametrize("method", ["gaussian", "ksg", "kde", "histogram"])
def test_cmi_of_an_upsampled_log_warns(method):
    x = _upsampled(4)[:, 0]
    with pytest.warns(InterpolationWarning, match=r"upsampled x4 .*log\[::4\]"):
        conditional_mutual_information(x[2:], x[:-2], x[1:-1], method=method)


def test_cmi_at_the_native_rate_is_silent_of_it():
    x = _upsampled(4)[::4, 0]
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        conditional_mutual_information(x[2:], x[:-2], x[1:-1], method="gaussian")
    assert not [w for w in seen if issubclass(w.category, InterpolationWarning)]


def test_transfer_entropy_and_select_inputs_warn():
    up = _upsampled(4)
    with pytest.warns(InterpolationWarning, match="upsampled x4"):
        transfer_entropy(up[:, 1], up[:, 0], method="gaussian")
    with pytest.warns(InterpolationWarning, match=r"select_inputs: 3 of 3 series .* x4"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # its other words (outliers)
            warnings.simplefilter("always", InterpolationWarning)
            select_inputs(_log(up), 0, max_lag=6, n_surrogates=19)


def test_evaluate_warns():
    from modalinfo.forecast import evaluate, make_predictor

    with pytest.warns(InterpolationWarning, match=r"evaluate: 3 of 3 series .* x4"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            warnings.simplefilter("always", InterpolationWarning)
            evaluate([make_predictor("linear-ls")], _log(_upsampled(4)), horizons=[1])
