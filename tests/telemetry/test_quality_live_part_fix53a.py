"""Outlier scales from the live part of a mode gone dead or x0.001 (fix53-a, issue 27).

Round 52 PART a, L11 / L26 (stop 59 note): a mode gone dead (exact zeros) or scaled
x0.001 over the last 40 % of a log shrank its pooled 1.4826 MAD x0.3, and ~466 normal
values of the live part were flagged as outliers (then clipped or dropped by the
policies). The spread rule's step now leaves the quiet side, a minority of the frames,
out of that mode's median / MAD and its AR innovations' scale.

References (outside the code): numpy's median and MAD of the live frames (the planted
frames 0 .. 11,999), times 1 / Phi^-1(3/4) from scipy; the planted event; an AR(1) 0.9
log from ``scipy.signal.lfilter`` (seeded; its 1 % family-wise false-flag rate means a
new seed may flag a value of a clean mode: the clean modes are not asserted on).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter
from scipy.stats import norm

from modalinfo.telemetry import ModalLog, apply_outlier_policy, assess_quality

N, STEP = 20000, 12000


def _log(event: str) -> np.ndarray:
    rng = np.random.default_rng(530)
    e = rng.standard_normal((N + 2000, 4)) * np.sqrt(1.0 - 0.81) * 0.05
    c = lfilter([1.0], [1.0, -0.9], e, axis=0)[2000:]
    if event == "dead":
        c[STEP:, 1] = 0.0
    elif event == "gain0.001":
        c[STEP:, 1] *= 1e-3
    elif event == "gain1000":
        c[STEP:, 1] *= 1e3
    return c


def _numpy_sigma(x: np.ndarray) -> float:
    return float(np.median(np.abs(x - np.median(x))) / norm.ppf(0.75))


@pytest.mark.parametrize("event", ["dead", "gain0.001"])
def test_the_scale_comes_from_the_live_part(event):
    c = _log(event)
    report = assess_quality(ModalLog(c, rate=1000.0, modes=[2, 3, 4, 5], units="rad"))
    live = _numpy_sigma(c[:STEP, 1])
    pooled = _numpy_sigma(c[:, 1])
    assert pooled < 0.5 * live                        # what the pass used before
    # the live rows end where the spread rule locates the step (within ~50 frames)
    np.testing.assert_allclose(report.sigma[1], live, rtol=0.01)
    assert report.outliers[1] == 0                    # before: hundreds of live values
    assert any(label == "Z3" for label, *_ in report.variance_steps)   # still named
    new, _ = apply_outlier_policy(ModalLog(c, rate=1000.0, modes=[2, 3, 4, 5],
                                           units="rad"), "clip")
    np.testing.assert_array_equal(new.coeffs[:STEP, 1], c[:STEP, 1])  # nothing replaced


def test_a_dead_mode_is_still_stuck():
    report = assess_quality(_log("dead"))
    assert report.stuck[1] == N - STEP


def test_a_loud_minority_keeps_the_normal_scale():
    # x1000 over 40 %: the quiet side is the normal majority, whose scale is kept, and the
    # loud segment stays flagged (round 52 PART a, L06 / L07)
    c = _log("gain1000")
    report = assess_quality(c)
    np.testing.assert_allclose(report.sigma[1], _numpy_sigma(c[:, 1]), rtol=1e-12)
    assert report.outliers[1] > 0.95 * (N - STEP)
