"""The continuous-time rejection function against the Fourier transform of the loop's lags.

Reference: ``W(f) = int h(t) exp(-2 i pi f t) dt`` integrated numerically (midpoint samples
of both boxes, ``T / 4000`` steps) for the causal impulse response of the continuous model the
docstring names: a WFS box of length ``T_i`` (the exposure's mean, what lies in the
past), a zero-order hold of one period ``T`` and the delay ``tau``, i.e. ``h`` = the
convolution of the two unit-area boxes on ``[0, T_i]`` and ``[0, T]``, shifted by
``tau``; then ``E = (1 - z^-1) / (1 - z^-1 + g W)``. Discretisation error <1e-7 here, the
tolerance 1e-5; a sign slip in any of the three phases (a lag read as an advance)
moves ``E`` by more than 0.05 at these frequencies.
"""

import numpy as np
import pytest

from modalinfo.servo import rejection_transfer_function

RATE = 1000.0
T = 1.0 / RATE


def _w_numerical(f: np.ndarray, t_i: float, tau: float) -> np.ndarray:
    dt = T / 4000.0
    box_i = np.ones(int(round(t_i / dt))) / t_i
    box_t = np.ones(int(round(T / dt))) / T
    h = np.convolve(box_i, box_t) * dt                 # [1/s], area 1
    # sample k of the discrete convolution of two midpoint-sampled boxes sits at (k + 1) dt
    t = tau + (np.arange(h.size) + 1.0) * dt
    return (h[None, :] * np.exp(-2j * np.pi * f[:, None] * t[None, :])).sum(axis=1) * dt


@pytest.mark.parametrize("delay_frames, integration_frames", [(1.3, 0.6), (0.5, 1.0)])
def test_continuous_model_is_the_fourier_transform_of_box_hold_and_delay(
        delay_frames, integration_frames):
    f = np.array([3.0, 25.0, 80.0, 170.0, 333.0, 490.0])
    gain = 0.4
    w = _w_numerical(f, integration_frames * T, delay_frames * T)
    zinv = np.exp(-2j * np.pi * f * T)
    want = (1.0 - zinv) / (1.0 - zinv + gain * w)
    got = rejection_transfer_function(f, rate=RATE, gain=gain, delay_frames=delay_frames,
                                      integration_frames=integration_frames,
                                      model="continuous")
    assert np.abs(got - want).max() < 1e-5, np.abs(got - want).max()
