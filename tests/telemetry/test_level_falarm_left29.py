"""The level rule's Bonferroni is over the modes tested, not the judged (issue 27, left29-falarm).

References (outside the code under test):
- stationary AR(1) logs of unit marginal variance (``scipy.signal.lfilter``, burnt in
  ``10 / (1 - phi)`` frames): no mean step by construction, so any level step named is
  a false alarm. At AR(1) 0.995, 10 x 8,000 frames, the rule of before (Bonferroni over
  the judged modes, about 1.3 of 10) named a step in 5 of 200 seeded logs (2.5 % for a
  stated 1 %; binomial bound 1 % + 2 sd = 2.4 %), the rule now 1 of 200
  (benchmarks/bench_falarm_left29.py, RESULTS.md "left29-falarm"). The seeds below are
  three of those 5 (chosen after the fact: the test pins those logs, it does not
  measure a rate);
- Bonferroni's inequality: the family-wise bound is ``alpha`` over the columns whose
  per-column rate ``P(judged and p < t)`` is at most ``t``;
- a planted step with known truth (5 marginal sd, AR(1) 0.9, one of 10 modes at 40 % of
  8,000 frames: ``|L_1|`` ~ 5 sqrt(2 n) sin(0.4 pi) / pi, p ~ 1e-9 at F(1, 40)), named
  by either rule.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo._stats import LEVEL_ALPHA, level_stationarity, level_steps
from modalinfo.telemetry import assess_quality


def _ar1(seed: int, t: int, phi: float, m: int) -> np.ndarray:
    """Stationary AR(1) columns of unit marginal variance, the benchmark's generator."""
    rng = np.random.default_rng([29, seed])
    e = rng.standard_normal((t + int(10 / (1 - phi)), m))
    return lfilter([math.sqrt(1 - phi * phi)], [1.0, -phi], e, axis=0)[-t:]


@pytest.mark.parametrize("seed", [44, 68, 95])
def test_stationary_persistent_log_names_no_level_step(seed):
    x = _ar1(seed, 8000, 0.995, 10)
    # the rule of before fired here: a judged mode beyond LEVEL_ALPHA / (modes judged).
    # Since fix54-a the long-memory reading (d of ~2 s.e. on these modes) leaves seeds
    # 68 and 95 above that cut too (p 0.0051 of 3 judged, 0.024 of 1): seed 44 keeps
    # the distinction; all three must stay silent
    tests = [level_stationarity(x[:, j]) for j in range(10)]
    judged = [t.p_value for t in tests if t.judged]
    assert 0 < len(judged) < 10
    if seed == 44:
        assert min(judged) < LEVEL_ALPHA / len(judged)
    flagged, n_judged = level_steps(x)
    assert flagged == [] and n_judged == len(judged)
    report = assess_quality(x)
    assert report.level_steps == () and report.stationary is True


def test_bonferroni_counts_the_modes_tested():
    x = _ar1(44, 8000, 0.995, 10)
    tests = [level_stationarity(x[:, j]) for j in range(10)]
    judged = [j for j in range(10) if tests[j].judged]
    best = min(judged, key=lambda j: tests[j].p_value)
    p = tests[best].p_value
    # a family-wise alpha of 5 p lies between p x (modes judged, 1 here) and p x 10:
    # the mode is named only when the other nine are not tested (skipped)
    assert len(judged) * p < 5 * p < 10 * p < 1
    assert level_steps(x, 5 * p)[0] == []
    skip = np.ones(10, dtype=bool)
    skip[best] = False
    assert [j for j, _ in level_steps(x, 5 * p, skip)[0]] == [best]


def test_a_planted_step_in_one_mode_is_still_named():
    x = _ar1(7, 8000, 0.9, 10)
    x[3200:, 4] += 5.0
    report = assess_quality(x)
    assert [label for label, *_ in report.level_steps] == ["col4"]
    assert abs(report.level_steps[0][1] - 3200) < 200
