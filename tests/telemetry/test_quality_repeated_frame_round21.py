"""The quality pass flags one frame written twice (round 21 PART a, row g23).

Reference: the construction itself (numpy): a continuous log with frame ``i`` inserted
a second time right after itself has exactly one frame, ``i + 1``, equal to the frame
before in every mode; ``"drop"`` must give back the original frames (numpy equality).
Chance repeats: with ``q_j`` each mode's share of equal consecutive pairs, independent
modes repeat a whole frame ``(T - 1) prod q_j`` times on average, so a Gaussian log
rounded to 2 sigma (``q`` about 0.5 per mode, 2 modes: ~750 chance repeats in 3000
frames) must not be flagged. Before the fix nothing flagged the repeated frame (every
mode's stuck run is at least 8).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog, apply_outlier_policy, assess_quality


def _repeated(n: int = 3000, m: int = 6, at: int = 1500) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(21)
    a = rng.normal(size=(n, m))
    return a, np.r_[a[:at + 1], a[at:]]


@pytest.mark.parametrize("chunk", [None, 1501])  # the repeat inside a block and at its edge
def test_one_frame_written_twice_is_flagged(chunk):
    a, doubled = _repeated()
    report = assess_quality(doubled, chunk_frames=chunk)
    assert report.repeated_frames.tolist() == [1501]
    assert not report.clean
    assert "1 repeated frame(s) equal to the frame before in every mode (1501)" in \
        report.describe()
    assert report.to_dict()["repeated_frames"] == 1


def test_drop_gives_back_the_original_frames():
    a, doubled = _repeated()
    log = ModalLog(doubled, rate=1000.0)
    cleaned, _ = apply_outlier_policy(log, "drop")
    np.testing.assert_array_equal(np.asarray(cleaned.coeffs), a)


def test_clean_and_coarsely_quantised_logs_are_not_flagged():
    a, _ = _repeated()
    report = assess_quality(a)
    assert report.repeated_frames.size == 0 and "repeated_frames" not in report.to_dict()
    coarse = np.round(np.random.default_rng(3).normal(size=(3000, 2)) * 0.5)
    assert assess_quality(coarse).repeated_frames.size == 0
