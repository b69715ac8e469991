"""A noise-free line at half the frame rate is not a change of spread (round 41 PART a V44).

Reference: ``x_t = sin(pi t + 0.5)`` is ``+-sin(0.5)``, a stationary random-phase line
whose absolute deviation from its median is ``sin(0.5)`` at every frame (numpy: equal to
round-off). ``assess_quality`` reported "the spread steps or drifts in 1 mode(s) (Z2 at
frame 9972 (x1))" and ``stationary=False`` for it: a ratio of 1 read as a step because
the deviations' own variance is round-off. The other modes are AR(1) turbulence (rho
0.99), stationary by construction.
"""

import numpy as np

from modalinfo.telemetry import ModalLog, assess_quality


def _log():
    n = 20000
    rng = np.random.default_rng(3)
    coeffs = np.zeros((n, 5))
    e = 0.1 * rng.standard_normal((n, 5))
    for i in range(1, n):
        coeffs[i] = 0.99 * coeffs[i - 1] + e[i]
    line = np.sin(np.pi * np.arange(n) + 0.5)
    dev = np.abs(line - np.median(line))
    assert np.ptp(dev) < 1e-9 * dev.max()  # the reference: a constant spread (sin(pi t) rounds)
    coeffs[:, 0] = line
    return ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4, 5, 6])


def test_rate_half_line_is_not_a_spread_step():
    report = assess_quality(_log())
    assert not report.variance_steps, report.note
    assert report.stationary is not False, report.note
