"""Step lines: on and off kept apart, short sides not judged (review27).

Planted bugs of review27 (docs/MUTATION.md, round 27) that the fixes-41-b file let
through: lines of one frequency grouped whether they appear or stop (a 60 Hz line
switching on in one mode and off in another read as one line appearing), and the
512-frame floor of a side lowered to 128. References: the sinusoids numpy wrote into
the log (their frequency, and on which side of the step they are), and the docstring of
``quality._step_line`` ("sides shorter than 512 frames are not judged").
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

from modalinfo.telemetry import ModalLog, assess_quality
from modalinfo.telemetry.quality import _step_line


def _turbulence(seed, n=4000, m=3):
    rng = np.random.default_rng(seed)
    z = rng.standard_normal((n + 500, m))
    return 0.2 * lfilter([np.sqrt(1 - 0.94**2)], [1, -0.94], z, axis=0)[500:]


def test_a_line_switching_on_in_one_mode_and_off_in_another_is_named_twice():
    x = _turbulence(41)
    t = np.arange(4000) / 1000.0
    line = 0.5 * np.sin(2 * np.pi * 60.0 * t + 0.7)
    x[2000:, 0] += line[2000:]
    x[:2000, 1] += line[:2000]
    report = assess_quality(ModalLog(x, rate=1000.0))
    assert sorted((s[0], s[3]) for s in report.step_lines) == [("Z2", True), ("Z3", False)]
    note = report.stationarity_note
    assert "appears after frame" in note and "switching on?" in note, note
    assert "stops after frame" in note and "switching off?" in note, note


def test_a_side_shorter_than_512_frames_is_not_judged():
    rng = np.random.default_rng(5)
    column = 0.2 * rng.standard_normal(4000)
    column[3600:] += 0.8 * np.sin(2 * np.pi * 0.06 * np.arange(400))
    # 400 frames after the step: below the floor, whatever the spectra
    assert _step_line(column.copy(), 3600, 4.0) is None
    # the same line with 600 frames after it is judged and found (the floor is 512)
    column = 0.2 * rng.standard_normal(4000)
    column[3400:] += 0.8 * np.sin(2 * np.pi * 0.06 * np.arange(600))
    found = _step_line(column.copy(), 3400, 4.0)
    assert found is not None and abs(found - 0.06) < 2e-3
