"""The ordering's cost estimate against the MI estimates an ordering makes (fixes 47-b).

Adversarial round 46 PART a, A03a / A03c (issue 27): ``least_ordering_seconds`` was
3.8-5.3x below the CPU of a 1000-mode ordering. One cause: the screened greedy search
was counted one estimate per screened step, where a step that scores one mode leaves
the next step's mode unscored, so ``_swapped_mi`` estimates that rival afterwards: at
least two per step. Reference, outside the cost model: the ``MutualInformation.score``
calls counted during the ordering (a 40-mode log whose mode variances fall 1.3x a mode,
so each screened step scores exactly one mode: the bound is attained). No timing is
asserted.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.information import MutualInformation
from modalinfo.ordering import cost, order_modes

M = 40


def _coeffs_and_basis():
    rng = np.random.default_rng(1)
    basis = ZernikeBasis(Pupil(32), modes=range(2, 2 + M))
    return rng.standard_normal((60, M)) * 1.3 ** (-np.arange(M) / 2), basis


@pytest.fixture
def counted(monkeypatch):
    calls = [0]
    original = MutualInformation.score

    def score(self, y):
        calls[0] += 1
        return original(self, y)

    monkeypatch.setattr(MutualInformation, "score", score)
    return calls


@pytest.mark.parametrize("estimator", ["gaussian", "histogram"])
def test_the_screened_greedy_count_is_attained(counted, estimator):
    coeffs, basis = _coeffs_and_basis()
    order_modes(coeffs, basis, "mi_greedy", estimator=estimator, search="screened",
                sample_budget=4000, n_resamples=0, seed=0)
    # the first step scores 40, the tail's 15 steps 16 + 15 + ... + 2, the 23 between two
    least = cost.least_ordering_calls(M, "mi_greedy", "screened")
    assert least == M + (16 * 17 // 2 - 1) + 2 * (M - 1 - 16) == 221
    assert counted[0] == least  # 198 were counted before: one per step between


def test_a_plan_above_the_limit_is_refused_before_any_estimate(counted):
    coeffs, basis = _coeffs_and_basis()
    seconds, calls = cost.least_ordering_seconds("histogram", 4000, M, 0, 1, "mi_greedy",
                                                 "screened")
    assert calls == 221
    # between the estimate of 198 estimates (before) and that of 221: refused now
    limit = seconds * (198 + 221) / 2 / 221
    # the estimate with the digits that read above the limit (fix50-b: "0 s" before)
    with pytest.raises(ValueError, match=r"at least 221 MI estimates\) "
                                         + re.escape(cost.seconds_text(seconds, above=limit))):
        order_modes(coeffs, basis, "mi_greedy", estimator="histogram", search="screened",
                    sample_budget=4000, n_resamples=0, seed=0, max_seconds=limit)
    assert counted[0] == 0  # refused before any work

