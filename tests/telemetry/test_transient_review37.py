"""A log's closure transient (metadata ``transient_frames``) as the quality pass reads it
(review37, issue 27).

Reference (outside the code under test): the rule as documented (quality module notes,
``transient_frames``): an integer in ``[1, T - MIN_STEADY_FRAMES]`` with
``MIN_STEADY_FRAMES = 2 (AR_ORDER + 1) = 10`` frames left for the AR(4) fits; anything
else (a bool, a float, a value past the bound) is 0. Rows are counted by hand: the first
``t`` frames are frames ``0 .. t - 1``. Data: white noise (numpy), no random test.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog, assess_quality
from modalinfo.telemetry.quality import transient_frames


def _log(n: int = 400, **meta) -> ModalLog:
    x = np.random.default_rng(0).standard_normal((n, 3))
    return ModalLog(x, rate=1000.0, modes=[2, 3, 4]).with_metadata(**meta)


@pytest.mark.parametrize(("value", "want"), [
    (True, 0), (5.0, 0), (0, 0), (-3, 0), (1, 1), (7, 7),
    (390, 390), (391, 0), (400, 0)])
def test_transient_frames_takes_integers_up_to_ten_frames_short(value, want):
    assert transient_frames(_log(transient_frames=value)) == want


def test_the_note_names_the_frames_before_the_transient_ends():
    report = assess_quality(_log(transient_frames=100))
    assert report.n_frames == 400
    assert "frames 0-99 not assessed" in report.transient_note
