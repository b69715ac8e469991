"""The servo model's leaky rejection against the simulator's leaky loop (fix54-e, issue 27).

Reference: the simulator itself, on a noise-free kaos loop with ``loop.leak = 0.3`` (1 s,
seed 0): its modal residual ``dm0.residual`` is the rejection of its loop applied to its
pseudo-open loop ``dm0.pol`` (noise-free, ``r = E(z) pol`` per mode exactly, from a flat
mirror). ``modalinfo.servo.rejection_transfer_function(..., leak=0.3)`` applied to the POL
by a zero-padded FFT (a linear convolution: the loop's poles, modulus 0.68, leave nothing
of the impulse response past the padding) must give that residual to rounding (3e-15
measured, 1e-9 asked). Before fix54-e the rejection had no ``leak`` (TypeError); its
leak-free answer predicts x0.007 of the servo-lag variance this loop leaves (the test
says it is off). The error budget, whose temporal term is a leaky copy of the controller,
adds up to the measured residual (field mean) within its stated 15 % (1.046 measured).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from closedloop import presets, simulate
from modalinfo.servo import rejection_transfer_function

LEAK = 0.3


@pytest.fixture(scope="module")
def run():
    base = presets.get("kaos")
    cfg = dataclasses.replace(base, loop=dataclasses.replace(base.loop, leak=LEAK),
                              wfss=tuple(dataclasses.replace(w, noise=0.0)
                                         for w in base.wfss))
    return cfg, simulate(cfg, 1.0, seed=0, progress=False, budget_every=10)


def _predicted(cfg, pol: np.ndarray, leak: float) -> np.ndarray:
    n = 1 << int(np.ceil(np.log2(2 * pol.shape[0])))
    rate = 1.0 / cfg.loop.time_step
    e = rejection_transfer_function(
        np.fft.rfftfreq(n, 1.0 / rate), rate=rate, gain=cfg.loop.gain,
        delay_frames=cfg.loop.delay_frames, integration_frames=cfg.loop.integration_frames,
        leak=leak)
    return np.fft.irfft(np.fft.rfft(pol, n, axis=0) * e[:, None], n, axis=0)[:pol.shape[0]]


def test_simulated_leaky_residual_is_the_leaky_rejection(run):
    cfg, result = run
    pol = np.asarray(result.logs["dm0.pol"].coeffs)
    residual = np.asarray(result.logs["dm0.residual"].coeffs)
    np.testing.assert_allclose(_predicted(cfg, pol, LEAK), residual, rtol=0, atol=1e-9)
    # the pure integrator's rejection is not this loop's servo lag
    free = _predicted(cfg, pol, 0.0)[200:]
    assert np.sum(free ** 2) < 0.1 * np.sum(residual[200:] ** 2)


def test_budget_adds_up_on_a_leaky_loop(run):
    _, result = run
    b = result.budget
    assert float(b.total.mean() / b.measured.mean()) == pytest.approx(1.0, abs=0.15)
