"""The servo's frequency responses refuse an unstable loop (round 9, rows sv-*-unstable).

Reference: the stability limit of the integrator with a one-frame delay and one-frame
integration, g < 2 sin(pi / (2 (2 d + 1))) = 1 for d = 1 (the characteristic equation
z^2 - z + g = 0 has a root on the unit circle at g = 1). At g = 1.5 the loop diverges,
yet closed_loop_bandwidth reported a 0 dB bandwidth of 130 Hz at 1 kHz and the transfer
functions finite values; at g = 0.99 all three still answer.
"""

import numpy as np
import pytest

from modalinfo import servo

KW = dict(rate=1000.0, delay_frames=1.0)


@pytest.mark.parametrize("call", [
    lambda g: servo.closed_loop_bandwidth(gain=g, **KW),
    lambda g: servo.rejection_transfer_function(np.array([10.0]), gain=g, **KW),
    lambda g: servo.noise_transfer_function(np.array([10.0]), gain=g, **KW),
])
def test_unstable_gain_refused_stable_gain_answered(call):
    assert 2 * np.sin(np.pi / 6) == pytest.approx(1.0)
    call(0.99)
    with pytest.raises(ValueError, match="unstable"):
        call(1.01)
    with pytest.raises(ValueError, match="unstable"):
        call(1.5)


def test_tiny_gain_bandwidth_follows_the_first_order_law():
    # row se-servo-tiny-gain: at g = 1e-9 the crossing lies below 1e-9 Nyquist and brentq
    # answered "f(a) and f(b) must have different signs". For g << 1 the closed loop
    # g / (1 - z^-1 + g z^-2) is a first-order low-pass of corner g rate / (2 pi).
    for g in (1e-9, 1e-12):
        bw = servo.closed_loop_bandwidth(gain=g, **KW)
        assert bw.closed_loop_3db == pytest.approx(g * KW["rate"] / (2 * np.pi), rel=1e-6)
