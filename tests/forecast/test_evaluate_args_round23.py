"""Swapped ``level`` / ``alpha`` in ``evaluate`` (adversarial round 23 PART a, m29).

Reference: the definition of a test's family-wise error rate. At ``alpha >= 0.5`` a
Bonferroni skill test rejects on noise at least half the time, so ``level=0.05,
alpha=0.95`` (the two arguments swapped) is refused naming ``alpha``, while the usual
``alpha=0.05`` still runs.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import evaluate, make_predictor


def _log():
    return np.random.default_rng(0).standard_normal((400, 2))


def test_swapped_level_and_alpha_refused():
    with pytest.raises(ValueError, match="`alpha`.*swapped"):
        evaluate([make_predictor("linear")], _log(), horizons=[1], level=0.05, alpha=0.95)


def test_usual_alpha_runs():
    ev = evaluate([make_predictor("linear")], _log(), horizons=[1], level=0.95, alpha=0.05)
    assert list(ev.horizons) == [1]
