"""``modalinfo.servo.closed_loop_time_constant`` (fix56-c): ``-1 / ln r`` of the loop.

References: the closed-loop poles written by hand from the recursion
``c[k] = (1 - leak) c[k-1] + g m[k]``, ``m[k] = phi[k] - sum_j w_j c[k-j]``: with one
frame of delay and a full exposure (``W = z**-2``) they are the roots of
``z**2 - (1 - leak) z + g`` (analytic: ``((1 - leak) +- sqrt((1 - leak)**2 - 4 g)) / 2``),
with no delay (``W = z**-1``) the single pole ``1 - leak - g``; and the recursion itself
run on a step, whose error decays as ``r**k`` (its log-slope over frames 200-400).
"""

import math

import numpy as np
import pytest

from modalinfo.servo import closed_loop_time_constant


@pytest.mark.parametrize("gain", [0.01, 0.02, 0.05, 0.2])
@pytest.mark.parametrize("leak", [0.0, 0.05])
def test_one_frame_delay_is_the_analytic_pole(gain, leak):
    r = ((1 - leak) + math.sqrt((1 - leak) ** 2 - 4 * gain)) / 2  # real roots here
    tau = closed_loop_time_constant(gain, 1.0, 1.0, leak=leak)
    assert tau == pytest.approx(-1 / math.log(r), rel=1e-9)


@pytest.mark.parametrize("gain", [0.05, 0.3, 0.7])
def test_no_delay_is_one_pole(gain):
    tau = closed_loop_time_constant(gain, 0.0, 1.0)
    assert tau == pytest.approx(-1 / math.log(1 - gain), rel=1e-12)


def test_the_recursion_decays_at_that_rate():
    gain, n = 0.03, 401
    phi = np.ones(n)  # a step of turbulence at frame 0
    c = np.zeros(n)
    err = np.zeros(n)
    for k in range(n):
        applied = c[k - 2] if k >= 2 else 0.0  # one frame of delay, full exposure
        err[k] = phi[k] - applied
        c[k] = (c[k - 1] if k else 0.0) + gain * err[k]
    slope = (math.log(abs(err[400])) - math.log(abs(err[200]))) / 200
    assert -1 / slope == pytest.approx(closed_loop_time_constant(gain, 1.0, 1.0), rel=1e-6)


def test_unstable_and_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="unstable"):
        closed_loop_time_constant(1.5, 1.0, 1.0)
    with pytest.raises(ValueError, match="leak"):
        closed_loop_time_constant(0.1, 1.0, 1.0, leak=1.0)
