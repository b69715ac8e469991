"""The quality pass on telemetry with a vibration line: no false swap, no missed step.

Adversarial round 41 PART b, issue 27 (rows F03 / P01: a line at a quarter of the
frame rate; V09: a line switched off mid-log).

1. A line at rate / 4 (250 Hz at 1 kHz), ``A sin(pi t / 2 + phi)``, has lag-1
   products ``(A^2 / 2) (-1)^t sin(2 phi)``: the parity pattern of frames written in
   pairs in reverse order, with the frames in order. Before, 0.5 rad of such a line on
   tip over AR(1) turbulence was said "frames in swapped pairs? ... lags and
   predictions are wrong" in 10 of 10 in-order logs (and 9 of 10 at 0.05 rad). The
   frames are in order by construction here (numpy); the same logs with every pair
   swapped by numpy are still found swapped.
2. A 25 Hz line of 0.8 rad on one mode in the first half only: that mode's standard
   deviation falls by x0.3 at the half (numpy on the halves). Before, its absolute
   deviations' lag-1 autocorrelation, taken across the step itself, put it under the
   spread rule's effective-sample floor: not judged, and no word (AR(1) 0.94 under
   the line: missed in 5 of 5 logs with a 0.8 rad line, found in 5 of 5 with 0.5 rad:
   the larger step went unsaid).

Reference, outside the code: the construction (numpy draws, numpy's pair swap) and
numpy's standard deviations of the two halves.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog, assess_quality

T = 4000
RATE = 1000.0


def turbulence(seed: int, modes: int, phi: float = 0.9, rms: float = 0.2) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((T, modes)) * rms * np.sqrt(1 - phi ** 2)
    x = np.zeros((T, modes))
    x[0] = rng.standard_normal(modes) * rms
    for t in range(1, T):
        x[t] = phi * x[t - 1] + e[t]
    return x


def quarter_line_log(seed: int) -> np.ndarray:
    x = turbulence(seed, 3)
    x[:, 0] += 0.5 * np.sin(2 * np.pi * (RATE / 4) * np.arange(T) / RATE + 0.3 + 0.1 * seed)
    return x


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_line_at_quarter_rate_is_not_a_pair_swap(seed):
    report = assess_quality(ModalLog(quarter_line_log(seed), rate=RATE))
    assert report.pair_order == ()
    assert "swapped pairs" not in report.describe()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_swapped_pairs_with_a_quarter_rate_line_are_still_found(seed):
    x = quarter_line_log(seed)
    z = x.copy()
    z[0::2], z[1::2] = x[1::2], x[0::2]
    report = assess_quality(ModalLog(z, rate=RATE))
    assert report.pair_order
    assert report.pair_order[0] > report.pair_order[1]  # the 2k -> 2k + 1 products


@pytest.mark.parametrize("seed", [0, 1])
def test_line_switched_off_mid_log_is_a_spread_step(seed):
    x = turbulence(seed, 10, phi=0.94, rms=0.17)
    line = 0.8 * np.sin(2 * np.pi * 25.0 * np.arange(T) / RATE)
    line[T // 2:] = 0.0
    x[:, 1] += line
    ratio = x[T // 2:, 1].std() / x[:T // 2, 1].std()
    assert ratio < 0.4  # the planted step, by numpy
    report = assess_quality(ModalLog(x, rate=RATE))
    steps = {label: (frame, r) for label, frame, r, _ in report.variance_steps}
    label = report.labels[1]
    assert label in steps
    frame, r = steps[label]
    assert abs(frame - T // 2) <= T // 50
    assert r < 0.5
