"""The quality pass names a mode that is an exact copy of another (round 53 PART a, W10).

Reference: numpy (``np.array_equal`` of the two columns). Before round 53 a 500-mode
Kolmogorov log whose Z12 was written from Z5's channel read "0 of 4000 frames flagged
...", naming the copy nowhere. Two independent continuous modes are never equal in
thousands of frames; a constant mode is the constant note's, not a copy.
"""

import numpy as np

from modalinfo.telemetry import ModalLog, assess_quality


def _log(seed: int = 5) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.standard_normal((3000, 40)) / np.sqrt(np.arange(1, 41))


def test_copied_mode_is_named():
    x = _log()
    x[:, 10] = x[:, 3]
    x[:, 20] = x[:, 3]
    assert np.array_equal(x[:, 10], x[:, 3]) and np.array_equal(x[:, 20], x[:, 3])
    text = assess_quality(ModalLog(x, rate=1000.0, modes=list(range(2, 42)))).describe()
    assert text.endswith("2 pair(s) of modes equal in all 3000 sampled frames (a channel "
                         "written twice?): Z12 = Z5, Z22 = Z5")


def test_near_copy_and_constant_pair_are_not_copies():
    x = _log()
    x[:, 10] = x[:, 3] + 1e-12  # not equal: a near copy is no exact copy
    x[:, 5] = x[:, 6] = 0.0     # two constant modes: the constant note names them
    text = assess_quality(ModalLog(x, rate=1000.0, modes=list(range(2, 42)))).describe()
    assert "equal in all" not in text
    assert "2 mode(s) constant over the whole log" in text
