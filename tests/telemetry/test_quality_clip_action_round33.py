"""What ``clip`` says it did matches what it did to the data (round 33 PART b, B02 / B38 / B40).

Reference (outside the code): the glitches planted in an AR(1) log (phi 0.9, 4000 x 12,
seeded) and numpy on the returned array. Planted: 40 single values at 1e3 after frame
200, one at frame 0 (mode 3), and frames 100..139 at 5e2 in every mode (480 values that
are outliers AND a stuck run of 40 equal values per mode): 521 outlier values, all
replaced (no value above 100 remains). Before the fix the action said "480 stuck or
non-finite value(s) left as they are" though every one of them was replaced, named no
run filled by the decaying AR forecast and said the frame-0 glitch was predicted "from
the frames before it". A stuck run that is not an outlier (20 frames of one mode held
at an ordinary value) is left unchanged and counted: 20.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog, apply_outlier_policy

T, M = 4000, 12


def _ar(seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((T, M)) * np.linspace(1.0, 0.2, M)
    x = np.zeros((T, M))
    for t in range(1, T):
        x[t] = 0.9 * x[t - 1] + e[t]
    return x


@pytest.fixture(scope="module")
def glitched():
    x = _ar()
    rng = np.random.default_rng(1)
    frames = rng.choice(np.arange(200, T), 40, replace=False)
    x[frames, rng.integers(0, M, 40)] = 1e3
    x[100:140] = 5e2
    x[0, 3] = 1e3
    return x


def test_block_replaced_is_not_called_left(glitched):
    out, rep = apply_outlier_policy(ModalLog(glitched, rate=1000.0), "clip")
    action = out.metadata["outliers"][-1]["action"]
    assert int(rep.outliers.sum()) == 40 + 480 + 1
    assert np.abs(out.coeffs).max() < 100  # numpy: every planted value replaced
    assert action.startswith("clipped 521 outlier value(s)")
    assert "left as they are" not in action  # 0 left: all 480 stuck values replaced
    assert "frames 100..139, 40 frames" in action  # the run filled by the AR forecast
    assert "decaying towards the mode's median" in action
    # frame 0 has no frame before it: backcast from the frames after it
    assert "1 in the first 4 frames" in action and "backcast from the frames after" in action


def test_stuck_run_that_is_not_an_outlier_is_counted_left():
    x = _ar(2)
    x[2000:2020, 5] = x[2000, 5]  # 20 equal ordinary values: stuck, not outliers
    x[3000, 1] = 1e3  # one outlier so that clip acts
    out, rep = apply_outlier_policy(ModalLog(x, rate=1000.0), "clip")
    action = out.metadata["outliers"][-1]["action"]
    assert int(rep.outliers.sum()) == 1
    assert np.array_equal(out.coeffs[2000:2020, 5], x[2000:2020, 5])
    assert "20 stuck or non-finite value(s) that were not outliers left as they are" in action
    assert "run of consecutive outliers" not in action  # a single value is no run
    assert "first 4 frames" not in action
