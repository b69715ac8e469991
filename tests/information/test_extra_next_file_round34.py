"""The next file of a night given as ``extra`` (adversarial round 34 PART b, C09).

Reference: the logs' own start times (Unix seconds, numpy). Two consecutive 400-frame
files of a 2 kHz night starting at 1.7e9 s are refused as not simultaneous (as round
9); the message printed both spans with 6 digits, "1.7e+09 .. 1.7e+09" twice, so the
reader could not see why. Each span's ends now parse back to the files' first and last
times within a tenth of a frame.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from modalinfo.information import select_inputs
from modalinfo.telemetry import ModalLog

RATE, N, T0 = 2000.0, 400, 1.7e9


def _part(k: int, seed: int) -> ModalLog:
    x = np.random.default_rng(seed).normal(size=(N, 2))
    return ModalLog(x, rate=RATE, start_time=T0 + k * N / RATE, modes=[2, 3])


def test_spans_of_consecutive_files_are_readable():
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
