"""Re-sent frames on logs of few modes (adversarial round 34 PART b, B12-B18).

Reference: the probability, under independent repeats of each mode, of the count of
whole frames equal to the frame before: a Poisson law of mean ``(T - 1) prod_j q_j``
(``q_j`` counted with numpy), its upper tail from ``scipy.stats.poisson``. Continuous
float64 data never repeat a value by chance, so every re-sent frame of a Gaussian
AR(1) log is a logger's doing: with 5 % of 8000 frames re-sent on 2 modes the mean is
``7999 x 0.05^2 = 20`` and ``P(X >= 400) < 1e-300``: all 400 are flagged (none were
before: the rule asked for a mean below alpha). A log quantised so that whole frames
repeat by chance about as often as found stays unflagged (the count's tail above alpha).
"""

from __future__ import annotations

import numpy as np
from scipy.stats import poisson

from modalinfo.telemetry import assess_quality


def _ar1(n: int, m: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.normal(size=(n, m))
    x = np.empty_like(e)
    x[0] = e[0]
    for t in range(1, n):
        x[t] = 0.9 * x[t - 1] + e[t] * np.sqrt(1 - 0.81)
    return x


def _resend(x: np.ndarray, share: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    n = x.shape[0]
    idx = np.sort(rng.choice(np.arange(1, n), int(share * n), replace=False))
    y = x.copy()
    for i in idx:
        y[i] = y[i - 1]
    # a run of re-sends counts each frame equal to its predecessor
    return y, np.flatnonzero(np.all(y[1:] == y[:-1], axis=1)) + 1


def test_tip_tilt_log_with_five_percent_resent_frames_is_flagged():
    y, truth = _resend(_ar1(8000, 2, 1), 0.05, 2)
    q = np.mean(y[1:] == y[:-1], axis=0)
    lam = (len(y) - 1) * np.prod(q)
    assert lam > 1 and poisson.sf(truth.size - 1, lam) < 1e-100  # chance cannot explain
    report = assess_quality(y)
    assert report.repeated_frames.tolist() == truth.tolist()


def test_one_percent_on_three_modes_is_flagged():
    y, truth = _resend(_ar1(4000, 3, 3), 0.01, 4)
    assert assess_quality(y).repeated_frames.tolist() == truth.tolist()


def test_chance_repeats_of_a_coarse_quantised_log_stay_unflagged():
    # two independent modes rounded to a third of their sigma: whole frames repeat by
    # chance (q ~ 0.1 each, mean ~ 80 over 8000 frames); the count found is typical
    x = np.round(_ar1(8000, 2, 5) * 3.0) / 3.0
    found = np.count_nonzero(np.all(x[1:] == x[:-1], axis=1))
    q = np.mean(x[1:] == x[:-1], axis=0)
    lam = (len(x) - 1) * np.prod(q)
    assert found > 0 and poisson.sf(found - 1, lam) > 0.01
    assert assess_quality(x).repeated_frames.size == 0
