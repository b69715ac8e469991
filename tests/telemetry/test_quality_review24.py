"""Planted-bug review 24 (issue 27): the clip action's counts, the repeated-frame count
rule and the quality record of a log that already holds one.

References (outside the code): glitches planted at known frames of a seeded Gaussian
log (their indices and counts by hand); the Poisson upper tail ``P(X >= found)`` of
``scipy.stats.poisson.sf(found - 1, lam)`` for the count of whole repeated frames.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import poisson

from modalinfo.telemetry import ModalLog, apply_outlier_policy
from modalinfo.telemetry.quality import AR_ORDER, _chance_repeats, policy_record

ALPHA = 0.01


def _noise(seed: int, n: int = 3000, m: int = 4) -> np.ndarray:
    return np.random.default_rng(seed).standard_normal((n, m))


def test_an_outlier_just_after_the_first_ar_order_frames_is_not_backcast():
    # frame AR_ORDER (the 5th) has AR_ORDER frames before it: predicted, not backcast
    x = _noise(0)
    x[AR_ORDER, 1] = 1e3
    x[2000, 2] = 1e3
    out, rep = apply_outlier_policy(ModalLog(x, rate=1000.0), "clip")
    assert int(rep.outliers.sum()) == 2
    action = out.metadata["outliers"][-1]["action"]
    assert action.startswith("clipped 2 outlier value(s)")
    assert f"first {AR_ORDER} frames" not in action
    # and one at frame AR_ORDER - 1 is
    y = _noise(0)
    y[AR_ORDER - 1, 1] = 1e3
    out, _ = apply_outlier_policy(ModalLog(y, rate=1000.0), "clip")
    assert f"1 in the first {AR_ORDER} frames" in out.metadata["outliers"][-1]["action"]


@pytest.mark.parametrize("found", [1, 2, 3, 5, 8])
@pytest.mark.parametrize("lam", [0.004, 0.02, 0.15, 0.6, 2.0])
def test_chance_repeats_is_the_poisson_tail_at_found_or_more(found, lam):
    n = 1001
    share = np.array([np.sqrt(lam / (n - 1))] * 2)  # (n - 1) q^2 = lam
    expected = poisson.sf(found - 1, lam) > ALPHA  # P(X >= found) above alpha: chance
    assert _chance_repeats(found, n, share, ALPHA) is bool(expected)


def test_one_repeat_is_chance_where_the_poisson_mean_is_above_alpha():
    # one frame found, lam = 0.05: P(X >= 1) = 0.049 > alpha (chance), whereas
    # P(X >= 2) = 0.0012 < alpha
    n = 1001
    share = np.full(2, np.sqrt(0.05 / 1000))
    assert poisson.sf(0, 0.05) > ALPHA > poisson.sf(1, 0.05)
    assert _chance_repeats(1, n, share, ALPHA)


def test_the_record_is_the_last_policy_applied_not_the_first():
    # a log that went through --outliers warn (say by `convert`) and is clipped now
    x = _noise(1)
    x[[500, 1500, 2500], [0, 1, 3]] = 1e3
    warned, _ = apply_outlier_policy(ModalLog(x, rate=1000.0), "warn")
    assert [r["policy"] for r in warned.metadata["outliers"]] == ["warn"]
    clipped, rep = apply_outlier_policy(warned, "clip")
    record = policy_record(rep, clipped, "clip")
    assert record["policy"] == "clip"
    assert record["action"].startswith("clipped 3 outlier value(s)")
