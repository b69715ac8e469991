"""Round 23 PART b: quality assessment of logs shorter than the AR predictor's window.

Reference: the definition of an AR(p) window (a frame with its p = ``AR_ORDER``
predecessors): a log of at most p frames has none, so it must be assessed as one with
exactly p frames is (too short to test, nothing flagged) - before the fix a 3-frame log
hit a numpy broadcast error from a slice that wrapped around (``g[0:-1]``).
"""

import numpy as np
import pytest

from modalinfo.telemetry import assess_quality
from modalinfo.telemetry.quality import AR_ORDER


@pytest.mark.parametrize("frames", range(1, AR_ORDER + 2))
def test_logs_of_at_most_ar_order_frames_are_assessed_not_crashed(frames):
    x = np.random.default_rng(23).standard_normal((frames, 5))
    report = assess_quality(x)
    assert len(report.flagged_frames) == 0
