"""The integrator's leak through the rejection and the bandwidths (fix54-e, issue 27).

Reference: ``scipy.signal.freqz`` of the leaky integrator loop with delay, written here by
hand: ``E(z) = L(z) / (L(z) + g W(z))``, ``L = 1 - (1 - leak) z**-1``, i.e. ``1 / (1 + C(z)
W(z))`` with ``C = g / (1 - (1 - leak) z**-1)``; with a whole-frame exposure the WFS sees
the command of ``d + 1`` frames earlier (``W = z**-(d + 1)``, one frame of delay is kaos'
``[1, -(1 - leak), g]``) and half of each of two at ``d = 0.5``. The bandwidths are read
off the same ``freqz`` on a 200001-point grid (the 0 dB crossing by linear interpolation
between grid points 5 mHz apart, the peak as the grid's largest value: both within 1e-3
of the package's Brent-refined values). ``E(0) = leak / (leak + g)`` analytically.
Before fix54-e ``rejection_transfer_function``, ``closed_loop_bandwidth`` and
``gain_for_bandwidth`` took no ``leak`` (TypeError).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from modalinfo.servo import (
    closed_loop_bandwidth,
    gain_for_bandwidth,
    max_stable_gain,
    noise_transfer_function,
    rejection_transfer_function,
)

RATE = 2000.0
# hand-written W(z) coefficients (powers of z**-1) for a whole-frame exposure
WEIGHTS = {0.0: [0.0, 1.0], 0.5: [0.0, 0.5, 0.5], 1.0: [0.0, 0.0, 1.0],
           2.0: [0.0, 0.0, 0.0, 1.0]}


def _own(gain: float, delay: float, leak: float) -> tuple[np.ndarray, np.ndarray]:
    """Numerator ``L`` and denominator ``L + g W`` of the rejection, by hand."""
    w = np.array(WEIGHTS[delay])
    b = np.array([1.0, -(1.0 - leak)])
    a = gain * w
    a[: b.size] += b
    return b, a


@pytest.mark.parametrize("delay", sorted(WEIGHTS))
@pytest.mark.parametrize("leak", [0.0, 0.05, 0.2, 0.5, 0.9])
def test_rejection_is_the_leaky_loop_of_freqz(delay, leak):
    gain = 0.5 * max_stable_gain(delay, 1.0, leak=leak)
    freqs = np.linspace(0.0, RATE / 2, 1001)
    b, a = _own(gain, delay, leak)
    _, expected = signal.freqz(b, a, worN=freqs, fs=RATE)
    got = rejection_transfer_function(freqs, rate=RATE, gain=gain, delay_frames=delay,
                                      leak=leak)
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-14)
    assert abs(got[0]) == pytest.approx(leak / (leak + gain), abs=1e-14)


@pytest.mark.parametrize("leak", [0.2, 0.5])
def test_noise_and_rejection_add_up(leak):
    """``E + N W = 1`` (residual plus what the mirror holds is the input): both from one model."""
    freqs = np.linspace(1.0, 999.0, 50)
    kw = dict(rate=RATE, gain=0.4664, delay_frames=1.0, leak=leak)
    e = rejection_transfer_function(freqs, **kw)
    n = noise_transfer_function(freqs, **kw)
    w = np.exp(-2j * np.pi * freqs / RATE * 2)  # W = z**-2 at one frame of delay
    np.testing.assert_allclose(e + n * w, 1.0, atol=1e-13)


@pytest.mark.parametrize(("delay", "leak"), [(1.0, 0.2), (1.0, 0.5), (2.0, 0.3),
                                             (0.5, 0.1)])
def test_bandwidth_of_a_leaky_loop(delay, leak):
    gain = 0.4 * max_stable_gain(delay, 1.0, leak=leak)
    grid = np.linspace(0.0, RATE / 2, 200001)
    b, a = _own(gain, delay, leak)
    _, h = signal.freqz(b, a, worN=grid, fs=RATE)
    mag = np.abs(h)
    i = int(np.flatnonzero(mag >= 1.0)[0])
    crossing = grid[i - 1] + (1.0 - mag[i - 1]) / (mag[i] - mag[i - 1]) * (grid[i] - grid[i - 1])
    bw = closed_loop_bandwidth(rate=RATE, gain=gain, delay_frames=delay, leak=leak)
    assert bw.rejection_0db == pytest.approx(crossing, abs=1e-3)
    assert bw.max_amplification == pytest.approx(mag.max(), rel=1e-6)
    free = closed_loop_bandwidth(rate=RATE, gain=gain, delay_frames=delay)
    assert bw.rejection_0db > free.rejection_0db + 1.0  # the leak moves it: not the old answer


def test_closed_loop_3db_of_a_large_leak_is_zero():
    """``|1 - E(0)| = g / (g + leak)`` below 1/sqrt(2): the -3 dB point is at 0 Hz."""
    bw = closed_loop_bandwidth(rate=RATE, gain=0.1, delay_frames=1.0, leak=0.5)
    assert bw.closed_loop_3db == 0.0


def test_gain_for_bandwidth_with_a_leak():
    gain = gain_for_bandwidth(130.0, rate=RATE, delay_frames=1.0, leak=0.2)
    b, a = _own(gain, 1.0, 0.2)
    # |E| = 1 at 130 Hz for that gain, by freqz
    _, h = signal.freqz(b, a, worN=[130.0], fs=RATE)
    assert abs(h[0]) == pytest.approx(1.0, abs=1e-8)


@pytest.mark.parametrize("bad", [-0.1, 1.0, float("nan"), "0.2"])
def test_bad_leak_named(bad):
    with pytest.raises((ValueError, TypeError), match="leak"):
        rejection_transfer_function([1.0], rate=RATE, gain=0.3, delay_frames=1.0, leak=bad)
    with pytest.raises((ValueError, TypeError), match="leak"):
        closed_loop_bandwidth(rate=RATE, gain=0.3, delay_frames=1.0, leak=bad)


def test_leak_default_is_the_pure_integrator():
    freqs = np.linspace(0.0, 1000.0, 101)
    kw = dict(rate=RATE, gain=0.4664, delay_frames=1.0)
    np.testing.assert_array_equal(rejection_transfer_function(freqs, **kw),
                                  rejection_transfer_function(freqs, **kw, leak=0.0))
    b, a = _own(0.4664, 1.0, 0.0)
    _, h = signal.freqz(b, a, worN=freqs, fs=RATE)
    np.testing.assert_allclose(rejection_transfer_function(freqs, **kw), h, atol=1e-13)
