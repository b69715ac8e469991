"""Quality pass: the edge of 'too short to assess' and the labels in the report's fingerprint.

Round 9 of planted bugs (review9). References from outside the code:

* Bartlett's (1946) effective sample size, ``(N - p) (1 - r) / (1 + r)`` for the
  innovations of an AR(p) fit (p = 4 coefficients fitted: at most ``N - 4``; issue 27
  leftovers 11), so a white log of N frames has at most N - 4 effective frames and is
  too short below 16 frames; the documented edge is 12 (``MIN_EFFECTIVE_FRAMES``, issue
  27 leftovers: the union-bound threshold k is 75 at 10 frames, 15 at 12). A rule moved
  to 5 assessed 8 - 11 frames without a word (planted bug C2 escaped).
* The fingerprint's contract (``data_fingerprint`` docstring: "any changed value, frame
  time or label changes it"): the same numbers under other mode labels give another
  fingerprint, and a report of them is refused. Planted bug C3 (labels left out of the
  digest) escaped: ``apply_outlier_policy`` still refuses such a report by its older
  label check, but the fingerprint, which a saved report keeps, no longer told the logs
  apart.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog, apply_outlier_policy, assess_quality
from modalinfo.telemetry.quality import data_fingerprint

M = 27


@pytest.mark.parametrize("n", [8, 12, 15])
def test_white_logs_under_12_effective_frames_are_too_short_to_assess(n):
    x = np.random.default_rng(n).standard_normal((n, M))
    r = assess_quality(x)
    assert r.effective_frames <= n - 4 < 12  # at most one per frame, less 4 coefficients
    assert not r.assessed and not r.clean and r.k == np.inf


@pytest.mark.parametrize("n", [20, 30])
def test_white_logs_from_12_effective_frames_are_assessed(n):
    x = np.random.default_rng(n).standard_normal((n, M))
    r = assess_quality(x)
    assert 12 <= r.effective_frames <= n - 4
    assert r.assessed and np.isfinite(r.k)


def test_a_report_of_the_same_numbers_under_other_labels_is_refused():
    x = np.random.default_rng(5).standard_normal((500, 4))
    x[100, 3] = 100.0
    log = ModalLog(x, rate=100.0, modes=[2, 3, 4, 5])
    relabelled = ModalLog(x, rate=100.0, modes=[5, 4, 3, 2])
    assert data_fingerprint(log) != data_fingerprint(relabelled)
    assert assess_quality(log).fingerprint != assess_quality(relabelled).fingerprint
    with pytest.raises(ValueError, match=r"^`report` must be the assessment of this log"):
        apply_outlier_policy(log, "clip", report=assess_quality(relabelled))
    out, _ = apply_outlier_policy(log, "clip", report=assess_quality(log))  # its own: kept
    assert out.coeffs[100, 3] < 10.0
