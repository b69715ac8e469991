"""Two consecutive files of a night, the second given as ``extra``, and the refusal's spans.

One copy for the tests of the refusal's printed spans (adversarial round 34 PART b, C09 at
2 kHz; planted-bug review 24 at 4 kHz). Reference: the logs' own frame times (numpy),
not the message's numbers.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from modalinfo.information import select_inputs
from modalinfo.telemetry import ModalLog

N, T0 = 400, 1.7e9  # frames per file; the night's first frame [Unix s]


def _part(k: int, seed: int, rate: float) -> ModalLog:
    """File ``k`` of the night: ``N`` frames of 2 white modes from ``T0 + k N / rate``."""
    x = np.random.default_rng(seed).normal(size=(N, 2))
    return ModalLog(x, rate=rate, start_time=T0 + k * N / rate, modes=[2, 3])


def refused_spans(rate: float) -> tuple[list[float], list[float]]:
    """Return the spans the refusal prints and the files' own first and last times.

    ``select_inputs`` is given file 0 as data and file 1 as ``extra``: refused as not
    simultaneous. First: ``[data start, data end, extra start, extra end]`` parsed from
    the message; second: the same four from the logs' ``times``.
    """
    data, extra = _part(0, 1, rate), _part(1, 2, rate)
    with pytest.raises(ValueError, match="`extra` must be sampled at the frames") as info:
        select_inputs(data, "Z2", extra=extra, max_lag=2, n_surrogates=19, n_resamples=19,
                      seed=0)
    spans = re.search(r"data: (\S+) \.\. (\S+) s, extra: (\S+) \.\. (\S+) s",
                      str(info.value))
    assert spans is not None, f"no spans in the refusal: {info.value}"
    got = [float(v) for v in spans.groups()]
    return got, [data.times[0], data.times[-1], extra.times[0], extra.times[-1]]
