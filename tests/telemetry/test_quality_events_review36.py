"""Mutation round 36 (review36): the quality pass's live parts, copies and events.

Plants that escaped stop 60's tests (docs/MUTATION.md, "Round 36"): the live-part rule
read only at x0.001 and dead (``LIVE_PART_RATIO`` 10 -> 100 escaped), its innovations'
scale never read (dropping it escaped, as did windows reaching into the quiet rows),
copies only ever differing in their first sampled values (``array_equal`` -> True
escaped), and ``mode_events`` never given two modes out of order.

References (outside the code): numpy's median and MAD of the live frames times
1 / Phi^-1(3/4) (scipy); the AR(1) law's innovation sd ``0.05 sqrt(1 - 0.9^2)`` (the
simulation's own); the planted copies (``np.array_equal``); the events given in the
report (their mode and frame by construction).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.signal import lfilter
from scipy.stats import norm

from modalinfo.telemetry import ModalLog, assess_quality
from modalinfo.telemetry.quality import AR_ORDER, _live_innovation_scale

N, STEP = 20000, 12000
INNOVATION_SD = 0.05 * np.sqrt(1.0 - 0.81)


def _log(gain: float) -> np.ndarray:
    rng = np.random.default_rng(530)
    e = rng.standard_normal((N + 2000, 4)) * INNOVATION_SD
    c = lfilter([1.0], [1.0, -0.9], e, axis=0)[2000:]
    c[STEP:, 1] *= gain
    return c


def _numpy_sigma(x: np.ndarray) -> float:
    return float(np.median(np.abs(x - np.median(x))) / norm.ppf(0.75))


def _report(c):
    return assess_quality(ModalLog(c, rate=1000.0, modes=[2, 3, 4, 5], units="rad"))


def test_a_x20_quiet_minority_takes_the_live_scale():
    # a step of x0.05 (ratio 20, beyond LIVE_PART_RATIO = 10) over 40 % of the log
    c = _log(0.05)
    report = _report(c)
    live = _numpy_sigma(c[:STEP, 1])
    assert _numpy_sigma(c[:, 1]) < 0.5 * live
    np.testing.assert_allclose(report.sigma[1], live, rtol=0.01)


def test_a_x5_quiet_minority_keeps_the_pooled_scale():
    # x0.2 (ratio 5) is under the rule's ratio: the pooled median / MAD stand
    c = _log(0.2)
    report = _report(c)
    np.testing.assert_allclose(report.sigma[1], _numpy_sigma(c[:, 1]), rtol=1e-12)


def test_the_innovations_scale_comes_from_the_live_part():
    # the outlier threshold on the innovations is k innovation sigmas of the live frames;
    # 8,000 dead frames (innovations 0) shrank the pooled one ~x0.4
    c = _log(0.0)
    report = _report(c)
    thr_e = report.predictor[4]
    np.testing.assert_allclose(thr_e[1] / report.k, INNOVATION_SD, rtol=0.05)


def test_live_innovations_take_only_windows_inside_the_live_rows():
    # coefficients 0: the innovations are the values minus the centre; rows r0 .. r0 + p - 1
    # have predecessors before r0 (the quiet side): their windows are left out
    rng = np.random.default_rng(36)
    col = rng.standard_normal(1000)
    col[300:300 + AR_ORDER] = 50.0
    g = np.arange(col.size)
    cen, sig = _live_innovation_scale(col, g, 0.1, np.zeros(AR_ORDER), 300, 900)
    e = col[300 + AR_ORDER:900] - 0.1
    assert cen == pytest.approx(float(np.median(e)), rel=1e-12)
    assert sig == pytest.approx(_numpy_sigma(e), rel=1e-12)


def test_modes_equal_in_the_first_values_only_are_no_copy():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((3000, 10))
    x[:100, 7] = x[:100, 2]           # equal in the first 100 frames, then independent
    assert not np.array_equal(x[:, 7], x[:, 2])
    report = assess_quality(ModalLog(x, rate=1000.0, modes=list(range(2, 12))))
    assert report.copied_modes == ()
    assert "equal in all" not in report.describe()


def test_mode_events_are_in_mode_order():
    c = _log(1.0)
    report = dataclasses.replace(
        _report(c), level_steps=(("Z5", 500, 1.0, 1e-20),),
        variance_steps=(("Z3", 900, 10.0, 1e-20), ("Z3", 100, 0.1, 1e-20)),
        step_lines=(), scale_steps=())
    events = report.mode_events()
    assert [(e[0], e[2]) for e in events] == [(1, 100), (1, 900), (3, 500)]
    assert events[2][3] == "the mean steps or drifts by +1 at frame 500"


def test_more_than_five_constant_modes_are_counted():
    rng = np.random.default_rng(3)
    x = rng.standard_normal((3000, 12))
    x[:, 2:9] = 0.0                       # 7 dead modes: 5 named, "and 2 more"
    text = assess_quality(ModalLog(x, rate=1000.0, modes=list(range(2, 14)))).describe()
    assert "7 mode(s) constant over the whole log" in text
    assert text.endswith(": Z4, Z5, Z6, Z7, Z8 and 2 more")
