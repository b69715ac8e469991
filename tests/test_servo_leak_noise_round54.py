"""The integrator's leak in the noise propagation (adversarial round 54 PART a, issue 27).

Reference: the impulse response of ``N = g / (1 - (1 - leak) z**-1 + g W(z))`` computed
here with ``scipy.signal.lfilter`` on the command recursion ``c[k] = (1 - leak) c[k-1] +
g (n[k] - (W c)[k])``, with the weights ``W`` written out by hand for whole-frame and
half-frame delays and a whole-frame exposure: its sum of squares is the command variance
per unit of white WFS noise (Parseval). Before the fix ``noise_propagation`` and
``noise_transfer_function`` had no ``leak`` (a TypeError), and the closed loop's budget and
noise floor used the leak-free value: x1.31 too high at leak 0.2 and x1.65 at 0.5.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from modalinfo.servo import noise_propagation, noise_transfer_function

# the weights by hand: the command c[k-j] covers the fraction w_j of frame k's exposure
# (a command d whole frames late covers the whole exposure d + 1 frames on; half a frame
# late, half of the next exposure and half of the one after)
WEIGHTS = {0.0: [0.0, 1.0], 0.5: [0.0, 0.5, 0.5], 1.0: [0.0, 0.0, 1.0],
           2.0: [0.0, 0.0, 0.0, 1.0]}


def _denominator(gain: float, delay: float, leak: float) -> np.ndarray:
    a = gain * np.array(WEIGHTS[delay])
    a[0] += 1.0
    a[1] -= 1.0 - leak
    return a


def _impulse_sum(gain: float, delay: float, leak: float) -> float:
    impulse = np.zeros(200_000)
    impulse[0] = 1.0
    h = signal.lfilter([gain], _denominator(gain, delay, leak), impulse)
    return float(np.sum(h ** 2))


@pytest.mark.parametrize("delay, gain", [(0.0, 0.8), (0.5, 0.9), (1.0, 0.4664), (2.0, 0.3)])
@pytest.mark.parametrize("leak", [0.0, 0.2, 0.5, 0.9])
def test_noise_propagation_with_leak_is_the_impulse_sum(delay, gain, leak):
    assert noise_propagation(gain=gain, delay_frames=delay, leak=leak) == pytest.approx(
        _impulse_sum(gain, delay, leak), rel=1e-9)


def test_leak_lowers_the_noise_as_measured_in_round54():
    # round 54 PART a's kaos timing: 0.5197 leak-free, 0.3958 at 0.2, 0.3146 at 0.5
    values = [noise_propagation(gain=0.4664, delay_frames=1.0, leak=k) for k in (0, 0.2, 0.5)]
    assert values == pytest.approx([0.51967, 0.39581, 0.31458], abs=1e-5)


@pytest.mark.parametrize("leak", [0.0, 0.3])
def test_noise_transfer_function_with_leak(leak):
    f = np.array([0.0, 10.0, 130.0, 999.0])
    z_inv = np.exp(-2j * np.pi * f / 2000.0)
    expected = 0.4664 / (1.0 - (1.0 - leak) * z_inv + 0.4664 * z_inv ** 2)
    got = noise_transfer_function(f, rate=2000.0, gain=0.4664, delay_frames=1.0, leak=leak)
    np.testing.assert_allclose(got, expected, rtol=1e-12)
    # Parseval: the band's mean of |N|^2 is the propagation factor
    grid = (np.arange(1 << 16) + 0.5) / (1 << 16) * 1000.0
    band = noise_transfer_function(grid, rate=2000.0, gain=0.4664, delay_frames=1.0, leak=leak)
    assert float(np.mean(np.abs(band) ** 2)) == pytest.approx(
        noise_propagation(gain=0.4664, delay_frames=1.0, leak=leak), rel=1e-6)


@pytest.mark.parametrize("leak", [-0.1, 1.0])
def test_bad_leak_refused_by_name(leak):
    with pytest.raises(ValueError, match="`leak`"):
        noise_propagation(gain=0.4, delay_frames=1.0, leak=leak)


def test_leak_moves_the_limit_here_too():
    # no delay, whole-frame exposure: stable below 2 - leak (round 20)
    assert np.isfinite(noise_propagation(gain=1.7, delay_frames=0.0, leak=0.2))
    with pytest.raises(ValueError, match="unstable"):
        noise_propagation(gain=1.7, delay_frames=0.0, leak=0.5)
