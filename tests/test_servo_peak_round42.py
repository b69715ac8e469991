"""The peak of |E| near the stability limit (adversarial round 42 PART a, T22-T24).

``closed_loop_bandwidth(...).max_amplification`` was the largest value of |E| on a
4097-point grid; near the stability limit the resonance is narrower than the grid step and
the grid missed it: 2,486 for 11,547 at 0.9999 of the limit (one frame of delay), 2,283
for 115,470 at 0.99999, 10,000 for 14,142 at half a frame of delay.

Reference: the hand-written rejection function of a pure integrator whose command acts
``W(z) = z**-2`` (delay_frames = 1, whole-frame integration) or ``W = (z**-1 + z**-2) / 2``
(delay 0.5), evaluated with numpy on a dense grid centred on the angle of the
closed-loop pole from ``np.roots`` and spanning 20 pole half-widths: the peak to a
relative 1e-6, independent of the package's grid.
"""

import numpy as np
import pytest

from modalinfo import servo

RATE = 1000.0


def _reference_peak(gain, weights):
    """max |E| from numpy: E = (1 - z^-1) / (1 - z^-1 + g sum w_j z^-j)."""
    weights = np.asarray(weights, dtype=float)
    denominator = np.zeros(max(weights.size, 2))
    denominator[: weights.size] += gain * weights
    denominator[0] += 1.0
    denominator[1] -= 1.0
    poles = np.roots(denominator)
    pole = poles[np.argmax(np.abs(poles))]
    centre = abs(np.angle(pole))
    half_width = max(1.0 - abs(pole), 1e-12)
    omega = np.clip(np.linspace(centre - 20 * half_width, centre + 20 * half_width, 400_001),
                    0.0, np.pi)
    zinv = np.exp(-1j * omega)
    taps = np.polyval(weights[::-1], zinv)
    return float(np.max(np.abs((1 - zinv) / (1 - zinv + gain * taps))))


@pytest.mark.parametrize("fraction, delay, weights", [
    (0.9999, 1.0, [0.0, 0.0, 1.0]),
    (0.99999, 1.0, [0.0, 0.0, 1.0]),
    (0.9999, 0.5, [0.0, 0.5, 0.5]),
    (0.99, 1.0, [0.0, 0.0, 1.0]),
])
def test_max_amplification_finds_the_resonance(fraction, delay, weights):
    np.testing.assert_allclose(servo.command_weights(delay, 1.0), np.trim_zeros(
        np.asarray(weights), "b"))  # the loop the reference writes by hand
    gain = fraction * servo.max_stable_gain(delay)
    reference = _reference_peak(gain, weights)
    got = servo.closed_loop_bandwidth(rate=RATE, gain=gain,
                                      delay_frames=delay).max_amplification
    assert got == pytest.approx(reference, rel=1e-5)


def test_max_amplification_of_a_broad_peak_unchanged():
    """A moderate gain: the peak is wide, grid and refinement agree with numpy."""
    gain = 0.5
    reference = _reference_peak(gain, [0.0, 0.0, 1.0])
    got = servo.closed_loop_bandwidth(rate=RATE, gain=gain, delay_frames=1.0)
    assert got.max_amplification == pytest.approx(reference, rel=1e-6)
