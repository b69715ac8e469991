"""A glitch in the first AR_ORDER frames of a persistent log is found.

Round 10 of planted bugs (review10). The first ``p = 4`` frames have no full past: the
rule predicts them backwards from the ``p`` frames after them (a stationary Gaussian
process is time-reversible; module notes of :mod:`modalinfo.telemetry.quality`, issue 27
leftovers 11). Reference: the construction — a glitch of 10 or 20 marginal sigmas on an
AR(1) log of unit marginal variance and rho 0.99 (innovation sd 0.14, k ~5) is beyond
the threshold in its level and 70-140 innovation sigmas from any prediction made from
its neighbours, wherever it sits; frame 4 has a full past (the control). Planted bug
R10-Q4 (the backward prediction of frame t taken from frames t .. t + 3, the glitch
itself included) escaped the quality tests, which glitch no frame of the first four:
the glitch predicted itself (its innovation ~(1 - rho) x its size) and went unreported.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import assess_quality


def _ar1(rng, n, m, rho):
    e = rng.standard_normal((n, m)) * np.sqrt(1 - rho**2)
    x = np.empty((n, m))
    x[0] = rng.standard_normal(m)
    for t in range(1, n):
        x[t] = rho * x[t - 1] + e[t]
    return x


@pytest.mark.parametrize("size", [10.0, 20.0])
@pytest.mark.parametrize("frame", [0, 1, 2, 3, 4])
def test_a_glitch_in_the_first_frames_is_found(frame, size):
    x = _ar1(np.random.default_rng(100 + frame), 2000, 4, 0.99)
    x[frame, 1] += size
    report = assess_quality(x)
    assert report.assessed and report.k < 10
    assert report.outlier_frames.tolist() == [frame]
    assert report.outliers.tolist() == [0, 1, 0, 0]
