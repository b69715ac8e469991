"""Frames that repeat an earlier frame in every mode are counted by the quality pass.

Fixes 47-e item 1 (issue 27): round 47 PART a, D10, recorded ``assess_quality`` of a log
whose every frame is written twice as not flagged; its harness printed the report's
first 600 characters only, where ``repeated_frames`` does not appear. Measured on
bd92b25a: all 3000 repeated frames flagged (``repeated_frames``, rule of round 34 PART
b), and re-sent frames scattered through the log (2 %) flagged as ``copied_frames``.
A guard, not a fix (it passes before): the count checked against numpy's
``np.unique(rows, axis=0)`` (the reference the brief names), the clean log flagging none.
"""

from __future__ import annotations

import numpy as np

from modalinfo.telemetry import ModalLog, assess_quality, synthetic


def _repeats(rows: np.ndarray) -> int:
    return rows.shape[0] - np.unique(rows, axis=0).shape[0]


def _log():
    return synthetic.open_loop_log(range(2, 8), n_frames=3000, rate=1000.0, diameter=4.0,
                                   layers=[synthetic.Layer(r0=0.1, wind_speed=10.0)], seed=2)


def test_every_frame_twice_is_flagged_frame_by_frame():  # round 47 PART a, D10
    log = _log()
    assert assess_quality(log).flagged_frames.size == 0
    twice = ModalLog(np.repeat(log.coeffs, 2, axis=0), rate=2000.0, modes=list(log.modes))
    report = assess_quality(twice)
    assert report.repeated_frames.size == _repeats(twice.coeffs) == 3000
    np.testing.assert_array_equal(report.repeated_frames, np.arange(1, 6000, 2))
    assert "3000 repeated frame(s) equal to the frame before in every mode" in \
        report.describe()


def test_frames_re_sent_at_scattered_places_are_flagged():  # round 47 PART a, D01-D03
    log = _log()
    rng = np.random.default_rng(47)
    rows = list(log.coeffs)
    for p in np.sort(rng.choice(np.arange(100, 3000), 60, replace=False))[::-1]:
        rows.insert(p, log.coeffs[rng.integers(0, p - 50)])  # an earlier frame, not the last
    resent = ModalLog(np.array(rows), rate=1000.0, modes=list(log.modes))
    report = assess_quality(resent)
    assert report.repeated_frames.size + report.copied_frames.size == \
        _repeats(resent.coeffs) == 60
