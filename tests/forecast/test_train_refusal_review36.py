"""Mutation round 36 (review36): ``evaluate`` refuses too few training frames first.

The plant ``n_train < n_min`` -> ``n_train < n_min - 1`` escaped stop 60's test, whose 300
training frames were 302 short of the rule. Reference: ``MultivariatePredictor(order=2)
.min_samples(30)``, the predictor's own documented rule, at one frame short of it, and
the count of ``fit`` calls (none may happen before the refusal).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, MultivariatePredictor, evaluate


def test_one_frame_short_is_refused_before_any_fit(monkeypatch):
    multi = MultivariatePredictor(order=2)
    n_min = multi.min_samples(30)
    x = np.random.default_rng(0).standard_normal((2 * n_min, 30))
    fitted = []
    original = LinearPredictor.fit

    def counted(self, history):
        fitted.append(type(self).__name__)
        return original(self, history)

    monkeypatch.setattr(LinearPredictor, "fit", counted)
    with pytest.raises(ValueError, match=f"needs at least {n_min} samples .* got {n_min - 1}"):
        evaluate({"linear": LinearPredictor(fit_weights=True), "multi": multi}, x,
                 train=n_min - 1, horizons=[1])
    assert fitted == []
