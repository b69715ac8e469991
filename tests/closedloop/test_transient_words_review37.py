"""``closedloop.aot``'s transient card and words (review37, issue 27).

Reference (outside the code under test): the rows counted by hand: a steady state from
frame 7 on leaves frames 0-6 as the closure transient, written as the ``MI_TRANS`` card
7; no transient (start 0) writes no card and no words. The result is a stand-in with
the one attribute read (``transient_frames`` since fix56-c), so no simulation is run.
"""

from __future__ import annotations

from types import SimpleNamespace

from closedloop.aot import _transient_card, _transient_words


def test_the_transient_is_frames_before_the_steady_start():
    result = SimpleNamespace(transient_frames=7)  # its source since fix56-c
    assert _transient_card(result) == {"MI_TRANS": 7}
    assert "frames 0-6 are the loop's closure transient" in _transient_words(result)
    none = SimpleNamespace(transient_frames=0)
    assert _transient_card(none) == {} and _transient_words(none) == ""
