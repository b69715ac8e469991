"""The budget's noise term and the noise floor of a leaky loop (adversarial round 54 PART a).

References: (1) the command noise of the leaky integrator, the sum of squares of the
impulse response of ``g / (1 - (1 - leak) z**-1 + g z**-2)`` (kaos' timing: one frame of
delay, whole-frame exposure) computed here with ``scipy.signal.lfilter``; the floor's
noise draws are seeded by the run's seed, so the floors of two runs differing only in the
leak are in the ratio of their propagation factors exactly. (2) The simulated residual
itself: with no turbulence to speak of (D/r0 1e-3) the science residual is the noise
alone, and the budget's noise term must match it (round 54: 0.96-1.01 over 3 seeds at
leaks 0, 0.2 and 0.5; one seed's spread is 3 %). Before the fix both ignored the leak:
at leak 0.5 the term was the leak-free 0.00063 rad^2 against 0.00038 measured (x1.65).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest
from scipy import signal

from closedloop import presets, simulate
from closedloop.config import FieldConfig


def _config(leak: float):
    base = presets.get("kaos")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # "total r0 ... beyond 1 m"
        return dataclasses.replace(
            base, field=FieldConfig(size=0.0, n_points=1),
            layers=tuple(dataclasses.replace(layer, d_over_r0=1e-3) for layer in base.layers),
            loop=dataclasses.replace(base.loop, leak=leak),
            wfss=tuple(dataclasses.replace(w, noise=0.01) for w in base.wfss))


def _impulse_sum(gain: float, leak: float) -> float:
    impulse = np.zeros(100_000)
    impulse[0] = 1.0
    h = signal.lfilter([gain], [1.0, -(1.0 - leak), gain], impulse)
    return float(np.sum(h ** 2))


def test_noise_floor_scales_with_the_leaky_propagation():
    floors = {leak: simulate(_config(leak), 0.02, seed=3, progress=False).noise_floor
              for leak in (0.0, 0.5)}
    gain = _config(0.0).loop.gain
    expected = _impulse_sum(gain, 0.5) / _impulse_sum(gain, 0.0)  # 0.605
    assert floors[0.5] / floors[0.0] == pytest.approx(expected, rel=1e-6)


def test_budget_noise_term_matches_a_noise_only_leaky_loop():
    r = simulate(_config(0.5), 1.0, seed=1, progress=False, budget_every=10)
    measured = float(r.residual_variance[200:].mean())
    ratio = float(np.mean(r.budget.noise)) / measured
    assert 0.9 < ratio < 1.1, ratio  # 1.014 after the fix, 1.65 before
