"""``quality.calibration_event_list``: six events shown, the count of all (review37, issue 27).

Reference (outside the code under test): the events written by hand; the documented
form ``label: words`` joined by ``; ``, the first six, then ``; ... (N events)``.
"""

from __future__ import annotations

from modalinfo.telemetry.quality import calibration_event_list


def test_more_than_six_events_are_counted():
    events = tuple((j, f"m{j}", 100 * j, f"words {j}") for j in range(8))
    labels = [f"Z{j}" for j in range(8)]
    text = calibration_event_list(events, labels)
    assert text.startswith("Z0: words 0; Z1: words 1")
    assert "Z5: words 5" in text and "Z6" not in text
    assert text.endswith("; ... (8 events)")
    assert calibration_event_list(events[:6], labels).endswith("Z5: words 5")


def test_logs_under_2000_frames_are_not_judged():
    # documented floor CALIBRATION_MIN_FRAMES = 2000: a +10 sd step in 1,999 frames of
    # white noise is not judged (no pass run), the same step in 2,000 frames is named
    import numpy as np

    from modalinfo.telemetry.quality import calibration_events

    x = np.random.default_rng(0).standard_normal((2000, 2))
    x[1000:, 0] += 10.0
    assert calibration_events(x[:1999]) == ()
    assert [e[0] for e in calibration_events(x)] == [0]
