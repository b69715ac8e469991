"""Tests of modalinfo.servo, the one servo model of the package.

References: the noise propagation is checked against a direct numerical integral of
|N(f)|^2 (scipy.integrate.quad) and against a brute-force time-domain integrator loop
written out here step by step (zero-order hold on a fine grid).
"""

import numpy as np
import pytest
from scipy import integrate

from modalinfo import servo


@pytest.mark.parametrize("gain,delay,integ", [(0.5, 0.5, 1.0), (0.3, 1.0, 1.0), (0.8, 0.25, 0.5)])
def test_noise_propagation_equals_band_integral(gain, delay, integ):
    rate = 1000.0

    def sq(f):
        n = servo.noise_transfer_function(np.array([f]), rate=rate, gain=gain,
                                          delay_frames=delay, integration_frames=integ)
        return abs(n[0]) ** 2

    integral, _ = integrate.quad(sq, 0.0, rate / 2, limit=500)
    expected = integral / (rate / 2)
    assert servo.noise_propagation(gain=gain, delay_frames=delay,
                                   integration_frames=integ) == pytest.approx(expected, rel=1e-6)


def _brute_force_commands(noise, gain, delay_steps, int_steps, oversampling):
    """Integrator fed with white noise only, the mirror held on a fine grid."""
    n_frames = noise.size
    mirror = np.zeros(n_frames * oversampling + delay_steps + oversampling)
    c = 0.0
    commands = np.empty(n_frames)
    for k in range(n_frames):
        window = mirror[(k + 1) * oversampling - int_steps:(k + 1) * oversampling]
        m = -window.mean() + noise[k]
        c = c + gain * m
        commands[k] = c
        mirror[(k + 1) * oversampling + delay_steps:] = c
    return commands


@pytest.mark.parametrize("gain,delay,integ", [(0.5, 0.5, 1.0), (0.4, 1.0, 0.5)])
def test_noise_propagation_matches_a_simulated_loop(gain, delay, integ):
    # 6e4 frames: the relative standard error of a variance of a correlated AR-like series
    # is ~ sqrt(2 tau / n) ~ 1e-2 (tau ~ 3 frames), so 5 % is ~ 4 s.e.
    oversampling = 4
    rng = np.random.default_rng(1)
    noise = rng.standard_normal(60_000)
    cmd = _brute_force_commands(noise, gain, round(delay * oversampling),
                                round(integ * oversampling), oversampling)
    measured = np.var(cmd[1000:])
    expected = servo.noise_propagation(gain=gain, delay_frames=delay, integration_frames=integ)
    assert measured == pytest.approx(expected, rel=0.05)


def test_noise_transfer_unity_at_zero_frequency_and_errors():
    n0 = servo.noise_transfer_function([0.0], rate=1000.0, gain=0.4, delay_frames=1.0)
    assert n0[0] == pytest.approx(1.0)
    with pytest.raises(ValueError, match="gain"):
        servo.noise_propagation(gain=5.0, delay_frames=1.0)
    with pytest.raises(ValueError, match="integration_frames"):
        servo.noise_transfer_function([1.0], rate=1000.0, gain=0.4, delay_frames=1.0,
                                      integration_frames=2.0)
