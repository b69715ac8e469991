"""Planted-bug review 18 (issue 27): the spread rule's floor, its skip of stepped modes,
and the quality threshold's in-sample term, each pinned against a reference outside the code.

References:

* the floor of judged columns, ``MIN_VARIANCE_EFFECTIVE`` = 100 effective absolute
  deviations ``T (1 - r) / (1 + r)`` (Bartlett 1946; documented in
  ``modalinfo._stats`` and the quality module docstring), evaluated here with the lag-1
  correlation of ``numpy.corrcoef``: white columns of 90 frames have at most 90 and are
  never judged; columns of 130 frames whose numpy ``r`` is below 0.05 have more than
  117 and are all judged (the code's own estimator of ``r`` differs from numpy's by
  O(1 / T), far less than the margins);
* a planted mean step (numpy): the documented rule that a mode whose mean steps is
  reported in ``level_steps`` and not again by the spread rule, which judges the others;
* the quality rule's ``k`` at stride 1 is the union bound for values *inside* the
  median / MAD sample and for a strided subsample the one for values outside it
  (``small_sample_threshold(..., in_sample=...)``, whose two terms
  ``tests/common/test_mad_union_left18.py`` checks against simulated Gaussian tails).
"""

from __future__ import annotations

import numpy as np

from modalinfo._stats import variance_steps
from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.quality import assess_quality, small_sample_threshold


def _numpy_effective(x: np.ndarray) -> np.ndarray:
    y = np.abs(x - np.median(x, axis=0))
    r = np.array([np.corrcoef(y[:-1, j], y[1:, j])[0, 1] for j in range(y.shape[1])])
    return y.shape[0] * (1 - np.clip(r, 0, None)) / (1 + np.clip(r, 0, None)), r


def test_columns_below_100_effective_deviations_are_not_judged():
    x = np.random.default_rng(21).standard_normal((90, 60))
    eff, _ = _numpy_effective(x)
    assert eff.max() <= 90
    _, judged = variance_steps(x)
    assert judged == 0


def test_columns_above_100_effective_deviations_are_judged():
    x = np.random.default_rng(22).standard_normal((130, 60))
    _, r = _numpy_effective(x)
    clear = int((r < 0.05).sum())  # T (1 - r) / (1 + r) > 117
    assert clear >= 30
    _, judged = variance_steps(x)
    assert clear <= judged <= 60


def test_a_mode_whose_mean_steps_is_not_judged_again_for_its_spread():
    x = np.random.default_rng(23).standard_normal((4000, 5))
    x[1000:, 0] += 3.0  # a mean step of 3 sigma in mode 0 at frame 1000
    rep = assess_quality(ModalLog(x, rate=1000.0))
    assert len(rep.level_steps) == 1
    label, frame = rep.level_steps[0][:2]
    assert label == rep.labels[0]  # mode 0, where the step was planted
    assert abs(frame - 1000) <= 40
    assert rep.variance_judged == 4  # the other four white modes
    assert label not in [s[0] for s in rep.variance_steps]


def test_quality_k_uses_the_in_sample_term_at_stride_1_only():
    rng = np.random.default_rng(24)
    whole = assess_quality(ModalLog(rng.standard_normal((50, 27)), rate=1000.0))
    n_eff = int(whole.effective_frames)
    assert whole.k == small_sample_threshold(n_eff, 50, 27, in_sample=True)
    assert whole.k < 0.99 * small_sample_threshold(n_eff, 50, 27, in_sample=False)
    strided = assess_quality(ModalLog(rng.standard_normal((400, 27)), rate=1000.0),
                             sample_frames=100)
    n_eff = int(strided.effective_frames)
    assert strided.k == small_sample_threshold(n_eff, 400, 27, in_sample=False)
