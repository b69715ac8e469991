"""Effective frames of the quality pass: Bartlett's law on the AR(4) innovations.

Round 10 of planted bugs (review10). The threshold ``k`` is set for the effective
number of independent innovations, ``(N - p) (1 - r) / (1 + r)`` (Bartlett 1946; ``p =
4`` fitted coefficients, ``r`` the median lag-1 autocorrelation of the innovations;
module notes of :mod:`modalinfo.telemetry.quality`). Reference, outside the code:
statsmodels' ``AutoReg(x, 4, trend="n")`` residuals and their ``acf`` at lag 1, put in
Bartlett's formula. The log is white noise smoothed by a Gaussian of 3 frames (scipy),
whose AR(4) innovations stay strongly correlated (r ~ 0.78: about 250 effective frames
of 2000). Planted bug R10-Q2 (the robust lag-1 estimate's sign reversed, so ``r`` was
clipped to 0 and every log had ``N - 4`` effective frames) escaped the quality tests,
whose logs have nearly white innovations.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.ndimage import gaussian_filter1d

from modalinfo.telemetry import assess_quality

statsmodels = pytest.importorskip("statsmodels")


@pytest.mark.parametrize("seed", [0, 1])
def test_effective_frames_follow_bartlett_on_the_ar4_residuals(seed):
    from statsmodels.tsa.ar_model import AutoReg
    from statsmodels.tsa.stattools import acf

    n, m = 2000, 10
    u = np.random.default_rng(seed).standard_normal((n + 100, m))
    x = gaussian_filter1d(u, 3.0, axis=0)[50:50 + n]
    r = float(np.median([acf(AutoReg(x[:, j], 4, trend="n").fit().resid, nlags=1)[1]
                         for j in range(m)]))
    assert 0.6 < r < 0.9  # the innovations of this log are far from white
    bartlett = (n - 4) * (1 - r) / (1 + r)
    report = assess_quality(x)
    assert report.assessed
    assert report.effective_frames == pytest.approx(bartlett, rel=0.15)  # measured 1-3 %
