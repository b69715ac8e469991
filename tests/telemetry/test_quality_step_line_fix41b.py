"""A spread step carried by a line switching on or off is named a line, not a reordering.

Adversarial round 41 PART b, issue 27 (rows I13, V08): a 47 Hz tip line switched on at
frame 2000 was reported as "the spread steps ... Z2 at frame 2001 (x4.3); modes reordered
between two nights joined, or the loop opened?", with no word of a vibration. The quality
pass now reads the Welch spectra of the two sides of each spread step (fixes 41-b,
``LINE_CONTRAST``). References: the frequency numpy wrote into the log (the sinusoid's),
and for the plain steps that must keep the old causes, an AR(1) scaled by numpy (a
spectrum of one shape on both sides).
"""

from __future__ import annotations

import re

import numpy as np
from scipy.signal import lfilter

from modalinfo.telemetry import ModalLog, assess_quality


def _turbulence(seed, n=4000, m=3):
    rng = np.random.default_rng(seed)
    z = rng.standard_normal((n + 500, m))
    return 0.2 * lfilter([np.sqrt(1 - 0.94**2)], [1, -0.94], z, axis=0)[500:], rng


def test_a_line_switching_on_half_way_is_named_with_its_frequency():
    x, rng = _turbulence(41)
    t = np.arange(2000, 4000) / 1000.0
    x[2000:, 0] += 0.5 * np.sin(2 * np.pi * 60.0 * t + 0.7)
    report = assess_quality(ModalLog(x, rate=1000.0))
    assert [s[0] for s in report.variance_steps] == ["Z2"]
    (label, frame, freq, on), = report.step_lines
    assert (label, on) == ("Z2", True)
    assert abs(freq * 1000.0 - 60.0) < 0.5  # the zero-padded periodogram's resolution
    note = report.stationarity_note
    said = re.search(r"a line at ~([0-9.]+) Hz appears after frame", note)
    assert said and abs(float(said.group(1)) - 60.0) < 0.5, note
    assert "a vibration switching on?" in note
    assert "modes reordered" not in note


def test_a_line_switching_off_is_named_without_a_rate_in_cycles_per_frame():
    x, _ = _turbulence(7)
    x[:2000, 1] += 0.8 * np.sin(2 * np.pi * 0.025 * np.arange(2000))
    report = assess_quality(x)
    (label, _, freq, on), = report.step_lines
    assert (label, on) == ("col1", False)
    assert abs(freq - 0.025) < 5e-4
    said = re.search(r"a line at ~([0-9.]+) of the frame rate stops after frame",
                     report.stationarity_note)
    assert said and abs(float(said.group(1)) - 0.025) < 5e-4, report.stationarity_note
    assert "switching off?" in report.stationarity_note


def test_a_plain_spread_step_keeps_the_reordering_and_loop_causes():
    for seed in range(3):
        x, _ = _turbulence(100 + seed)
        x[2000:, 0] *= 3.0
        report = assess_quality(ModalLog(x, rate=1000.0))
        assert report.variance_steps and not report.step_lines
        assert "modes reordered between two nights joined" in report.stationarity_note
