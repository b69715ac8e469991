"""The next file of a night given as ``extra`` (adversarial round 34 PART b, C09).

Reference: the logs' own start times (Unix seconds, numpy). Two consecutive 400-frame
files of a 2 kHz night starting at 1.7e9 s are refused as not simultaneous (as round
9); the message printed both spans with 6 digits, "1.7e+09 .. 1.7e+09" twice, so the
reader could not see why. Each span's ends now parse back to the files' first and last
times within a tenth of a frame.
"""

from __future__ import annotations

import numpy as np

from ._extra_spans import refused_spans

RATE = 2000.0  # frames per second


def test_spans_of_consecutive_files_are_readable():
    got, want = refused_spans(RATE)
    np.testing.assert_allclose(got, want, rtol=0, atol=0.1 / RATE)
