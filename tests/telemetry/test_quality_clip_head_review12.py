"""``clip`` predicts the first frames from the cleaned frames after them (review12, round 12).

Reference (outside the code): the log before the glitches were planted. An AR(1) mode
of rho = 0.999 (``scipy.signal.lfilter``, unit marginal variance, innovation sd 0.0447)
gets two glitches in its first frames, +100 and +60 marginal sigmas at frames 0 and 1.
Each has no past, so ``clip`` predicts it backwards from the frames after it; frame 0's
prediction must use frame 1 as cleaned (its own prediction), not the glitched value,
or it lands ~60 sigmas off. Both must end within 4 innovation sigmas of the values
before the glitches (as the left12 test of one glitch asks).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.signal import lfilter

from modalinfo.telemetry import ModalLog, apply_outlier_policy

RHO = 0.999
SIGMA_E = math.sqrt(1.0 - RHO**2)


def test_two_glitches_in_the_first_frames_are_both_predicted_from_clean_frames():
    for seed in range(3):
        rng = np.random.default_rng(seed)
        e = rng.standard_normal((7000, 2)) * SIGMA_E
        clean = lfilter([1.0], [1.0, -RHO], e, axis=0)[3000:]
        x = clean.copy()
        x[0, 1] += 100.0
        x[1, 1] += 60.0
        out, report = apply_outlier_policy(ModalLog(x, rate=1000.0), "clip")
        assert report.outlier_frames.tolist() == [0, 1]
        assert np.all(np.abs(out.coeffs[:2, 1] - clean[:2, 1]) < 4 * SIGMA_E)
        assert (out.coeffs != x).sum() == 2
