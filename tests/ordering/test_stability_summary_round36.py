"""Round 36 PART b, R03: a method without MI has no seed stability to report.

Reference: the definition of the seeds' comparison - the seeds draw the MI's (frame,
pixel) samples; the variance order is a deterministic function of the coefficients
(NumPy mean squares), so every seed gives the same order and a "median Spearman 1.000
across seeds" measures nothing. Before the fix ``reorder --method variance --stability``
printed it as a measured stability.
"""

import numpy as np

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import ordering_stability
from modalinfo.telemetry import ModalLog


def test_the_variance_order_says_the_seeds_are_not_assessed():
    rng = np.random.default_rng(36)
    x = rng.standard_normal((400, 5)) * np.array([3.0, 2.0, 1.5, 1.0, 0.5])
    log = ModalLog(x, rate=1000.0, modes=[2, 3, 4, 5, 6], units="rad")
    basis = ZernikeBasis(Pupil(16), modes=[2, 3, 4, 5, 6])
    stab = ordering_stability(log, basis, "variance", window=100, seeds=(0, 1, 2))
    text = stab.summary()
    assert "seeds on the whole log: not assessed (method variance draws no samples" in text
    assert "3 seeds on the whole log: median Spearman" not in text
    assert "4 windows of 100 frames" in text
