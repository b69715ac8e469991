"""The quality pass on noise-free vibration lines: not called non-stationary.

Adversarial round 28 PART a, issue 27 (row V-q-pure). A sinusoid of random phase is
strictly stationary (its law is invariant under a time shift: analytic), so a log of
noise-free 30 / 250 / 333 Hz lines sampled at 1 kHz (a simulated telescope vibration)
must not be reported ``stationary=False`` with the note "the innovations' scale changes
x15 ... (seeing not steady?)": the AR(4) innovations of such a line are round-off
(1e-15 to 9e-13 of the values' scale, measured), whose block-to-block ratio says nothing
of the seeing. With white noise 1e-6 of the line added (innovations of a known scale,
stationary by construction) the pass judges and finds the log steady.

Reference, outside the code: the stationarity of a random-phase sinusoid and of white
noise (their laws are shift-invariant), the seeded noise being drawn by numpy.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog, assess_quality

T = 20000
RATE = 1000.0


def lines(freq: float, noise: float) -> ModalLog:
    t = np.arange(T) / RATE
    coeffs = np.stack([np.sin(2 * np.pi * freq * t + phase) for phase in (0.0, 1.0, 2.0, 3.0)],
                      axis=1)
    coeffs += noise * np.random.default_rng(28).standard_normal(coeffs.shape)
    return ModalLog(coeffs, rate=RATE)


@pytest.mark.parametrize("freq", [30.0, 250.0, 333.0])
def test_noise_free_line_is_not_called_non_stationary(freq):
    report = assess_quality(lines(freq, 0.0))
    assert report.stationary is not False
    assert "seeing not steady" not in report.note
    assert report.clean


@pytest.mark.parametrize("freq", [30.0, 333.0])
def test_line_with_noise_is_judged_steady(freq):
    report = assess_quality(lines(freq, 1e-6))
    assert report.stationary is True
    assert report.scale_ratio < 1.5
