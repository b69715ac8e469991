"""Bounded servo computations: long delays neither hang nor give wrong limits.

References (outside the code under test): the stability limit from the roots of the
characteristic polynomial (``np.roots`` bisected here, the former implementation); two
closed forms (no delay: ``g < 2``; a half-frame exposure and a two-frame delay:
``z**3 - z**2 + g``, whose roots reach the unit circle at ``z = exp(+-i pi / 5)``,
``g = 2 sin(pi / 10) = (sqrt 5 - 1) / 2``);
for delays too long for roots, the impulse response of the loop recursion run with
``scipy.signal.lfilter`` (decays just below the limit, grows just above it), and the
noise propagation as the sum of its squared impulse response.
"""

import math

import numpy as np
import pytest
from scipy import optimize, signal

from modalinfo import servo


def _roots_limit(delay, integ):
    """Stability limit by bisection on the largest root modulus (independent method)."""
    def excess(g):
        a = np.trim_zeros(servo.loop_denominator(g, servo.command_weights(delay, integ)), "b")
        return (np.max(np.abs(np.roots(a))) if a.size > 1 else 0.0) - 1.0

    hi = 1.0
    while excess(hi) < 0.0:
        hi *= 2.0
    return optimize.brentq(excess, 1e-9, hi, xtol=1e-13)


@pytest.mark.parametrize(("delay", "integ"), [(0.25, 0.5), (1.5, 1.0), (4.0, 0.4),
                                              (9.75, 1.0), (31.0, 0.8)])
def test_max_stable_gain_equals_the_root_locus_limit(delay, integ):
    assert servo.max_stable_gain(delay, integ) == pytest.approx(_roots_limit(delay, integ),
                                                                rel=1e-9)


def test_max_stable_gain_closed_forms():
    # no delay, full exposure: the pole is 1 - g, stable for g < 2
    assert servo.max_stable_gain(0.0, 1.0) == pytest.approx(2.0, rel=1e-12)
    # delay 2, exposure 0.5: W = z**-3, poles of z**3 - z**2 + g; on |z| = 1,
    # g = z**2 (1 - z) is real > 0 where 2 w + (w - pi) / 2 = 0, w = pi / 5, and then
    # g = |1 - z| = 2 sin(pi / 10)
    assert servo.max_stable_gain(2.0, 0.5) == pytest.approx((math.sqrt(5.0) - 1.0) / 2.0,
                                                            rel=1e-12)


@pytest.mark.parametrize("delay", [150.0, 420.5])
def test_long_delay_limit_separates_decay_from_growth(delay):
    limit = servo.max_stable_gain(delay, 1.0)
    weights = servo.command_weights(delay, 1.0)
    n = 60 * weights.size
    impulse = np.zeros(n)
    impulse[0] = 1.0
    amplitudes = []
    for g in (0.97 * limit, 1.03 * limit):
        h = signal.lfilter([1.0], servo.loop_denominator(g, weights), impulse)
        first, last = np.abs(h[: n // 3]).max(), np.abs(h[-n // 3:]).max()
        amplitudes.append(last / first)
    assert amplitudes[0] < 0.5 < 2.0 < amplitudes[1]
    with pytest.raises(ValueError, match=r"unstable .* stable for gain <"):
        servo.check_stable(1.05 * limit, delay, 1.0)
    servo.check_stable(0.95 * limit, delay, 1.0)


def test_long_delay_noise_propagation_equals_impulse_energy():
    delay, integ = 240.0, 0.7
    gain = 0.5 * servo.max_stable_gain(delay, integ)
    a = servo.loop_denominator(gain, servo.command_weights(delay, integ))
    impulse = np.zeros(400_000)
    impulse[0] = gain
    h = signal.lfilter([1.0], a, impulse)
    assert abs(h[-1000:]).max() < 1e-12 * abs(h).max()  # the reference has converged
    assert servo.noise_propagation(gain=gain, delay_frames=delay,
                                   integration_frames=integ) == pytest.approx(
        float(np.dot(h, h)), rel=1e-10)


def test_delays_beyond_the_documented_limit_are_refused():
    bad = servo.MAX_DELAY_FRAMES * 1.5
    for call in (lambda: servo.max_stable_gain(bad, 1.0),
                 lambda: servo.check_stable(0.1, bad, 1.0),
                 lambda: servo.noise_propagation(gain=0.1, delay_frames=bad),
                 lambda: servo.rejection_transfer_function([1.0], rate=1e3, gain=0.1,
                                                           delay_frames=bad)):
        with pytest.raises(ValueError, match=r"`delay_frames` must be <= 1000 frames.*got 1500"):
            call()


@pytest.mark.parametrize("gain", [1e-15, 1e-13, 1e-9, 1e-6])
@pytest.mark.parametrize(("delay", "integ"), [(0.5, 1.0), (1.5, 1.0), (2.0, 0.5)])
def test_a_tiny_gain_is_stable(gain, delay, integ):
    # every gain below the root-locus limit is stable (the integrator's pole sits at 1 - g,
    # strictly inside): a pole-modulus test within rounding of 1 refused gain 1e-13 as
    # "unstable ... stable for gain < 2.0000" (table1: gain 1e-13, delay 0.5 frame)
    assert gain < _roots_limit(delay, integ)
    servo.check_stable(gain, delay, integ)
    with pytest.raises(ValueError, match=r"unstable .* stable for gain <"):
        servo.check_stable(1.01 * _roots_limit(delay, integ), delay, integ)
