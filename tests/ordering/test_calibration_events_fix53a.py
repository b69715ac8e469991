"""Calibration events inside a log, named by ``order_modes`` (fix53-a, issue 27).

Round 52 PART a, L04 / L09 / L24 / L34 / L39: a level step, a x1000 gain, two columns
swapped, a linear drift or the first 5 % of the log x10 moved the pooled orderings
(Z5 first after a +3 sd step) while ``order_modes`` said nothing, though
``assess_quality`` names each event. ``order_modes`` now runs the quality pass on the
coefficients it ranks and warns (``CalibrationEventWarning``) naming the mode, the event
and its frame; the ordering itself is unchanged.

References (outside the code): the planted events (mode and frame known by
construction); numpy's mean squares for the variance order (the pooled numbers stay
those of the pooled log); stationary AR(1) logs from ``scipy.signal.lfilter`` for the
silent cases (measured: 0 of 150 AR(1) 0.9 / 0.95 / 0.99 logs of 10 x 20,000 frames and
0 of 50 ``kaos_like`` closed-loop logs warned, docs/ADVERSARIAL.md "Calibration events
inside a log (fix53-a)"; the seeds below are fixed).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes
from modalinfo.telemetry import CalibrationEventWarning, ModalLog, assess_quality

from ._silent_order import mean_square_order, silent_order

MODES = list(range(2, 10))
N, STEP = 20000, 12000
# distinct rms per mode, so that the variance order is set (Z2 largest ... Z9 smallest)
RMS = np.linspace(1.0, 0.3, len(MODES))


def _clean(seed: int, phi: float = 0.9) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((N + 2000, len(MODES))) * np.sqrt(1.0 - phi**2)
    return lfilter([1.0], [1.0, -phi], e, axis=0)[2000:] * RMS


def _event(name: str) -> np.ndarray:
    c = _clean(53)
    j5, j8 = MODES.index(5), MODES.index(8)
    sd = c.std(axis=0)
    if name == "level":                 # L04: a new reference, Z5 + 3 sd
        c[STEP:, j5] += 3.0 * sd[j5]
    elif name == "gain":                # L09: nm read as um
        c[STEP:, j5] *= 1000.0
    elif name == "swap":                # L24: two columns re-mapped
        c[STEP:, [j5, j8]] = c[STEP:, [j8, j5]]
    elif name == "drift":               # L34: 0 -> 3 sd over the log
        c[:, j5] += np.linspace(0.0, 3.0 * sd[j5], N)
    elif name == "openstart":           # L39: the loop closes after 5 % of the log
        c[:1000] *= 10.0
    return c


BASIS = ZernikeBasis(Pupil(32), MODES)


def _log(c: np.ndarray) -> ModalLog:
    return ModalLog(c, rate=2000.0, modes=MODES, units="rad")


@pytest.mark.parametrize("name, modes, frames", [
    ("level", ["Z5"], (11500, 12500)),
    ("gain", ["Z5"], (11500, 12500)),
    ("swap", ["Z5", "Z8"], (11000, 13000)),
    ("drift", ["Z5"], (0, N)),
    ("openstart", ["Z2", "Z4"], (0, 1300)),
])
@pytest.mark.parametrize("method", ["variance", "mi_marginal"])
def test_an_event_is_named_with_its_mode_and_frame(name, modes, frames, method):
    c = _event(name)
    with pytest.warns(CalibrationEventWarning) as rec:
        result = order_modes(_log(c), BASIS, method, n_resamples=0, seed=1)
    msg = str(rec[0].message)
    assert sum(isinstance(w.message, CalibrationEventWarning) for w in rec) == 1
    assert method in msg
    for label in modes:
        at = re.findall(rf"{label}: [^;)]*?(?:at frame|in frames) (\d+)", msg)
        assert at, (label, msg)
        assert frames[0] <= int(at[0]) <= frames[1], (label, at, msg)
    if method == "variance":
        # the pooled order is numpy's mean squares', event and all
        assert [BASIS.labels[i] for i in result.order] == mean_square_order(c, MODES)


def test_the_standard_and_per_frame_orderings_run_no_pass():
    c = _event("level")
    order_modes(_log(c), BASIS, "standard")          # filterwarnings = error: silent
    order_modes(_log(c), BASIS, "variance", frame=100)
    order_modes(_log(c), BASIS, "variance", quality=False)


def test_a_report_given_is_used_and_checked():
    c = _event("level")
    report = assess_quality(c)                        # array labels col0..: not the basis'
    with pytest.raises(ValueError, match="`quality` must be the QualityReport"):
        order_modes(_log(c), BASIS, "variance", quality=report)
    own = assess_quality(ModalLog(c, rate=2000.0, modes=MODES, units="rad"))
    with pytest.warns(CalibrationEventWarning, match="Z5: the mean steps"):
        order_modes(_log(c), BASIS, "variance", quality=own)
    with pytest.raises(TypeError, match="`quality` must be True, False or a QualityReport"):
        order_modes(_log(c), BASIS, "variance", quality="yes")


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("phi", [0.9, 0.99])
def test_stationary_logs_are_silent(seed, phi):
    c = _clean(seed, phi)
    result = silent_order(_log(c), BASIS)
    assert [BASIS.labels[i] for i in result.order] == mean_square_order(c, MODES)
