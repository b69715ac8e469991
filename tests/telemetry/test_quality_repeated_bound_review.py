"""The repeated-frame rule's chance bound: (T - 1) prod q_j <= alpha (round 21 PART a, g23).

Reference: numpy counts of equal consecutive values. A log of two modes, one rounded so
that a share q of its consecutive pairs are equal (0.01 < q < 0.1), the other continuous,
with one frame written twice: independent repeats explain a whole repeated frame
(T - 1) q (1 / (T - 1)) = q times on average, above alpha = 0.01, so the frame is not
flagged; the same log with alpha = 0.2 (q below it) is. A bound read 10x too loose
flags the first (planted-bug check of this stop).
"""

from __future__ import annotations

import numpy as np

from modalinfo.telemetry import assess_quality


def _log() -> tuple[np.ndarray, float]:
    rng = np.random.default_rng(7)
    n = 3000
    a = rng.normal(size=(n, 2))
    a[:, 0] = np.round(a[:, 0] / 0.18) * 0.18  # P(equal neighbours) ~ 0.18 / (2 sqrt(pi))
    doubled = np.r_[a[:1501], a[1500:]]
    q = float(np.mean(doubled[1:, 0] == doubled[:-1, 0]))
    return doubled, q


def test_chance_explains_the_repeat_above_alpha():
    doubled, q = _log()
    assert 0.02 < q < 0.09  # the case sits between alpha and 10 alpha
    assert assess_quality(doubled, alpha=0.01).repeated_frames.tolist() == []


def test_repeat_flagged_where_chance_is_below_alpha():
    doubled, q = _log()
    assert assess_quality(doubled, alpha=0.2).repeated_frames.tolist() == [1501]
