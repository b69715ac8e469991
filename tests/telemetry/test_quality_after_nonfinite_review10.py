"""A glitch within AR_ORDER frames after a non-finite value is still an outlier.

Round 10 of planted bugs (review10). The rule (module notes of
:mod:`modalinfo.telemetry.quality`, issue 27 leftovers 11): a value is an outlier when
it is beyond ``k`` robust sigmas of its mode's median and its AR(4) innovation is
beyond ``k`` of the innovations' sigmas; "after a non-finite value the levels alone are
tested" (no innovation can be formed from a NaN). Reference: the construction — a
100-sigma value on a unit-variance log is beyond any threshold of the pass (k ~5 here),
placed 1 to 4 frames after a NaN of the same mode; frame 5 after it has a full past
(the control). Planted bug R10-Q3 (the kernel reading a NaN innovation as "not an
outlier") escaped the quality tests, which glitch no frame next to a non-finite one:
the 100-sigma values there went unreported.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import assess_quality


@pytest.mark.parametrize("rho", [0.0, 0.99])
@pytest.mark.parametrize("after", [1, 2, 4, 5])
def test_a_glitch_just_after_a_nan_is_reported(after, rho):
    n, m = 2000, 5
    rng = np.random.default_rng(10 + after)
    e = rng.standard_normal((n, m)) * np.sqrt(1 - rho**2)
    x = np.empty((n, m))
    x[0] = rng.standard_normal(m)
    for t in range(1, n):  # AR(1) of unit marginal variance
        x[t] = rho * x[t - 1] + e[t]
    x[700, 2] = np.nan
    x[700 + after, 2] += 100.0
    report = assess_quality(x)
    assert report.assessed and report.k < 10
    assert report.nonfinite_frames.tolist() == [700]
    assert report.outlier_frames.tolist() == [700 + after]
    assert report.outliers.tolist() == [0, 0, 1, 0, 0]
