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
