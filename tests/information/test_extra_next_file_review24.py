"""Planted-bug review 24 (issue 27): the refusal's spans of consecutive files at 4 kHz.

Reference: the logs' own times (numpy). At 4 kHz from 1.7e9 s the frame times are
multiples of 0.25 ms: the first file's last frame is at 1.7e9 + 0.09975 s, which a span
printed to 0.1 ms (14 digits) would show 0.5 ms-rounded away (0.2 frame); each printed
end must parse back within a tenth of a frame.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from modalinfo.information import select_inputs
from modalinfo.telemetry import ModalLog

RATE, N, T0 = 4000.0, 400, 1.7e9


def _part(k: int, seed: int) -> ModalLog:
    x = np.random.default_rng(seed).normal(size=(N, 2))
    return ModalLog(x, rate=RATE, start_time=T0 + k * N / RATE, modes=[2, 3])


def test_spans_at_4khz_parse_back_within_a_tenth_of_a_frame():
    data, extra = _part(0, 1), _part(1, 2)
    with pytest.raises(ValueError, match="`extra` must be sampled at the frames") as info:
        select_inputs(data, "Z2", extra=extra, max_lag=2, n_surrogates=19, n_resamples=19,
                      seed=0)
    spans = re.search(r"data: (\S+) \.\. (\S+) s, extra: (\S+) \.\. (\S+) s",
                      str(info.value))
    assert spans is not None
    got = [float(v) for v in spans.groups()]
    want = [data.times[0], data.times[-1], extra.times[0], extra.times[-1]]
    np.testing.assert_allclose(got, want, rtol=0, atol=0.1 / RATE)
