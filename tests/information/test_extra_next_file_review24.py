"""Planted-bug review 24 (issue 27): the refusal's spans of consecutive files at 4 kHz.

Reference: the logs' own times (numpy). At 4 kHz from 1.7e9 s the frame times are
multiples of 0.25 ms: the first file's last frame is at 1.7e9 + 0.09975 s, which a span
printed to 0.1 ms (14 digits) would show 0.5 ms-rounded away (0.2 frame); each printed
end must parse back within a tenth of a frame.
"""

from __future__ import annotations

import numpy as np

from ._extra_spans import refused_spans

RATE = 4000.0  # frames per second


def test_spans_at_4khz_parse_back_within_a_tenth_of_a_frame():
    got, want = refused_spans(RATE)
    np.testing.assert_allclose(got, want, rtol=0, atol=0.1 / RATE)
