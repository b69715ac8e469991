"""``clip`` replaces a glitch by its AR prediction, not by a far-away level (leftovers 12-est).

Reference (outside the code): the log before the glitch was planted. On an AR(1) mode
of rho = 0.999 (unit marginal variance, innovations of sd sqrt(1 - rho^2) = 0.0447, made
with ``scipy.signal.lfilter``), one value is raised by 100 marginal sigmas. The former
``clip`` winsorised it to median + k sigma (k ~ 5.3), a level unrelated to the
neighbours of a persistent mode: 62-179 innovation sigmas from the value it replaced
(seeds 0-4). Replaced by its AR(4) prediction from the frames before it (the quality
pass's own replacement, Chen & Liu 1993), it must land within 4 innovation sigmas of
both the true value and the previous frame (measured: 0.0-2.1), and nothing else may
change.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.telemetry import ModalLog, apply_outlier_policy

RHO = 0.999
SIGMA_E = math.sqrt(1.0 - RHO**2)
T, GLITCH = 4000, 2000


def _log(seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((T + 3000, 3)) * SIGMA_E
    clean = lfilter([1.0], [1.0, -RHO], e, axis=0)[3000:]  # burn-in: stationary
    x = clean.copy()
    x[GLITCH, 0] += 100.0
    return clean, x


@pytest.mark.parametrize("seed", range(5))
def test_the_glitch_is_replaced_near_its_neighbours(seed):
    clean, x = _log(seed)
    out, report = apply_outlier_policy(ModalLog(x, rate=1000.0), "clip")
    assert report.outlier_frames.tolist() == [GLITCH]
    got = out.coeffs[GLITCH, 0]
    assert abs(got - clean[GLITCH, 0]) < 4 * SIGMA_E
    assert abs(got - x[GLITCH - 1, 0]) < 4 * SIGMA_E
    changed = out.coeffs != x
    assert changed.sum() == 1 and changed[GLITCH, 0]
    assert "replaced by its AR(4) prediction" in out.metadata["outliers"][-1]["action"]


@pytest.mark.parametrize("frame", [0, 1, 3])
def test_a_glitch_in_the_first_frames_is_predicted_backwards(frame):
    # no past there: predicted from the frames after it, as the pass tests it (before
    # this: the median, ~1 marginal sigma = 22 innovation sigmas from the neighbours)
    clean, x = _log(8)
    x[GLITCH, 0] = clean[GLITCH, 0]
    x[frame, 1] += 100.0
    out, report = apply_outlier_policy(ModalLog(x, rate=1000.0), "clip")
    assert report.outlier_frames.tolist() == [frame]
    assert abs(out.coeffs[frame, 1] - clean[frame, 1]) < 4 * SIGMA_E
    assert (out.coeffs != x).sum() == 1


def test_float32_log_keeps_its_dtype():
    clean, x = _log(7)
    out, _ = apply_outlier_policy(ModalLog(x.astype(np.float32), rate=1000.0), "clip")
    assert out.coeffs.dtype == np.float32
    assert abs(float(out.coeffs[GLITCH, 0]) - clean[GLITCH, 0]) < 4 * SIGMA_E
